/* Hard cases for the numerics (DESIGN.md, "Numerics"), on every structure and build mode that
 * exists and on both backends: closed meshes never leak (rays at vertices, at edge midpoints,
 * in random directions, from inside), rays with zero and negative-zero direction components,
 * rays in a triangle's plane, rays starting on surfaces and on node boundaries, huge and tiny
 * coordinates, slivers and zero-area triangles, coincident triangles, invalid rays mixed into a
 * batch, the fast triangle test, and secondary rays that must not hit their own surface.
 * Every answer must equal the brute-force reference bit for bit (prim, t, u, v), which also
 * makes all structures, modes and backends equal to each other. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "runtime/bvh_ondemand_host.h"
#include "runtime/structure_internal.h"
#include "tests/hard_cases.h"
#include "tests/support.h"
#include "traversal/ray.h"

/* ---- Every structure, build mode and backend ---- */

/* Every structure and build mode, as the registry lists them. */
typedef struct variant {
  lt_structure_kind kind;
  lt_build_mode build;
} variant;

#define MAX_VARIANTS (3 * LT_STRUCTURE_COUNT)
static variant variants[MAX_VARIANTS];
static size_t VARIANTS;

/* One context per backend for the whole file: OpenCL kernels compile once. */
static lt_context *contexts[2];
static int context_count;

static int setup_contexts(void **state) {
  (void)state;
  lt_structure_kind kinds[MAX_VARIANTS];
  lt_build_mode modes[MAX_VARIANTS];
  VARIANTS = lt_structure_variants(kinds, modes, MAX_VARIANTS);
  for (size_t v = 0; v < VARIANTS; v++) variants[v] = (variant){kinds[v], modes[v]};
  lt_context_config native = {LT_DEVICE_NATIVE, 0, 2, 0, 1}, opencl = {LT_DEVICE_OPENCL, 0, 0, 0, 1};
  if (lt_context_create(&native, &contexts[context_count]) == LT_OK) context_count++;
  if (!getenv("LT_TEST_NATIVE_ONLY") && lt_context_create(&opencl, &contexts[context_count]) == LT_OK)
    context_count++;
  return context_count ? 0 : -1;
}

static int teardown_contexts(void **state) {
  (void)state;
  for (int i = 0; i < context_count; i++) lt_context_destroy(contexts[i]);
  context_count = 0;
  return 0;
}

static int quick(void) { return getenv("LT_TEST_QUICK") != NULL; }

/* Bitwise equality of whole hit records (t, u, v and prim); prints the first few others. */
static size_t count_different(const char *what, const lt_hit *a, const lt_hit *ref, size_t n) {
  size_t bad = 0;
  for (size_t i = 0; i < n; i++) {
    if (memcmp(&a[i], &ref[i], sizeof a[i]) == 0) continue;
    if (bad++ < 5)
      fprintf(stderr, "%s: ray %zu: prim %d t %.9g u %.9g v %.9g, reference prim %d t %.9g u %.9g v %.9g\n", what, i,
              a[i].prim, a[i].t, a[i].u, a[i].v, ref[i].prim, ref[i].t, ref[i].u, ref[i].v);
  }
  return bad;
}

typedef struct check {
  const char *what;
  int closed;                  /* every ray starts inside a closed mesh: a miss is a leak */
  int with_reference;          /* compare with brute force (otherwise with the first variant) */
  lt_intersect_kind intersect; /* the triangle test */
  size_t leaks;                /* out: the most misses any variant had (closed meshes) */
} check;

/* Traces rays closest-hit and any-hit with every variant on every backend; every closest
 * answer equals the reference (or the first variant's), any-hit agrees on occlusion, and on a
 * closed mesh nothing misses (unless the fast test is asked for, whose leaks are counted). */
