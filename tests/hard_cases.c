/* Closed meshes and hard-case rays (see hard_cases.h). */
#include "tests/hard_cases.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tests/support.h"

static lt_scene *scene_from(const float *tris, size_t n) {
  lt_scene *scene = NULL;
  return lt_scene_from_triangles(tris, n, &scene) == LT_OK ? scene : NULL;
}

/* A point uniformly in the ball of radius r about c, away from c itself. */
static void point_in_ball(uint64_t *seed, const float c[3], float r, float *p) {
  float d[3], len2;
  do {
    for (int k = 0; k < 3; k++) d[k] = (2.0f * lt__splitmix_unit(seed) - 1.0f) * r;
    len2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
  } while (len2 > r * r || len2 < 1e-4f * r * r);
  for (int k = 0; k < 3; k++) p[k] = c[k] + d[k];
}

lt_hc_mesh lt_hc_sphere(int level, uint64_t seed) {
  lt_hc_mesh m = {NULL, NULL, 0};
  char spec[32];
  snprintf(spec, sizeof spec, "sphere:%d", level);
  if (lt_scene_load(spec, &m.scene) != LT_OK) return m;
  m.inside_count = 16;
  m.inside = calloc(3 * m.inside_count, sizeof *m.inside);
  const float centre[3] = {0, 0, 0};
  for (size_t i = 1; i < m.inside_count; i++) point_in_ball(&seed, centre, 0.5f, m.inside + 3 * i);
  return m;
}

lt_hc_mesh lt_hc_torus(int major_segments, int minor_segments) {
  const double major = 1.0, minor = 0.35, pi = 3.14159265358979323846;
  int M = major_segments, m = minor_segments;
  lt_hc_mesh out = {NULL, NULL, 0};
  float *verts = malloc((size_t)M * m * 3 * sizeof *verts);
  float *tris = malloc((size_t)M * m * 2 * 9 * sizeof *tris);
  if (!verts || !tris) return free(verts), free(tris), out;

  /* Vertices on an index grid, each computed once: the seams reuse the same floats. */
  for (int i = 0; i < M; i++)
    for (int j = 0; j < m; j++) {
      double theta = 2.0 * pi * i / M, phi = 2.0 * pi * j / m, radius = major + minor * cos(phi);
      float *v = verts + 3 * (i * m + j);
      v[0] = (float)(radius * cos(theta)), v[1] = (float)(minor * sin(phi)), v[2] = (float)(radius * sin(theta));
    }
  size_t n = 0;
  for (int i = 0; i < M; i++)
    for (int j = 0; j < m; j++) {
      const float *a = verts + 3 * (i * m + j), *b = verts + 3 * (((i + 1) % M) * m + j);
      const float *c = verts + 3 * (((i + 1) % M) * m + (j + 1) % m), *d = verts + 3 * (i * m + (j + 1) % m);
      const float *quad[2][3] = {{a, b, c}, {a, c, d}};
      for (int t = 0; t < 2; t++, n++)
        for (int k = 0; k < 3; k++) memcpy(tris + 9 * n + 3 * k, quad[t][k], 3 * sizeof(float));
    }
  out.scene = scene_from(tris, n);

  /* Inside: points of the core circle, between and on the rings. */
  out.inside_count = 16;
  out.inside = calloc(3 * out.inside_count, sizeof *out.inside);
  for (size_t i = 0; i < out.inside_count; i++) {
    double theta = 2.0 * pi * (i + 0.37 * (i % 3)) / out.inside_count;
    out.inside[3 * i] = (float)(major * cos(theta)), out.inside[3 * i + 2] = (float)(major * sin(theta));
  }
  free(verts), free(tris);
  return out;
}