static void check_everywhere(const lt_scene *scene, const lt_ray *rays, size_t n, check *c) {
  lt_hit *ref = malloc(n * sizeof *ref), *hits = malloc(n * sizeof *hits), *any = malloc(n * sizeof *any);
  assert_non_null(ref), assert_non_null(hits), assert_non_null(any);
  int flags = c->intersect == LT_INTERSECT_FAST ? LT_QUERY_FLAG_FAST_TRIANGLES : 0;
  if (c->with_reference) assert_int_equal(lt__reference_trace_flags(scene, rays, n, flags, ref), LT_OK);
  c->leaks = 0;
  int have_ref = c->with_reference;
  for (int x = 0; x < context_count; x++)
    for (size_t v = 0; v < VARIANTS; v++) {
      lt_structure_config config = lt_structure_config_default(variants[v].kind);
      config.build = variants[v].build, config.intersect = c->intersect;
      lt_structure *s;
      char what[256];
      snprintf(what, sizeof what, "%s: %s %s on %s", c->what, lt_structure_kind_name(variants[v].kind),
               lt_build_mode_name(variants[v].build), lt_context_device_name(contexts[x]));
      lt_status status = lt_structure_create(contexts[x], scene, &config, NULL, &s);
      if (status) fprintf(stderr, "%s: %s\n", what, lt_last_error());
      assert_int_equal(status, LT_OK);
      assert_int_equal(lt_structure_trace(s, rays, n, LT_QUERY_CLOSEST, hits, NULL), LT_OK);
      lt_structure_destroy(s);
      /* A fresh structure for any-hit, so that on-demand modes build from scratch for it too. */
      assert_int_equal(lt_structure_create(contexts[x], scene, &config, NULL, &s), LT_OK);
      assert_int_equal(lt_structure_trace(s, rays, n, LT_QUERY_ANY, any, NULL), LT_OK);
      lt_structure_destroy(s);

      if (!have_ref) memcpy(ref, hits, n * sizeof *ref), have_ref = 1;
      assert_int_equal(count_different(what, hits, ref, n), 0);
      assert_int_equal(lt_test_count_occlusion_mismatches(any, ref, n), 0);
      size_t misses = lt_hc_count_misses(hits, n);
      if (misses > c->leaks) c->leaks = misses;
      if (c->closed && c->intersect == LT_INTERSECT_WATERTIGHT) {
        if (misses) fprintf(stderr, "%s: %zu of %zu rays leak\n", what, misses, n);
        assert_int_equal(misses, 0);
      }
    }
  fprintf(stderr, "%s: %zu rays, %zu variants x %d backends agree%s", c->what, n, VARIANTS, context_count,
          c->with_reference ? " with brute force" : "");
  if (c->closed) fprintf(stderr, "; leaks: %zu", c->leaks);
  fputc('\n', stderr);
  free(ref), free(hits), free(any);
}

/* The closed-mesh rays (vertices, edge midpoints, random) of a mesh, checked everywhere. */
static size_t check_closed_mesh(const char *what, const lt_hc_mesh *mesh, size_t n, lt_intersect_kind intersect) {
  assert_non_null(mesh->scene);
  lt_ray *rays = malloc(n * sizeof *rays);
  assert_non_null(rays);
  assert_int_equal(lt_hc_closed_rays(mesh, 11, n, rays), n);
  check c = {what, 1, 1, intersect, 0};
  check_everywhere(mesh->scene, rays, n, &c);
  free(rays);
  return c.leaks;
}

/* ---- Closed meshes ---- */

/* Icosphere levels 0 to 4, a torus and a cube of shared edges: rays from inside at every
 * vertex, every edge midpoint and in random directions never escape. */
static void robustness_closed_meshes_never_leak(void **state) {
  (void)state;
  for (int level = 0; level <= (quick() ? 2 : 4); level++) {
    char what[32];
    snprintf(what, sizeof what, "sphere:%d", level);
    lt_hc_mesh sphere = lt_hc_sphere(level, 3);
    check_closed_mesh(what, &sphere, quick() ? 600 : 3000, LT_INTERSECT_WATERTIGHT);
    lt_hc_free(&sphere);
  }
  lt_hc_mesh torus = lt_hc_torus(48, 24), cube = lt_hc_cube(16, 5);
  check_closed_mesh("torus 48x24", &torus, quick() ? 600 : 3000, LT_INTERSECT_WATERTIGHT);
  check_closed_mesh("cube of shared edges 16x16", &cube, quick() ? 600 : 3000, LT_INTERSECT_WATERTIGHT);
  lt_hc_free(&torus), lt_hc_free(&cube);
}

/* The case Embree 3.13.5 (robust flag) lets 8 of 50,000 rays escape from: rays from inside a
 * closed icosphere of 81,920 triangles aimed exactly at its vertices, half of them from the
 * centre (the ray passes exactly through the vertex) and half from points inside. */
static void robustness_sphere_vertex_rays_never_leak(void **state) {
  (void)state;
  lt_hc_mesh sphere = lt_hc_sphere(quick() ? 4 : 6, 7);
  assert_non_null(sphere.scene);
  float *verts;
  size_t nv = lt_hc_vertices(sphere.scene, &verts), n = quick() ? 5000 : 50000;
  lt_ray *rays = malloc(n * sizeof *rays);
  lt_hc_rays_to_targets(&sphere, verts, nv, n, rays);
  for (size_t i = 0; i < n; i += 2) rays[i].org[0] = rays[i].org[1] = rays[i].org[2] = 0.0f;
  for (size_t i = 0; i < n; i += 2)
    for (int k = 0; k < 3; k++) rays[i].dir[k] = verts[3 * ((i / 2) % nv) + k];

  /* Brute force over 82k triangles is slow: the variants must agree with each other, and a
   * sample of the rays with the reference. */
  check c = {"sphere vertex rays", 1, 0, LT_INTERSECT_WATERTIGHT, 0};
  check_everywhere(sphere.scene, rays, n, &c);
  assert_int_equal(c.leaks, 0);
  check sample = {"sphere vertex rays, sample", 1, 1, LT_INTERSECT_WATERTIGHT, 0};
  check_everywhere(sphere.scene, rays, quick() ? 100 : 400, &sample);
  free(verts), free(rays);
  lt_hc_free(&sphere);
}

/* ---- Direction components of 0 and -0; rays in a triangle's plane ---- */

/* Axis-aligned and face-diagonal rays from integer points inside the shared-edge cube: they
 * hit faces exactly on grid edges and vertices. Every zero component is tried as +0 and -0,
 * and both must give the same answers (and no leak). */
static void robustness_zero_and_negative_zero_direction_components(void **state) {
  (void)state;
  lt_hc_mesh cube = lt_hc_cube(8, 9);
  size_t n = 0, max = 4096;
  lt_ray *rays = malloc(max * sizeof *rays);
  for (size_t p = 0; p < cube.inside_count; p += 2) /* the integer points */
    for (int d = 0; d < 27 && n + 8 <= max; d++) {
      int comp[3] = {d % 3 - 1, d / 3 % 3 - 1, d / 9 - 1};
      if (!comp[0] && !comp[1] && !comp[2]) continue;
      /* Every sign of zero on the zero components. */
      for (int signs = 0; signs < 8; signs++) {
        lt_ray *r = &rays[n++];
        *r = (lt_ray){{cube.inside[3 * p], cube.inside[3 * p + 1], cube.inside[3 * p + 2]}, 0.0f, {0, 0, 0}, INFINITY};
        for (int k = 0; k < 3; k++) r->dir[k] = comp[k] ? (float)comp[k] : ((signs >> k) & 1 ? -0.0f : 0.0f);
      }
    }
  check c = {"axis-aligned rays with +0 and -0 in the cube", 1, 1, LT_INTERSECT_WATERTIGHT, 0};
  check_everywhere(cube.scene, rays, n, &c);

  /* The sign of a zero component changes nothing. */
  lt_hit *hits = malloc(n * sizeof *hits);
  assert_int_equal(lt_reference_trace(cube.scene, rays, n, LT_QUERY_CLOSEST, hits), LT_OK);
  for (size_t i = 0; i < n; i += 8)
    for (int s = 1; s < 8; s++) {
      assert_int_equal(hits[i + s].prim, hits[i].prim);
      assert_memory_equal(&hits[i + s].t, &hits[i].t, sizeof(float));
    }
  free(hits), free(rays);
  lt_hc_free(&cube);
}

/* Rays lying exactly in the planes of the cube's faces and of its grid lines, from outside
 * and from points on the faces: the triangles they run along are never hit (their
 * determinant is 0), and every structure says what the reference says. */
static void robustness_rays_parallel_to_triangle_planes(void **state) {
  (void)state;
  lt_hc_mesh cube = lt_hc_cube(8, 13);
  size_t n = 0, max = 2048;
  lt_ray *rays = malloc(max * sizeof *rays);
  uint64_t seed = 17;
  for (int axis = 0; axis < 3; axis++)
    for (int side = -1; side <= 1; side += 2)
      for (int i = 0; i < 100 && n < max; i++) {
        /* In the plane axis = side * 4: origin anywhere in the plane (on the face or beyond
         * it), direction with a zero component along the axis. */
        lt_ray *r = &rays[n++];
        for (int k = 0; k < 3; k++) {
          float u = 12.0f * lt__splitmix_unit(&seed) - 6.0f;
          r->org[k] = i % 3 ? floorf(u) : u;
          r->dir[k] = 2.0f * lt__splitmix_unit(&seed) - 1.0f;
        }
        r->org[axis] = (float)(side * 4);
        r->dir[axis] = i % 2 ? 0.0f : -0.0f;
        r->tmin = 0.0f, r->tmax = INFINITY;
      }
  check c = {"rays in the planes of the cube's faces", 0, 1, LT_INTERSECT_WATERTIGHT, 0};
  check_everywhere(cube.scene, rays, n, &c);

  /* A ray in a face's plane never hits a triangle of that face. */
  lt_hit *hits = malloc(n * sizeof *hits);
  assert_int_equal(lt_reference_trace(cube.scene, rays, n, LT_QUERY_CLOSEST, hits), LT_OK);
  const float *tris = lt_scene_triangles(cube.scene);
  for (size_t i = 0; i < n; i++) {
    if (hits[i].prim < 0) continue;
    const float *t = tris + 9 * (size_t)hits[i].prim;
    int in_plane = 0;
    for (int k = 0; k < 3; k++)
      in_plane |= rays[i].dir[k] == 0.0f && t[k] == rays[i].org[k] && t[3 + k] == rays[i].org[k] && t[6 + k] == rays[i].org[k];
    assert_false(in_plane);
  }
  free(hits), free(rays);
  lt_hc_free(&cube);
}