lt_hc_mesh lt_hc_cube(int n, uint64_t seed) {
  lt_hc_mesh out = {NULL, NULL, 0};
  int h = n / 2;
  float *tris = malloc((size_t)6 * n * n * 2 * 9 * sizeof *tris);
  if (!tris) return out;
  size_t count = 0;
  for (int axis = 0; axis < 3; axis++)
    for (int side = -1; side <= 1; side += 2)
      for (int i = -h; i < h; i++)
        for (int j = -h; j < h; j++) {
          /* The square's corners in (u, v) on the face; integer coordinates are exact, so
           * every edge is shared bit for bit with the next square or the next face. */
          float c[4][3];
          int uv[4][2] = {{i, j}, {i + 1, j}, {i + 1, j + 1}, {i, j + 1}};
          for (int q = 0; q < 4; q++) {
            c[q][axis] = (float)(side * h);
            c[q][(axis + 1) % 3] = (float)uv[q][0];
            c[q][(axis + 2) % 3] = (float)uv[q][1];
          }
          /* Diagonal 0-2 or 1-3, alternating like a checkerboard. */
          static const int diagonals[2][2][3] = {{{0, 1, 2}, {0, 2, 3}}, {{0, 1, 3}, {1, 2, 3}}};
          const int(*order)[3] = diagonals[(i + j) & 1];
          for (int t = 0; t < 2; t++, count++)
            for (int k = 0; k < 3; k++) memcpy(tris + 9 * count + 3 * k, c[order[t][k]], 3 * sizeof(float));
        }
  out.scene = scene_from(tris, count);
  free(tris);

  /* Inside: the centre and integer points (even indices), arbitrary points (odd ones). */
  out.inside_count = 24;
  out.inside = calloc(3 * out.inside_count, sizeof *out.inside);
  for (size_t p = 1; p < out.inside_count; p++)
    for (int k = 0; k < 3; k++) {
      float u = (2.0f * lt__splitmix_unit(&seed) - 1.0f) * (h - 1);
      out.inside[3 * p + k] = p % 2 == 0 ? floorf(u + 0.5f) : u;
    }
  return out;
}

lt_hc_mesh lt_hc_transform(const lt_hc_mesh *mesh, float scale, float offset) {
  lt_hc_mesh out = {NULL, NULL, 0};
  size_t n = lt_scene_triangle_count(mesh->scene);
  float *tris = malloc(9 * n * sizeof *tris);
  out.inside = malloc(3 * mesh->inside_count * sizeof *out.inside);
  if (!tris || !out.inside) return free(tris), free(out.inside), out;
  const float *src = lt_scene_triangles(mesh->scene);
  for (size_t i = 0; i < 9 * n; i++) tris[i] = src[i] * scale + offset;
  for (size_t i = 0; i < 3 * mesh->inside_count; i++) out.inside[i] = mesh->inside[i] * scale + offset;
  out.inside_count = mesh->inside_count;
  out.scene = scene_from(tris, n);
  free(tris);
  return out;
}

void lt_hc_free(lt_hc_mesh *mesh) {
  lt_scene_destroy(mesh->scene);
  free(mesh->inside);
  mesh->scene = NULL, mesh->inside = NULL;
}

static int compare_points(const void *a, const void *b) { return memcmp(a, b, 3 * sizeof(float)); }
static int compare_edges(const void *a, const void *b) { return memcmp(a, b, 6 * sizeof(float)); }

/* Sorts records of `width` floats and drops bitwise duplicates; returns how many remain. */
static size_t unique(float *v, size_t n, size_t width, int (*compare)(const void *, const void *)) {
  qsort(v, n, width * sizeof(float), compare);
  size_t m = 0;
  for (size_t i = 0; i < n; i++)
    if (m == 0 || memcmp(v + width * (m - 1), v + width * i, width * sizeof(float)) != 0)
      memmove(v + width * m++, v + width * i, width * sizeof(float));
  return m;
}

size_t lt_hc_vertices(const lt_scene *scene, float **out) {
  size_t n = lt_scene_triangle_count(scene);
  *out = malloc(9 * n * sizeof **out);
  if (!*out) return 0;
  memcpy(*out, lt_scene_triangles(scene), 9 * n * sizeof **out);
  return unique(*out, 3 * n, 3, compare_points);
}