/* ---- Rays starting on surfaces and on node boundaries ---- */

/* Origins exactly at vertices, on edges, inside triangles, and on the faces and corners of
 * the full tree's node boxes, with tmin 0, in random directions: whether the surface the ray
 * starts on counts is decided by the same arithmetic everywhere. */
static void robustness_rays_starting_on_surfaces_and_node_boundaries(void **state) {
  (void)state;
  lt_scene *scene;
  assert_int_equal(lt_scene_load("sphere:3", &scene), LT_OK);
  size_t n = 0, max = 6000;
  lt_ray *rays = malloc(max * sizeof *rays);
  uint64_t seed = 19;
  const float *tris = lt_scene_triangles(scene);
  size_t count = lt_scene_triangle_count(scene);

  /* On the surface: a vertex, an edge's midpoint, a barycentric point. */
  for (size_t i = 0; i < 3000; i++) {
    const float *t = tris + 9 * ((i * 7919) % count);
    float w1 = lt__splitmix_unit(&seed), w2 = lt__splitmix_unit(&seed) * (1 - w1), p[3];
    for (int k = 0; k < 3; k++)
      p[k] = i % 3 == 0 ? t[k] : i % 3 == 1 ? 0.5f * (t[k] + t[3 + k]) : (1 - w1 - w2) * t[k] + w1 * t[3 + k] + w2 * t[6 + k];
    lt_ray *r = &rays[n++];
    *r = (lt_ray){{p[0], p[1], p[2]}, 0.0f, {0, 0, 0}, INFINITY};
    for (int k = 0; k < 3; k++) r->dir[k] = 2.0f * lt__splitmix_unit(&seed) - 1.0f;
  }

  /* On node boundaries: corners and face centres of the full tree's boxes. */
  lt_structure_config full = lt_structure_config_default(LT_STRUCTURE_BVH);
  full.build = LT_BUILD_FULL, full.max_leaf_size = 4;
  lt_structure *s;
  assert_int_equal(lt_structure_create(contexts[0], scene, &full, NULL, &s), LT_OK);
  lt_bvh_node *nodes;
  int node_count, *index;
  assert_int_equal(lt__ondemand_snapshot(lt__structure_ondemand(s), &nodes, &node_count, &index), LT_OK);
  for (int i = 1; i < node_count && n + 2 <= max; i++) {
    const lt_bvh_node *nd = &nodes[i];
    float lo[3] = {nd->left_xy.x, nd->left_xy.z, nd->lr_z.x}, hi[3] = {nd->left_xy.y, nd->left_xy.w, nd->lr_z.y};
    for (int j = 0; j < 2; j++) {
      lt_ray *r = &rays[n++];
      *r = (lt_ray){{0, 0, 0}, 0.0f, {0, 0, 0}, INFINITY};
      for (int k = 0; k < 3; k++) {
        r->org[k] = j == 0 ? ((i >> k) & 1 ? hi[k] : lo[k]) : 0.5f * (lo[k] + hi[k]);
        r->dir[k] = 2.0f * lt__splitmix_unit(&seed) - 1.0f;
      }
      if (j == 1) r->org[i % 3] = (i & 8) ? hi[i % 3] : lo[i % 3];
      if (i % 5 == 0) r->dir[(i + 1) % 3] = 0.0f; /* running along the box's face */
    }
  }
  free(nodes), free(index);
  lt_structure_destroy(s);
  check c = {"rays starting on surfaces and node boundaries", 0, 1, LT_INTERSECT_WATERTIGHT, 0};
  check_everywhere(scene, rays, n, &c);
  free(rays);
  lt_scene_destroy(scene);
}

/* ---- Huge and tiny coordinates ---- */

/* A sphere of radius 100 and the shared-edge cube, both moved by 1e6 (where floats are 1/16
 * apart): still closed, still no leak, still the reference's answers. */
static void robustness_huge_coordinates(void **state) {
  (void)state;
  lt_hc_mesh sphere = lt_hc_sphere(3, 23), cube = lt_hc_cube(8, 29);
  lt_hc_mesh far_sphere = lt_hc_transform(&sphere, 100.0f, 1e6f), far_cube = lt_hc_transform(&cube, 1.0f, 1e6f);
  check_closed_mesh("sphere:3, radius 100, at 1e6", &far_sphere, quick() ? 600 : 3000, LT_INTERSECT_WATERTIGHT);
  check_closed_mesh("cube 8x8 at 1e6", &far_cube, quick() ? 600 : 3000, LT_INTERSECT_WATERTIGHT);
  lt_hc_free(&sphere), lt_hc_free(&cube), lt_hc_free(&far_sphere), lt_hc_free(&far_cube);
}

/* A sphere whose edges are about 1e-6 long, at the origin and moved to 1 (where floats are
 * 6e-8 apart, so that its vertices snap to a coarse grid): no leak, the reference's answers. */
static void robustness_tiny_triangles(void **state) {
  (void)state;
  lt_hc_mesh sphere = lt_hc_sphere(3, 31);
  lt_hc_mesh tiny = lt_hc_transform(&sphere, 8e-6f, 0.0f), tiny_far = lt_hc_transform(&sphere, 8e-6f, 1.0f);
  check_closed_mesh("sphere:3 with 1e-6 edges", &tiny, quick() ? 600 : 3000, LT_INTERSECT_WATERTIGHT);
  check_closed_mesh("sphere:3 with 1e-6 edges at 1", &tiny_far, quick() ? 600 : 3000, LT_INTERSECT_WATERTIGHT);
  lt_hc_free(&sphere), lt_hc_free(&tiny), lt_hc_free(&tiny_far);
}

/* ---- Degenerate and coincident triangles ---- */

/* Long slivers (60 units long, 0.02 wide, any orientation): every structure's hit distance is
 * within a few float roundings of the exact distance to the triangle's plane (the watertight
 * test's own distance was off by up to 3% on them). */
static void robustness_long_slivers_have_accurate_distances(void **state) {
  (void)state;
  enum { SLIVERS = 400, PER = 8 };
  float *tris = malloc(9 * SLIVERS * sizeof *tris);
  uint64_t seed = 61;
  for (int i = 0; i < SLIVERS; i++) {
    double c[3], d[3], e[3], dl = 0, ed = 0, el = 0;
    for (int k = 0; k < 3; k++) c[k] = 200.0 * lt__splitmix_unit(&seed) - 100.0, d[k] = lt__splitmix_unit(&seed) - 0.5;
    for (int k = 0; k < 3; k++) e[k] = lt__splitmix_unit(&seed) - 0.5, dl += d[k] * d[k];
    for (int k = 0; k < 3; k++) d[k] /= sqrt(dl), ed += e[k] * d[k];
    for (int k = 0; k < 3; k++) e[k] -= ed * d[k], el += e[k] * e[k];
    double along = 10.0 * lt__splitmix_unit(&seed);
    for (int k = 0; k < 3; k++) {
      tris[9 * i + k] = (float)(c[k] - 30.0 * d[k]);
      tris[9 * i + 3 + k] = (float)(c[k] + 30.0 * d[k]);
      tris[9 * i + 6 + k] = (float)(c[k] + 0.02 * e[k] / sqrt(el) + along * d[k]);
    }
  }
  lt_scene *scene;
  assert_int_equal(lt_scene_from_triangles(tris, SLIVERS, &scene), LT_OK);

  /* Rays at random points inside each sliver, from random places around it. */
  size_t n = (size_t)SLIVERS * PER;
  lt_ray *rays = malloc(n * sizeof *rays);
  for (size_t i = 0; i < n; i++) {
    const float *t = tris + 9 * (i / PER);
    float a = lt__splitmix_unit(&seed), b = lt__splitmix_unit(&seed);
    if (a + b > 1.0f) a = 1.0f - a, b = 1.0f - b;
    float p[3], o[3];
    for (int k = 0; k < 3; k++) {
      p[k] = (1.0f - a - b) * t[k] + a * t[3 + k] + b * t[6 + k];
      o[k] = p[k] + 40.0f * lt__splitmix_unit(&seed) - 20.0f;
    }
    rays[i] = (lt_ray){{o[0], o[1], o[2]}, 0.0f, {p[0] - o[0], p[1] - o[1], p[2] - o[2]}, INFINITY};
  }
  check c = {"long slivers", 0, 1, LT_INTERSECT_WATERTIGHT, 0};
  check_everywhere(scene, rays, n, &c);

  /* The reference's distances (which every structure matched bit for bit) against the plane. */
  lt_hit *hits = malloc(n * sizeof *hits);
  assert_int_equal(lt_reference_trace(scene, rays, n, LT_QUERY_CLOSEST, hits), LT_OK);
  double worst = 0.0;
  size_t hit = 0;
  for (size_t i = 0; i < n; i++) {
    if (hits[i].prim < 0) continue;
    const float *t = tris + 9 * hits[i].prim;
    double e1[3], e2[3], nn[3], num = 0, den = 0;
    for (int k = 0; k < 3; k++) e1[k] = (double)t[3 + k] - t[k], e2[k] = (double)t[6 + k] - t[k];
    nn[0] = e1[1] * e2[2] - e1[2] * e2[1], nn[1] = e1[2] * e2[0] - e1[0] * e2[2], nn[2] = e1[0] * e2[1] - e1[1] * e2[0];
    for (int k = 0; k < 3; k++) num += nn[k] * ((double)t[k] - rays[i].org[k]), den += nn[k] * rays[i].dir[k];
    double exact = num / den, err = fabs(hits[i].t - exact) / fabs(exact);
    worst = err > worst ? err : worst;
    hit++;
  }
  fprintf(stderr, "long slivers: %zu hits, worst relative distance error %.3g\n", hit, worst);
  assert_true(hit > n / 2);
  assert_true(worst < 1e-6);
  free(hits), free(rays), free(tris);
  lt_scene_destroy(scene);
}