size_t lt_hc_edge_midpoints(const lt_scene *scene, float **out) {
  size_t n = lt_scene_triangle_count(scene);
  const float *t = lt_scene_triangles(scene);
  float *edges = malloc(18 * n * sizeof *edges);
  *out = malloc(9 * n * sizeof **out);
  if (!edges || !*out) return free(edges), 0;

  /* Each edge with its endpoints in a fixed order, so that both triangles give the same key. */
  for (size_t i = 0; i < n; i++)
    for (int e = 0; e < 3; e++) {
      const float *a = t + 9 * i + 3 * e, *b = t + 9 * i + 3 * ((e + 1) % 3);
      int swap = memcmp(a, b, 3 * sizeof(float)) > 0;
      memcpy(edges + 6 * (3 * i + e), swap ? b : a, 3 * sizeof(float));
      memcpy(edges + 6 * (3 * i + e) + 3, swap ? a : b, 3 * sizeof(float));
    }
  size_t m = unique(edges, 3 * n, 6, compare_edges);
  for (size_t i = 0; i < m; i++)
    for (int k = 0; k < 3; k++) (*out)[3 * i + k] = (float)(0.5 * ((double)edges[6 * i + k] + edges[6 * i + 3 + k]));
  free(edges);
  return m;
}

void lt_hc_rays_to_targets(const lt_hc_mesh *mesh, const float *targets, size_t target_count, size_t count,
                           lt_ray *out) {
  for (size_t i = 0; i < count; i++) {
    const float *o = mesh->inside + 3 * (i % mesh->inside_count), *p = targets + 3 * (i % target_count);
    out[i] = (lt_ray){{o[0], o[1], o[2]}, 0.0f, {p[0] - o[0], p[1] - o[1], p[2] - o[2]}, INFINITY};
  }
}

void lt_hc_random_rays(const lt_hc_mesh *mesh, uint64_t seed, size_t count, lt_ray *out) {
  const float zero[3] = {0, 0, 0};
  for (size_t i = 0; i < count; i++) {
    const float *o = mesh->inside + 3 * (i % mesh->inside_count);
    float d[3];
    point_in_ball(&seed, zero, 1.0f, d);
    out[i] = (lt_ray){{o[0], o[1], o[2]}, 0.0f, {d[0], d[1], d[2]}, INFINITY};
  }
}

size_t lt_hc_closed_rays(const lt_hc_mesh *mesh, uint64_t seed, size_t count, lt_ray *out) {
  float *verts, *mids;
  size_t nv = lt_hc_vertices(mesh->scene, &verts), ne = lt_hc_edge_midpoints(mesh->scene, &mids);
  size_t third = count / 3;
  if (nv && ne) {
    lt_hc_rays_to_targets(mesh, verts, nv, third, out);
    lt_hc_rays_to_targets(mesh, mids, ne, third, out + third);
    lt_hc_random_rays(mesh, seed, count - 2 * third, out + 2 * third);
  }
  free(verts), free(mids);
  return nv && ne ? count : 0;
}

size_t lt_hc_invalid_rays(lt_ray *out, size_t max) {
  const float nan = NAN, inf = INFINITY;
  const lt_ray good = {{0.0f, 0.0f, 0.0f}, 0.0f, {1.0f, 0.25f, 0.125f}, INFINITY};
  size_t n = 0;
#define LT_HC_BAD(field, value)   \
  if (n < max) {                  \
    out[n] = good;                \
    out[n].field = (value);       \
    n++;                          \
  }
  for (int k = 0; k < 3; k++) {
    LT_HC_BAD(org[k], nan) LT_HC_BAD(org[k], inf) LT_HC_BAD(org[k], -inf)
    LT_HC_BAD(dir[k], nan) LT_HC_BAD(dir[k], inf) LT_HC_BAD(dir[k], -inf)
  }
  LT_HC_BAD(tmin, nan) LT_HC_BAD(tmin, inf) LT_HC_BAD(tmin, -inf) LT_HC_BAD(tmax, nan) LT_HC_BAD(tmax, -inf)
#undef LT_HC_BAD
  /* tmin > tmax, and zero directions of every sign. */
  if (n < max) out[n] = good, out[n].tmin = 1.0f, out[n].tmax = 0.5f, n++;
  for (int signs = 0; signs < 8 && n < max; signs++, n++) {
    out[n] = good;
    for (int k = 0; k < 3; k++) out[n].dir[k] = (signs >> k) & 1 ? -0.0f : 0.0f;
  }
  return n;
}

size_t lt_hc_count_misses(const lt_hit *hits, size_t n) {
  size_t misses = 0;
  for (size_t i = 0; i < n; i++) misses += hits[i].prim < 0;
  return misses;
}