/* Slivers (a vertex one float step off the opposite edge), needles, and zero-area triangles
 * (collinear, two equal vertices, three equal vertices), with rays aimed at their vertices,
 * edges and insides: zero-area triangles are never hit, everything else is the reference's. */
static void robustness_sliver_and_zero_area_triangles(void **state) {
  (void)state;
  enum { KINDS = 6, COPIES = 60 };
  float *tris = malloc(9 * KINDS * COPIES * sizeof *tris);
  uint64_t seed = 37;
  size_t count = 0;
  for (int c = 0; c < COPIES; c++)
    for (int kind = 0; kind < KINDS; kind++) {
      float a[3], b[3], m[3];
      /* Multiples of 1/64, so that the midpoint is exact and "collinear" means collinear. */
      for (int k = 0; k < 3; k++)
        a[k] = floorf(256.0f * lt__splitmix_unit(&seed) - 128.0f) / 64.0f, b[k] = floorf(256.0f * lt__splitmix_unit(&seed) - 128.0f) / 64.0f;
      for (int k = 0; k < 3; k++) m[k] = 0.5f * (a[k] + b[k]);
      float *t = tris + 9 * count++;
      memcpy(t, a, sizeof a), memcpy(t + 3, b, sizeof b);
      if (kind == 0) memcpy(t + 6, m, sizeof m);                        /* collinear, on the midpoint */
      if (kind == 1) memcpy(t + 6, a, sizeof a);                        /* two equal vertices */
      if (kind == 2) memcpy(t + 3, a, sizeof a), memcpy(t + 6, a, sizeof a); /* a point */
      if (kind == 3) memcpy(t + 6, m, sizeof m), t[6] = nextafterf(m[0], INFINITY); /* a sliver */
      if (kind == 4) memcpy(t + 6, m, sizeof m), t[7] += 1e-6f;          /* a needle */
      if (kind == 5)
        for (int k = 0; k < 3; k++) t[6 + k] = m[k] + 0.5f * (b[(k + 1) % 3] - a[(k + 1) % 3]); /* a fair one */
    }
  lt_scene *scene;
  assert_int_equal(lt_scene_from_triangles(tris, count, &scene), LT_OK);

  /* Rays from random points at each triangle's vertices, edge midpoints and centroid; and rays
   * that start there, in random directions (a zero-area triangle reported hits at t = 0 for
   * rays starting on it). */
  size_t n = 12 * count;
  lt_ray *rays = malloc(n * sizeof *rays);
  for (size_t i = 0; i < n; i++) {
    const float *t = tris + 9 * (i / 12);
    int aim = (int)(i % 6), from = (int)(i % 12) >= 6;
    float p[3], o[3];
    for (int k = 0; k < 3; k++) {
      p[k] = aim < 3 ? t[3 * aim + k] : aim < 5 ? 0.5f * (t[k] + t[3 * (aim - 2) + k]) : (t[k] + t[3 + k] + t[6 + k]) / 3.0f;
      o[k] = 8.0f * lt__splitmix_unit(&seed) - 4.0f;
    }
    if (from)
      rays[i] = (lt_ray){{p[0], p[1], p[2]}, 0.0f, {o[0], o[1], o[2]}, INFINITY};
    else
      rays[i] = (lt_ray){{o[0], o[1], o[2]}, 0.0f, {p[0] - o[0], p[1] - o[1], p[2] - o[2]}, INFINITY};
  }
  check c = {"slivers and zero-area triangles", 0, 1, LT_INTERSECT_WATERTIGHT, 0};
  check_everywhere(scene, rays, n, &c);
  lt_hit *hits = malloc(n * sizeof *hits);
  assert_int_equal(lt_reference_trace(scene, rays, n, LT_QUERY_CLOSEST, hits), LT_OK);
  size_t hit_kind[KINDS] = {0};
  for (size_t i = 0; i < n; i++)
    if (hits[i].prim >= 0) hit_kind[hits[i].prim % KINDS]++;
  fprintf(stderr, "hits on collinear %zu, two equal vertices %zu, a point %zu, slivers %zu, needles %zu, fair %zu\n",
          hit_kind[0], hit_kind[1], hit_kind[2], hit_kind[3], hit_kind[4], hit_kind[5]);
  assert_int_equal(hit_kind[0] + hit_kind[1] + hit_kind[2], 0);
  assert_true(hit_kind[5] > 0);
  free(hits), free(rays), free(tris);
  lt_scene_destroy(scene);
}

/* Each triangle of sphere:2 repeated 40 times (more than a leaf holds, so the copies end up in
 * different leaves and subtrees), the copies interleaved with the other triangles: the closest
 * hit is always the lowest-numbered copy, everywhere. A second set of copies has its vertices
 * rotated (same triangle, different arithmetic): ties are still broken by number. */
static void robustness_coincident_triangles_break_ties_by_lowest_number(void **state) {
  (void)state;
  enum { COPIES = 40 };
  lt_scene *sphere;
  assert_int_equal(lt_scene_load("sphere:2", &sphere), LT_OK);
  size_t base = lt_scene_triangle_count(sphere), count = base * COPIES;
  const float *src = lt_scene_triangles(sphere);
  float *tris = malloc(9 * count * sizeof *tris);
  for (size_t c = 0; c < COPIES; c++)
    for (size_t i = 0; i < base; i++) {
      /* Copy c of triangle i is triangle c * base + i; odd copies rotate the vertices. */
      int rot = (int)(c % 2) * (1 + (int)(i % 2));
      for (int v = 0; v < 3; v++) memcpy(tris + 9 * (c * base + i) + 3 * v, src + 9 * i + 3 * ((v + rot) % 3), 12);
    }
  lt_scene *scene;
  assert_int_equal(lt_scene_from_triangles(tris, count, &scene), LT_OK);
  size_t n = quick() ? 300 : 1500;
  lt_ray *rays = malloc(n * sizeof *rays);
  lt_test_random_rays(scene, 41, n, rays);
  check c = {"40 coincident copies of every triangle", 0, 1, LT_INTERSECT_WATERTIGHT, 0};
  check_everywhere(scene, rays, n, &c);

  /* Exact copies tie; the winner is one of the first two copies (0 and its rotated twin). */
  lt_hit *hits = malloc(n * sizeof *hits);
  assert_int_equal(lt_reference_trace(scene, rays, n, LT_QUERY_CLOSEST, hits), LT_OK);
  size_t hit = 0;
  for (size_t i = 0; i < n; i++) {
    if (hits[i].prim < 0) continue;
    hit++;
    assert_true((size_t)hits[i].prim < 2 * base);
  }
  assert_true(hit > n / 4);
  free(hits), free(rays), free(tris);
  lt_scene_destroy(scene), lt_scene_destroy(sphere);
}

/* ---- Invalid rays ---- */

/* Rays with NaN or infinite components, zero directions of every sign and tmin > tmax,
 * interleaved with good rays in one batch: each bad ray is a defined miss (prim -1, t +inf,
 * u = v = 0), nothing hangs or crashes, and the good rays get the reference's answers. */
static void robustness_invalid_rays_miss_and_leave_the_batch_alone(void **state) {
  (void)state;
  lt_hc_mesh sphere = lt_hc_sphere(3, 43);
  lt_ray bad[64];
  size_t nbad = lt_hc_invalid_rays(bad, 64), ngood = 600, n = nbad + ngood;
  lt_ray *rays = malloc(n * sizeof *rays), *good = malloc(ngood * sizeof *good);
  lt_hc_random_rays(&sphere, 47, ngood, good);
  size_t g = 0, b = 0;
  for (size_t i = 0; i < n; i++) rays[i] = (i % 10 == 3 && b < nbad) || g == ngood ? bad[b++] : good[g++];
  check c = {"invalid rays mixed with good ones", 0, 1, LT_INTERSECT_WATERTIGHT, 0};
  check_everywhere(sphere.scene, rays, n, &c);
  lt_hit *hits = malloc(n * sizeof *hits);
  assert_int_equal(lt_reference_trace(sphere.scene, rays, n, LT_QUERY_CLOSEST, hits), LT_OK);
  size_t misses = 0;
  for (size_t i = 0; i < n; i++) {
    lt_ray_setup r = lt_ray_prepare(rays[i].org[0], rays[i].org[1], rays[i].org[2], rays[i].tmin, rays[i].dir[0],
                                    rays[i].dir[1], rays[i].dir[2], rays[i].tmax);
    if (r.valid) {
      assert_true(hits[i].prim >= 0); /* every good ray starts inside the sphere */
      continue;
    }
    misses++;
    assert_int_equal(hits[i].prim, -1);
    assert_true(isinf(hits[i].t) && hits[i].t > 0 && hits[i].u == 0.0f && hits[i].v == 0.0f);
  }
  assert_int_equal(misses, nbad);
  free(hits), free(rays), free(good);
  lt_hc_free(&sphere);
}

/* ---- The fast triangle test ---- */

/* With --intersect fast every structure, mode and backend still gives exactly the brute-force
 * answer of the same test; it may leak at vertices and edges, and the count is printed. */
static void robustness_fast_test_agrees_everywhere(void **state) {
  (void)state;
  lt_hc_mesh sphere = lt_hc_sphere(quick() ? 2 : 4, 53), cube = lt_hc_cube(16, 59);
  size_t leaks = check_closed_mesh("sphere, fast test", &sphere, quick() ? 600 : 3000, LT_INTERSECT_FAST);
  leaks += check_closed_mesh("cube of shared edges, fast test", &cube, quick() ? 600 : 3000, LT_INTERSECT_FAST);
  fprintf(stderr, "the fast test leaked %zu rays (the watertight test: none)\n", leaks);
  lt_hc_free(&sphere), lt_hc_free(&cube);
}

/* ---- Secondary rays ---- */

/* Ambient-occlusion rays from the outside of a convex closed mesh can only hit that mesh by
 * hitting their own surface: none may, at the origin, at 1e6 and with tiny triangles. Rays
 * from the inside surface (long enough to cross the sphere) must all hit. */
static void robustness_ambient_occlusion_rays_never_hit_their_own_surface(void **state) {
  (void)state;
  lt_hc_mesh sphere = lt_hc_sphere(4, 61);
  const float scales[3] = {1.0f, 100.0f, 1e-5f}, offsets[3] = {0.0f, 1e6f, 1.0f};
  for (int c = 0; c < 3; c++) {
    lt_hc_mesh m = lt_hc_transform(&sphere, scales[c], offsets[c]);
    for (int inside = 0; inside < 2; inside++) {
      /* Primary rays from a camera outside looking at the centre, or from the centre out. */
      size_t n = quick() ? 1000 : 4000, samples = 8;
      lt_ray *primary = malloc(n * sizeof *primary), *ao = malloc(n * samples * sizeof *ao);
      lt_hit *hits = malloc(n * samples * sizeof *hits);
      uint64_t seed = 67;
      for (size_t i = 0; i < n; i++) {
        float d[3], o[3], len = 0.0f;
        for (int k = 0; k < 3; k++) d[k] = 2.0f * lt__splitmix_unit(&seed) - 1.0f, len += d[k] * d[k];
        for (int k = 0; k < 3; k++) d[k] /= sqrtf(len);
        for (int k = 0; k < 3; k++) o[k] = inside ? offsets[c] : offsets[c] + 3.0f * scales[c] * d[k];
        primary[i] = (lt_ray){{o[0], o[1], o[2]}, 0.0f, {inside ? d[0] : -d[0], inside ? d[1] : -d[1], inside ? d[2] : -d[2]}, INFINITY};
      }
      assert_int_equal(lt_reference_trace(m.scene, primary, n, LT_QUERY_CLOSEST, hits), LT_OK);
      size_t m_rays = lt_ao_rays(m.scene, primary, hits, n, (int)samples, 4.0f * scales[c], 71, ao);
      assert_true(m_rays > n * samples / 2);
      char what[96];
      snprintf(what, sizeof what, "AO rays from the %s of a sphere at scale %g, offset %g", inside ? "inside" : "outside",
               scales[c], offsets[c]);
      check chk = {what, inside, 1, LT_INTERSECT_WATERTIGHT, 0};
      check_everywhere(m.scene, ao, m_rays, &chk);
      if (!inside) {
        assert_int_equal(lt_reference_trace(m.scene, ao, m_rays, LT_QUERY_CLOSEST, hits), LT_OK);
        size_t self = m_rays - lt_hc_count_misses(hits, m_rays);
        if (self) fprintf(stderr, "%s: %zu of %zu hit their own surface\n", what, self, m_rays);
        assert_int_equal(self, 0);
      }
      free(primary), free(ao), free(hits);
    }
    lt_hc_free(&m);
  }
  lt_hc_free(&sphere);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(robustness_closed_meshes_never_leak),
      cmocka_unit_test(robustness_sphere_vertex_rays_never_leak),
      cmocka_unit_test(robustness_zero_and_negative_zero_direction_components),
      cmocka_unit_test(robustness_rays_parallel_to_triangle_planes),
      cmocka_unit_test(robustness_rays_starting_on_surfaces_and_node_boundaries),
      cmocka_unit_test(robustness_huge_coordinates),
      cmocka_unit_test(robustness_tiny_triangles),
      cmocka_unit_test(robustness_sliver_and_zero_area_triangles),
      cmocka_unit_test(robustness_long_slivers_have_accurate_distances),
      cmocka_unit_test(robustness_coincident_triangles_break_ties_by_lowest_number),
      cmocka_unit_test(robustness_invalid_rays_miss_and_leave_the_batch_alone),
      cmocka_unit_test(robustness_fast_test_agrees_everywhere),
      cmocka_unit_test(robustness_ambient_occlusion_rays_never_hit_their_own_surface),
  };
  return cmocka_run_group_tests(tests, setup_contexts, teardown_contexts);
}
