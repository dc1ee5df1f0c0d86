/* The uniform grid (builders/host/grid.c, traversal/grid_traverse.h driven on host arrays as
 * C) against the brute-force reference: every closest hit equal bit for bit (t, u, v, prim),
 * any-hit agreeing on occlusion, on generated scenes and on the hard cases that break a naive
 * 3D-DDA: closed meshes at their vertices and edges, rays along cell planes and grid lines,
 * direction components of +0 and -0, nearly parallel and far-away rays, flat scenes, one
 * triangle, coincident triangles, huge and tiny coordinates, rays that end or start exactly at
 * a hit. Also the build: resolution, the statistics, and every reference where it belongs. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "builders/host/grid.h"
#include "runtime/irgrid_host.h"
#include "runtime/structure_internal.h"
#include "tests/hard_cases.h"
#include "tests/support.h"
#include "traversal/grid_traverse.h"

/* ---- Tracing the arrays ---- */

typedef struct totals {
  size_t rays, hits;
  double steps, tests; /* per ray, closest hit */
} totals;

/* Traces every ray with the given query flags; a miss is written as the kernels write it. */
static void trace_grid(const lt__grid *grid, const float *verts, const lt_ray *rays, size_t n, int flags, lt_hit *hits,
                       lt_trace_counters *counters) {
  for (size_t i = 0; i < n; i++) {
    const lt_ray *ray = &rays[i];
    lt_ray_setup r = lt_ray_prepare(ray->org[0], ray->org[1], ray->org[2], ray->tmin, ray->dir[0], ray->dir[1],
                                    ray->dir[2], ray->tmax);
    r.flags = flags;
    lt_hit_record hit;
    int status = lt_grid_traverse(&r, &grid->header, grid->cell_begin, grid->refs, verts, flags & LT_QUERY_FLAG_ANY,
                                  &hit, counters);
    assert_int_equal(status, 0);
    if (hit.prim < 0) hit.t = INFINITY, hit.u = hit.v = 0.0f;
    hits[i] = (lt_hit){hit.t, hit.u, hit.v, hit.prim};
  }
}

/* Bitwise equality of whole hit records; prints the first few others. */
static size_t count_different(const char *what, const lt_ray *rays, const lt_hit *a, const lt_hit *ref, size_t n) {
  size_t bad = 0;
  for (size_t i = 0; i < n; i++) {
    if (memcmp(&a[i], &ref[i], sizeof a[i]) == 0) continue;
    if (bad++ < 5)
      fprintf(stderr,
              "%s: ray %zu (%.9g %.9g %.9g) + t (%.9g %.9g %.9g), t in [%.9g, %.9g]: prim %d t %.9g u %.9g v %.9g, "
              "reference prim %d t %.9g u %.9g v %.9g\n",
              what, i, rays[i].org[0], rays[i].org[1], rays[i].org[2], rays[i].dir[0], rays[i].dir[1], rays[i].dir[2],
              rays[i].tmin, rays[i].tmax, a[i].prim, a[i].t, a[i].u, a[i].v, ref[i].prim, ref[i].t, ref[i].u, ref[i].v);
  }
  return bad;
}

/* Closest hits (bitwise) and occlusion against the reference with the same triangle test. */
static totals check_rays(const char *what, const lt_scene *scene, const lt__grid *grid, const lt_ray *rays, size_t n,
                         int flags) {
  lt_hit *ref = malloc(n * sizeof *ref), *hits = malloc(n * sizeof *hits);
  assert_non_null(ref), assert_non_null(hits);
  const float *verts = lt_scene_triangles(scene);
  assert_int_equal(lt__reference_trace_flags(scene, rays, n, flags, ref), LT_OK);

  lt_trace_counters closest = {0, 0}, any = {0, 0};
  trace_grid(grid, verts, rays, n, flags, hits, &closest);
  assert_int_equal(count_different(what, rays, hits, ref, n), 0);
  trace_grid(grid, verts, rays, n, flags | LT_QUERY_FLAG_ANY, hits, &any);
  assert_int_equal(lt_test_count_occlusion_mismatches(hits, ref, n), 0);
  assert_true(any.traversal_steps <= closest.traversal_steps);

  totals t = {n, n - lt_hc_count_misses(ref, n), (double)closest.traversal_steps / (double)(n ? n : 1),
              (double)closest.intersections / (double)(n ? n : 1)};
  free(ref), free(hits);
  return t;
}

/* ---- Checking the build ---- */

static void triangle_box(const float *t, float lo[3], float hi[3]) {
  for (int k = 0; k < 3; k++) {
    lo[k] = fminf(t[k], fminf(t[3 + k], t[6 + k]));
    hi[k] = fmaxf(t[k], fmaxf(t[3 + k], t[6 + k]));
  }
}

/* The offsets, the statistics, and every reference: a triangle sits in exactly the cells whose
 * closed box meets its box (counted here by a plain scan of the planes), in number order. */
static void check_grid(const lt__grid *grid, const float *tris, size_t n) {
  const lt_grid_header *h = &grid->header;
  int dims[3] = {h->dims.x, h->dims.y, h->dims.z};
  lt_grid_axis axes[3];
  for (int k = 0; k < 3; k++) {
    axes[k] = lt_grid_axis_of(h, k);
    assert_true(dims[k] >= 1 && dims[k] <= LT_GRID_MAX_AXIS_CELLS);
    assert_true(lt_grid_plane(&axes[k], 0) == axes[k].lo && lt_grid_plane(&axes[k], dims[k]) == axes[k].hi);
    for (int j = 0; j < dims[k]; j++) assert_true(lt_grid_plane(&axes[k], j) <= lt_grid_plane(&axes[k], j + 1));
  }
  assert_int_equal(h->dims.w, (int64_t)dims[0] * dims[1] * dims[2]);
  assert_int_equal(grid->cell_count, h->dims.w);

  /* Offsets: from 0 to ref_count, never decreasing; the statistics as recounted. */
  int64_t cells = grid->cell_count, empty = 0;
  int most = 0;
  assert_int_equal(grid->cell_begin[0], 0);
  for (int64_t c = 0; c < cells; c++) {
    int count = grid->cell_begin[c + 1] - grid->cell_begin[c];
    assert_true(count >= 0);
    empty += count == 0;
    most = count > most ? count : most;
    for (int i = grid->cell_begin[c] + 1; i < grid->cell_begin[c + 1]; i++)
      assert_true(grid->refs[i - 1] < grid->refs[i]);
  }
  assert_int_equal(grid->cell_begin[cells], grid->ref_count);
  assert_int_equal(grid->empty_cells, empty);
  assert_int_equal(grid->max_cell_refs, most);
  assert_int_equal(grid->bytes, 64 + 4 * (size_t)(cells + 1) + 4 * (size_t)grid->ref_count);

  /* Every reference where the triangle's box meets the cell, and as many as those cells. */
  int64_t *seen = calloc(n, sizeof *seen);
  assert_non_null(seen);
  for (int z = 0; z < dims[2]; z++)
    for (int y = 0; y < dims[1]; y++)
      for (int x = 0; x < dims[0]; x++) {
        int cell[3] = {x, y, z};
        lt_i32 c = lt_grid_cell_index(dims[0], dims[1], x, y, z);
        for (int i = grid->cell_begin[c]; i < grid->cell_begin[c + 1]; i++) {
          int prim = grid->refs[i];
          assert_true(prim >= 0 && (size_t)prim < n);
          float lo[3], hi[3];
          triangle_box(tris + 9 * (size_t)prim, lo, hi);
          for (int k = 0; k < 3; k++)
            assert_true(lt_grid_plane(&axes[k], cell[k]) <= hi[k] && lt_grid_plane(&axes[k], cell[k] + 1) >= lo[k]);
          seen[prim]++;
        }
      }
  for (size_t i = 0; i < n; i++) {
    float lo[3], hi[3];
    triangle_box(tris + 9 * i, lo, hi);
    int64_t want = 1;
    for (int k = 0; k < 3; k++) {
      int64_t meets = 0;
      for (int j = 0; j < dims[k]; j++)
        meets += lt_grid_plane(&axes[k], j) <= hi[k] && lt_grid_plane(&axes[k], j + 1) >= lo[k];
      want *= meets;
    }
    assert_true(want >= 1);
    assert_int_equal(seen[i], want);
  }
  free(seen);
}

static lt__grid build_checked(const lt_scene *scene, const lt__grid_config *config) {
  lt__grid grid;
  size_t n = lt_scene_triangle_count(scene);
  assert_int_equal(lt__grid_build(lt_scene_triangles(scene), n, config, &grid), LT_OK);
  check_grid(&grid, lt_scene_triangles(scene), n);
  return grid;
}

/* Builds, checks and traces; on a closed mesh (rays from inside) nothing may miss. */
static totals check_scene(const char *what, const lt_scene *scene, const lt__grid_config *config, const lt_ray *rays,
                          size_t n, int flags, int closed) {
  assert_non_null(scene);
  lt__grid grid = build_checked(scene, config);
  totals t = check_rays(what, scene, &grid, rays, n, flags);
  if (closed) {
    if (t.hits != n) fprintf(stderr, "%s: %zu of %zu rays leak\n", what, n - t.hits, n);
    assert_int_equal(t.hits, n);
  }
  fprintf(stderr,
          "%s: %zu triangles, %d x %d x %d cells, %.2f refs a triangle, %zu bytes; %zu rays (%zu hits) agree, "
          "%.1f cells and %.1f tests a ray\n",
          what, lt_scene_triangle_count(scene), grid.header.dims.x, grid.header.dims.y, grid.header.dims.z,
          (double)grid.ref_count / (double)lt_scene_triangle_count(scene), grid.bytes, n, t.hits, t.steps, t.tests);
  lt__grid_free(&grid);
  return t;
}

/* The resolution factor that gives `cells` cells along the longest axis of n triangles. */
static lt__grid_config config_for(size_t n, int cells) {
  lt__grid_config config = lt__grid_config_default();
  config.resolution_factor = (float)cells / (float)cbrt((double)n);
  return config;
}

static lt_ray *scene_rays(const lt_scene *scene, int size, size_t random, size_t *n) {
  *n = 2 * (size_t)size * size + random;
  lt_ray *rays = malloc(*n * sizeof *rays);
  assert_non_null(rays);
  lt_test_camera_rays(scene, "outer", size, size, rays);
  lt_test_camera_rays(scene, "close", size, size, rays + size * size);
  lt_test_random_rays(scene, 7, random, rays + 2 * size * size);
  return rays;
}

static size_t closed_mesh(const char *what, const lt_hc_mesh *mesh, const lt__grid_config *config, size_t n) {
  assert_non_null(mesh->scene);
  lt_ray *rays = malloc(n * sizeof *rays);
  assert_non_null(rays);
  assert_int_equal(lt_hc_closed_rays(mesh, 11, n, rays), n);
  check_scene(what, mesh->scene, config, rays, n, 0, 1);
  free(rays);
  return n;
}

/* ---- The build ---- */

/* Arguments are checked before anything is built; NULL config means the defaults; a failed
 * build leaves a zeroed grid that can be freed. */
static void grid_rejects_bad_arguments(void **state) {
  (void)state;
  const float tri[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  lt__grid grid;
  lt__grid_config config = lt__grid_config_default();
  assert_true(config.resolution_factor == 3.0f && config.max_cells == 1 << 24);
  assert_int_equal(lt__grid_build(tri, 0, &config, &grid), LT_ERROR_INVALID_ARGUMENT);
  assert_int_equal(lt__grid_build(NULL, 1, &config, &grid), LT_ERROR_INVALID_ARGUMENT);
  assert_int_equal(lt__grid_build(tri, 1, &config, NULL), LT_ERROR_INVALID_ARGUMENT);
  const float bad[3] = {NAN, INFINITY, -INFINITY};
  for (int b = 0; b < 3; b++) {
    float t[9];
    memcpy(t, tri, sizeof t);
    t[4] = bad[b];
    assert_int_equal(lt__grid_build(t, 1, &config, &grid), LT_ERROR_INVALID_ARGUMENT);
    assert_null(grid.cell_begin), assert_null(grid.refs);
    lt__grid_free(&grid);
  }
  const float factors[3] = {0.0f, -1.0f, NAN};
  for (int f = 0; f < 3; f++) {
    config = lt__grid_config_default(), config.resolution_factor = factors[f];
    assert_int_equal(lt__grid_build(tri, 1, &config, &grid), LT_ERROR_INVALID_ARGUMENT);
  }
  config = lt__grid_config_default(), config.max_cells = 0;
  assert_int_equal(lt__grid_build(tri, 1, &config, &grid), LT_ERROR_INVALID_ARGUMENT);
  assert_int_equal(lt__grid_build(tri, 1, NULL, &grid), LT_OK);
  check_grid(&grid, tri, 1);
  lt__grid_free(&grid);
  lt__grid_free(NULL);

  /* 200 copies of a triangle over 4096 x 4096 cells would need 3.4e9 references, more than
   * 32-bit offsets reach: refused up front, before any cell is counted. */
  enum { COPIES = 200 };
  float copies[9 * COPIES];
  for (int i = 0; i < COPIES; i++) memcpy(copies + 9 * i, tri, sizeof tri);
  config = lt__grid_config_default(), config.resolution_factor = 4096.0f / (float)cbrt((double)COPIES);
  assert_int_equal(lt__grid_build(copies, COPIES, &config, &grid), LT_ERROR_OUT_OF_MEMORY);
  assert_null(grid.cell_begin), assert_null(grid.refs);
  assert_int_equal(grid.ref_count, 0);
}

/* round(3 * cbrt(N)) cells along the longest axis, near-cubical cells, one cell on a flat
 * axis, and the cap on all cells shrinking every axis alike. */
static void grid_resolution_follows_the_thesis(void **state) {
  (void)state;
  /* A box 8 x 4 x 2 made of its 12 triangles, repeated so that N = 12 * 250 = 3000. */
  enum { REPEAT = 250 };
  static const float corner[8][3] = {{0, 0, 0}, {8, 0, 0}, {0, 4, 0}, {8, 4, 0},
                                     {0, 0, 2}, {8, 0, 2}, {0, 4, 2}, {8, 4, 2}};
  static const int faces[12][3] = {{0, 1, 3}, {0, 3, 2}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                                   {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 3, 7}, {1, 7, 5}};
  size_t n = 12 * REPEAT;
  float *tris = malloc(9 * n * sizeof *tris);
  assert_non_null(tris);
  for (size_t i = 0; i < n; i++)
    for (int v = 0; v < 3; v++) memcpy(tris + 9 * i + 3 * v, corner[faces[i % 12][v]], 3 * sizeof(float));
  lt__grid grid;
  assert_int_equal(lt__grid_build(tris, n, NULL, &grid), LT_OK);
  int along = (int)floor(3.0 * cbrt((double)n) + 0.5); /* 43 */
  assert_int_equal(grid.header.dims.x, along);
  assert_int_equal(grid.header.dims.y, (int)floor(along / 2.0 + 0.5));
  assert_int_equal(grid.header.dims.z, (int)floor(along / 4.0 + 0.5));
  assert_true(fabsf(grid.header.size.x - 8.0f / along) < 1e-6f);
  check_grid(&grid, tris, n);
  lt__grid_free(&grid);

  /* A cap of 1000 cells: every axis shrinks by about the same ratio, and all fit. */
  lt__grid_config config = lt__grid_config_default();
  config.max_cells = 1000;
  assert_int_equal(lt__grid_build(tris, n, &config, &grid), LT_OK);
  assert_true(grid.cell_count <= 1000 && grid.cell_count >= 500);
  assert_true(grid.header.dims.x >= 3 * grid.header.dims.z && grid.header.dims.x <= 5 * grid.header.dims.z);
  check_grid(&grid, tris, n);
  lt__grid_free(&grid);
  config.max_cells = 1;
  assert_int_equal(lt__grid_build(tris, n, &config, &grid), LT_OK);
  assert_int_equal(grid.cell_count, 1);
  assert_int_equal(grid.ref_count, (int64_t)n);
  lt__grid_free(&grid);

  /* Flat in z: one cell there, of size 0. */
  for (size_t i = 0; i < 9 * n; i += 3) tris[i + 2] = 1.5f;
  assert_int_equal(lt__grid_build(tris, n, NULL, &grid), LT_OK);
  assert_int_equal(grid.header.dims.z, 1);
  assert_true(grid.header.size.z == 0.0f && grid.header.lo.z == 1.5f && grid.header.hi.z == 1.5f);
  assert_int_equal(grid.header.dims.x, along);
  check_grid(&grid, tris, n);
  lt__grid_free(&grid);
  free(tris);
}

/* The statistics and references of generated scenes (check_grid), and how much memory a
 * reference per cell costs against one copy of the triangles. */
static void grid_statistics_are_consistent(void **state) {
  (void)state;
  static const char *const specs[] = {"cornell", "sphere:3", "hairball:300", "house"};
  for (size_t s = 0; s < sizeof specs / sizeof specs[0]; s++) {
    lt_scene *scene;
    assert_int_equal(lt_scene_load(specs[s], &scene), LT_OK);
    lt__grid grid = build_checked(scene, NULL);
    size_t n = lt_scene_triangle_count(scene);
    assert_true(grid.ref_count >= (int64_t)n);
    assert_true(grid.empty_cells < grid.cell_count);
    fprintf(stderr, "%s: %zu triangles, %lld cells (%lld empty), %lld refs, at most %d in a cell, %zu bytes\n",
            specs[s], n, (long long)grid.cell_count, (long long)grid.empty_cells, (long long)grid.ref_count,
            grid.max_cell_refs, grid.bytes);
    lt__grid_free(&grid);
    lt_scene_destroy(scene);
  }
}

/* ---- Generated scenes ---- */

/* A room, a closed sphere, long thin strands, a house and a big stadium: camera rays from
 * outside and from close up, and random rays of which many start inside the grid. */
static void grid_matches_reference_on_generators(void **state) {
  (void)state;
  static const struct {
    const char *spec;
    int camera;
    size_t random;
  } scenes[] = {{"cornell", 32, 2000},
                {"sphere:3", 32, 2000},
                {"hairball:300", 32, 1000},
                {"house", 24, 800},
                {"teapot-stadium", 12, 200}};
  for (size_t s = 0; s < sizeof scenes / sizeof scenes[0]; s++) {
    lt_scene *scene;
    assert_int_equal(lt_scene_load(scenes[s].spec, &scene), LT_OK);
    size_t n;
    lt_ray *rays = scene_rays(scene, scenes[s].camera, scenes[s].random, &n);
    totals t = check_scene(scenes[s].spec, scene, NULL, rays, n, 0, 0);
    assert_true(t.hits > n / 10); /* the rays must actually meet the scene */
    free(rays);
    lt_scene_destroy(scene);
  }
}

/* Far fewer cells than triangles (one cell, then a coarse grid) and far more (cells much
 * smaller than triangles, which then sit in many cells): the same answers. */
static void grid_matches_reference_at_any_resolution(void **state) {
  (void)state;
  lt_scene *scene;
  assert_int_equal(lt_scene_load("sphere:3", &scene), LT_OK);
  size_t n;
  lt_ray *rays = scene_rays(scene, 24, 1000, &n);
  const float factors[] = {0.01f, 0.5f, 3.0f, 12.0f, 24.0f};
  for (size_t f = 0; f < sizeof factors / sizeof factors[0]; f++) {
    lt__grid_config config = lt__grid_config_default();
    config.resolution_factor = factors[f];
    char what[64];
    snprintf(what, sizeof what, "sphere:3 at resolution factor %g", factors[f]);
    check_scene(what, scene, &config, rays, n, 0, 0);
  }
  free(rays);
  lt_scene_destroy(scene);
}

/* ---- Closed meshes ---- */

/* Icospheres, a torus, and cubes of shared edges whose edges lie on cell planes: rays from
 * inside aimed at every vertex and edge midpoint, and in random directions, never escape. */
static void grid_closed_meshes_never_leak(void **state) {
  (void)state;
  for (int level = 0; level <= 4; level++) {
    char what[32];
    snprintf(what, sizeof what, "sphere:%d", level);
    lt_hc_mesh sphere = lt_hc_sphere(level, 3);
    closed_mesh(what, &sphere, NULL, 3000);
    lt_hc_free(&sphere);
  }
  lt_hc_mesh torus = lt_hc_torus(48, 24), cube = lt_hc_cube(16, 5);
  closed_mesh("torus 48x24", &torus, NULL, 3000);
  closed_mesh("cube of shared edges 16x16", &cube, NULL, 3000);
  size_t n = lt_scene_triangle_count(cube.scene);
  lt__grid_config unit = config_for(n, 16), half = config_for(n, 32);
  closed_mesh("cube 16x16, planes on every edge", &cube, &unit, 3000);
  closed_mesh("cube 16x16, planes on every edge and between", &cube, &half, 3000);
  lt_hc_free(&torus), lt_hc_free(&cube);
}

/* The case Embree 3.13.5 lets rays escape from: rays from the centre of a closed icosphere
 * through its vertices exactly, and from points inside towards them. */
static void grid_sphere_vertex_rays_never_leak(void **state) {
  (void)state;
  lt_hc_mesh sphere = lt_hc_sphere(5, 7);
  assert_non_null(sphere.scene);
  float *verts;
  size_t nv = lt_hc_vertices(sphere.scene, &verts), n = 2000;
  lt_ray *rays = malloc(n * sizeof *rays);
  lt_hc_rays_to_targets(&sphere, verts, nv, n, rays);
  for (size_t i = 0; i < n; i += 2) {
    for (int k = 0; k < 3; k++) rays[i].org[k] = 0.0f, rays[i].dir[k] = verts[3 * ((i * 37) % nv) + k];
  }
  check_scene("sphere:5 vertex rays", sphere.scene, NULL, rays, n, 0, 1);
  free(verts), free(rays);
  lt_hc_free(&sphere);
}

/* ---- Rays on cell boundaries, along axes, nearly parallel, from far away ---- */

/* Axis-aligned and diagonal rays from integer points inside a cube whose faces' grid lines
 * are cell planes: every zero component as +0 and as -0, all giving the same answers. */
static void grid_zero_and_negative_zero_direction_components(void **state) {
  (void)state;
  lt_hc_mesh cube = lt_hc_cube(8, 9);
  size_t n = 0, max = 8192;
  lt_ray *rays = malloc(max * sizeof *rays);
  for (size_t p = 0; p < cube.inside_count; p++)
    for (int d = 0; d < 27 && n + 8 <= max; d++) {
      int comp[3] = {d % 3 - 1, d / 3 % 3 - 1, d / 9 - 1};
      if (!comp[0] && !comp[1] && !comp[2]) continue;
      for (int signs = 0; signs < 8; signs++) {
        lt_ray *r = &rays[n++];
        *r = (lt_ray){{cube.inside[3 * p], cube.inside[3 * p + 1], cube.inside[3 * p + 2]}, 0.0f, {0, 0, 0}, INFINITY};
        for (int k = 0; k < 3; k++) r->dir[k] = comp[k] ? (float)comp[k] : ((signs >> k) & 1 ? -0.0f : 0.0f);
      }
    }
  size_t tris = lt_scene_triangle_count(cube.scene);
  lt__grid_config configs[3] = {lt__grid_config_default(), config_for(tris, 8), config_for(tris, 16)};
  const char *names[3] = {"+0 and -0 in the cube, default grid", "+0 and -0 in the cube, planes on the edges",
                          "+0 and -0 in the cube, planes on and between the edges"};
  for (int c = 0; c < 3; c++) check_scene(names[c], cube.scene, &configs[c], rays, n, 0, 1);

  /* The sign of a zero component changes nothing. */
  lt__grid grid = build_checked(cube.scene, &configs[1]);
  lt_hit *hits = malloc(n * sizeof *hits);
  lt_trace_counters counters = {0, 0};
  trace_grid(&grid, lt_scene_triangles(cube.scene), rays, n, 0, hits, &counters);
  for (size_t i = 0; i < n; i += 8)
    for (int s = 1; s < 8; s++) assert_memory_equal(&hits[i + s], &hits[i], sizeof hits[i]);
  lt__grid_free(&grid);
  free(hits), free(rays);
  lt_hc_free(&cube);
}

/* A corner of cells: plane indices i, j, l, as a point. */
static void grid_point(const lt_grid_axis axes[3], const int idx[3], float p[3]) {
  for (int k = 0; k < 3; k++) p[k] = lt_grid_plane(&axes[k], idx[k]);
}

/* Rays that run exactly along grid lines and inside cell planes, start on grid corners, aim
 * exactly at grid corners from inside and outside, and cross corners diagonally. */
static size_t boundary_rays(const lt__grid *grid, uint64_t seed, size_t max, lt_ray *out) {
  lt_grid_axis axes[3] = {lt_grid_axis_of(&grid->header, 0), lt_grid_axis_of(&grid->header, 1),
                          lt_grid_axis_of(&grid->header, 2)};
  float lo[3], hi[3];
  for (int k = 0; k < 3; k++) lo[k] = axes[k].lo, hi[k] = axes[k].hi;
  size_t n = 0;
  while (n < max) {
    int idx[3];
    for (int k = 0; k < 3; k++) idx[k] = (int)(lt__splitmix_unit(&seed) * (axes[k].n + 1)) % (axes[k].n + 1);
    float p[3], q[3];
    grid_point(axes, idx, p);
    for (int k = 0; k < 3; k++) {
      float pad = 0.2f * (hi[k] - lo[k]);
      q[k] = lo[k] - pad + lt__splitmix_unit(&seed) * (hi[k] - lo[k] + 2 * pad);
    }
    int kind = (int)(n % 6), axis = (int)(lt__splitmix_unit(&seed) * 3) % 3;
    lt_ray *r = &out[n++];
    *r = (lt_ray){{p[0], p[1], p[2]}, 0.0f, {0, 0, 0}, INFINITY};
    if (kind == 0) {
      /* Along a grid line, either way, the other components +0 or -0. */
      for (int k = 0; k < 3; k++) r->dir[k] = lt__splitmix_unit(&seed) < 0.5f ? 0.0f : -0.0f;
      r->dir[axis] = lt__splitmix_unit(&seed) < 0.5f ? 1.0f : -1.0f;
    } else if (kind == 1) {
      /* Inside one cell plane, from anywhere in it. */
      for (int k = 0; k < 3; k++) r->org[k] = k == axis ? p[k] : q[k], r->dir[k] = 2 * lt__splitmix_unit(&seed) - 1;
      r->dir[axis] = lt__splitmix_unit(&seed) < 0.5f ? 0.0f : -0.0f;
    } else if (kind == 2) {
      /* From anywhere, exactly at a grid corner. */
      for (int k = 0; k < 3; k++) r->org[k] = q[k], r->dir[k] = p[k] - q[k];
    } else if (kind == 3) {
      /* From a grid corner through the next corners (as exactly as floats allow). */
      for (int k = 0; k < 3; k++)
        r->dir[k] = (lt__splitmix_unit(&seed) < 0.5f ? -1.0f : 1.0f) * (axes[k].size > 0 ? axes[k].size : 1.0f) *
                    (float)(1 + (int)(lt__splitmix_unit(&seed) * 2));
    } else if (kind == 4) {
      /* Along a grid line from outside the grid. */
      for (int k = 0; k < 3; k++) r->dir[k] = 0.0f;
      r->org[axis] = lt__splitmix_unit(&seed) < 0.5f ? lo[axis] - 0.5f * (hi[axis] - lo[axis]) - 1.0f
                                                     : hi[axis] + 0.5f * (hi[axis] - lo[axis]) + 1.0f;
      r->dir[axis] = p[axis] - r->org[axis];
    } else {
      /* From a grid corner in any direction. */
      for (int k = 0; k < 3; k++) r->dir[k] = 2 * lt__splitmix_unit(&seed) - 1;
    }
  }
  return n;
}

static void boundary_case(const char *what, const lt_scene *scene, const lt__grid_config *config, size_t n) {
  lt__grid grid = build_checked(scene, config);
  lt_ray *rays = malloc(n * sizeof *rays);
  assert_non_null(rays);
  boundary_rays(&grid, 3, n, rays);
  totals t = check_rays(what, scene, &grid, rays, n, 0);
  fprintf(stderr, "%s: %zu rays (%zu hits) agree, %.1f cells a ray\n", what, n, t.hits, t.steps);
  assert_true(t.hits > n / 10);
  lt__grid_free(&grid);
  free(rays);
}

static void grid_rays_along_cell_boundaries(void **state) {
  (void)state;
  lt_hc_mesh cube = lt_hc_cube(8, 13), sphere = lt_hc_sphere(3, 17);
  size_t tris = lt_scene_triangle_count(cube.scene);
  lt__grid_config on_edges = config_for(tris, 8), between = config_for(tris, 16);
  boundary_case("boundary rays, cube, planes on the edges", cube.scene, &on_edges, 6000);
  boundary_case("boundary rays, cube, planes on and between the edges", cube.scene, &between, 6000);
  boundary_case("boundary rays, cube, default grid", cube.scene, NULL, 6000);
  boundary_case("boundary rays, sphere:3", sphere.scene, NULL, 6000);
  lt_scene *house;
  assert_int_equal(lt_scene_load("cornell", &house), LT_OK);
  boundary_case("boundary rays, cornell", house, NULL, 6000);
  lt_scene_destroy(house);
  lt_hc_free(&cube), lt_hc_free(&sphere);
}

/* Direction components so small that 1/d overflows or is huge (1e-30, subnormal 1e-40), or so
 * large that t is tiny: crossing distances become infinite or collapse, and still the hits
 * are the reference's. */
static void grid_nearly_parallel_and_extreme_directions(void **state) {
  (void)state;
  lt_scene *scene;
  assert_int_equal(lt_scene_load("sphere:3", &scene), LT_OK);
  const float small[4] = {1e-30f, -1e-30f, 1e-40f, -3e-39f};
  size_t n = 0, max = 4000;
  lt_ray *rays = malloc(max * sizeof *rays);
  uint64_t seed = 29;
  while (n < max) {
    lt_ray *r = &rays[n];
    for (int k = 0; k < 3; k++) r->org[k] = 2.4f * lt__splitmix_unit(&seed) - 1.2f;
    int main_axis = (int)(n % 3), kind = (int)(n / 3 % 4);
    for (int k = 0; k < 3; k++) r->dir[k] = small[(n + 7 * k) % 4];
    r->dir[main_axis] = lt__splitmix_unit(&seed) < 0.5f ? 1.0f : -1.0f;
    if (kind == 1) r->dir[(main_axis + 1) % 3] = 2 * lt__splitmix_unit(&seed) - 1;
    if (kind == 2)
      for (int k = 0; k < 3; k++) r->dir[k] *= 1e30f;
    if (kind == 3) r->org[main_axis] = r->dir[main_axis] > 0 ? -5.0f : 5.0f;
    r->tmin = 0.0f, r->tmax = INFINITY;
    n++;
  }
  totals t = check_scene("nearly parallel and extreme directions, sphere:3", scene, NULL, rays, n, 0, 0);
  assert_true(t.hits > n / 4);
  free(rays);
  lt_scene_destroy(scene);
}

/* Rays from 1e4 and 1e6 away at a unit sphere's vertices: crossing distances are a million
 * times the cells' size, and the rounding bound a sizeable part of a cell. */
static void grid_rays_from_far_away(void **state) {
  (void)state;
  lt_hc_mesh sphere = lt_hc_sphere(3, 37);
  float *verts;
  size_t nv = lt_hc_vertices(sphere.scene, &verts), n = 4000;
  lt_ray *rays = malloc(n * sizeof *rays);
  uint64_t seed = 41;
  for (size_t i = 0; i < n; i++) {
    float d[3], len = 0, dist = i % 2 ? 1e6f : 1e4f;
    for (int k = 0; k < 3; k++) d[k] = 2 * lt__splitmix_unit(&seed) - 1, len += d[k] * d[k];
    const float *p = verts + 3 * ((i * 13) % nv);
    for (int k = 0; k < 3; k++) rays[i].org[k] = dist * d[k] / sqrtf(len);
    for (int k = 0; k < 3; k++) rays[i].dir[k] = p[k] - rays[i].org[k];
    if (i % 4 == 3) rays[i].dir[(int)(i % 3)] = 0.0f; /* and parallel to an axis, just past it */
    rays[i].tmin = 0.0f, rays[i].tmax = INFINITY;
  }
  totals t = check_scene("rays from 1e4 and 1e6 away at the vertices, sphere:3", sphere.scene, NULL, rays, n, 0, 0);
  assert_true(t.hits > n / 4);
  free(verts), free(rays);
  lt_hc_free(&sphere);
}

/* ---- Degenerate scenes ---- */

/* Triangles all in the plane z = 0.25 (and a wall x = -1): the grid has one cell of zero size
 * there; rays from above and below, grazing rays in the plane, rays along it with dz = +0 or
 * -0, and rays through the plane exactly at triangle vertices. */
static void grid_flat_scene(void **state) {
  (void)state;
  for (int wall = 0; wall < 2; wall++) {
    enum { TRIS = 400 };
    float tris[9 * TRIS];
    uint64_t seed = 43;
    int flat = wall ? 0 : 2;
    for (int i = 0; i < TRIS; i++) {
      /* Corners on a 1/16 grid, so that neighbours often share vertices and edges exactly. */
      float centre[3];
      for (int k = 0; k < 3; k++) centre[k] = floorf(64 * lt__splitmix_unit(&seed)) / 16 - 2;
      for (int v = 0; v < 3; v++)
        for (int k = 0; k < 3; k++)
          tris[9 * i + 3 * v + k] =
              k == flat ? (wall ? -1.0f : 0.25f) : centre[k] + floorf(8 * lt__splitmix_unit(&seed)) / 16 - 0.25f;
    }
    lt_scene *scene;
    assert_int_equal(lt_scene_from_triangles(tris, TRIS, &scene), LT_OK);
    size_t n = 3000;
    lt_ray *rays = malloc(n * sizeof *rays);
    for (size_t i = 0; i < n; i++) {
      lt_ray *r = &rays[i];
      const float *target = tris + 9 * (i % TRIS) + 3 * (i / TRIS % 3);
      for (int k = 0; k < 3; k++) r->org[k] = 6 * lt__splitmix_unit(&seed) - 3;
      int kind = (int)(i % 4);
      if (kind == 0) /* exactly at a vertex, from either side */
        for (int k = 0; k < 3; k++) r->dir[k] = target[k] - r->org[k];
      if (kind == 1) /* random */
        for (int k = 0; k < 3; k++) r->dir[k] = 2 * lt__splitmix_unit(&seed) - 1;
      if (kind >= 2) { /* in the plane, along it */
        r->org[flat] = target[flat];
        for (int k = 0; k < 3; k++) r->dir[k] = 2 * lt__splitmix_unit(&seed) - 1;
        r->dir[flat] = kind == 2 ? 0.0f : -0.0f;
      }
      r->tmin = 0.0f, r->tmax = INFINITY;
    }
    lt__grid grid = build_checked(scene, NULL);
    int dims[3] = {grid.header.dims.x, grid.header.dims.y, grid.header.dims.z};
    assert_int_equal(dims[flat], 1);
    lt__grid_free(&grid);
    totals t = check_scene(wall ? "flat scene, a wall at x = -1" : "flat scene, a floor at z = 0.25", scene, NULL, rays,
                           n, 0, 0);
    assert_true(t.hits > n / 8);
    free(rays);
    lt_scene_destroy(scene);
  }
}

/* One triangle: a grid of one cell in the flat axis; hits at its vertices, edges and inside,
 * misses beside it, and the answer bit for bit the reference's. */
static void grid_single_triangle(void **state) {
  (void)state;
  const float tri[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  lt_scene *scene;
  assert_int_equal(lt_scene_from_triangles(tri, 1, &scene), LT_OK);
  lt__grid grid = build_checked(scene, NULL);
  assert_int_equal(grid.cell_count, 3 * 3 * 1); /* round(3 * cbrt(1)) = 3 along x and y */
  lt_ray rays[8] = {{{0.25f, 0.25f, -1}, 0, {0, 0, 1}, INFINITY}, {{2, 2, -1}, 0, {0, 0, 1}, INFINITY},
                    {{0, 0, 1}, 0, {-0.0f, 0, -1}, INFINITY},     {{0.5f, 0.5f, 1}, 0, {0, -0.0f, -2}, INFINITY},
                    {{-1, 0.5f, 0}, 0, {1, 0, 0}, INFINITY},      {{0.25f, 0.25f, -1}, 0, {0, 0, 1}, 0.5f},
                    {{0.25f, 0.25f, 1}, 0, {0, 0, -1}, 1.0f},     {{0.25f, 0.25f, 1}, 1.0f, {0, 0, -1}, 1.0f}};
  lt_hit hits[8];
  lt_trace_counters counters = {0, 0};
  trace_grid(&grid, tri, rays, 8, 0, hits, &counters);
  assert_int_equal(hits[0].prim, 0);
  assert_true(hits[0].t == 1.0f);
  assert_int_equal(hits[1].prim, -1);
  assert_int_equal(hits[5].prim, -1); /* ends before the triangle */
  assert_int_equal(hits[6].prim, 0);  /* ends exactly on it */
  assert_int_equal(hits[7].prim, 0);  /* starts and ends exactly on it */
  totals t = check_rays("single triangle", scene, &grid, rays, 8, 0);
  assert_true(t.hits >= 4);
  lt__grid_free(&grid);
  lt_scene_destroy(scene);
}

/* Each triangle of sphere:2 repeated 40 times, interleaved, odd copies with rotated vertices:
 * the closest hit is one of the two lowest copies, exactly the reference's. */
static void grid_coincident_triangles_lowest_number_wins(void **state) {
  (void)state;
  enum { COPIES = 40 };
  lt_scene *sphere;
  assert_int_equal(lt_scene_load("sphere:2", &sphere), LT_OK);
  size_t base = lt_scene_triangle_count(sphere), count = base * COPIES;
  const float *src = lt_scene_triangles(sphere);
  float *tris = malloc(9 * count * sizeof *tris);
  for (size_t c = 0; c < COPIES; c++)
    for (size_t i = 0; i < base; i++) {
      int rot = (int)(c % 2) * (1 + (int)(i % 2));
      for (int v = 0; v < 3; v++) memcpy(tris + 9 * (c * base + i) + 3 * v, src + 9 * i + 3 * ((v + rot) % 3), 12);
    }
  lt_scene *scene;
  assert_int_equal(lt_scene_from_triangles(tris, count, &scene), LT_OK);
  size_t n = 1500;
  lt_ray *rays = malloc(n * sizeof *rays);
  lt_test_random_rays(scene, 41, n, rays);
  check_scene("40 coincident copies of every triangle", scene, NULL, rays, n, 0, 0);

  lt__grid grid = build_checked(scene, NULL);
  lt_hit *hits = malloc(n * sizeof *hits);
  lt_trace_counters counters = {0, 0};
  trace_grid(&grid, tris, rays, n, 0, hits, &counters);
  size_t hit = 0;
  for (size_t i = 0; i < n; i++) {
    if (hits[i].prim < 0) continue;
    hit++;
    assert_true((size_t)hits[i].prim < 2 * base);
  }
  assert_true(hit > n / 4);
  lt__grid_free(&grid);
  free(hits), free(rays), free(tris);
  lt_scene_destroy(scene), lt_scene_destroy(sphere);
}

/* ---- Huge and tiny coordinates ---- */

/* A sphere of radius 100 and the shared-edge cube (cell planes on its edges) moved by 1e6,
 * where floats are 1/16 apart: closed, no leak, the reference's answers. */
static void grid_huge_coordinates(void **state) {
  (void)state;
  lt_hc_mesh sphere = lt_hc_sphere(3, 23), cube = lt_hc_cube(8, 29);
  lt_hc_mesh far_sphere = lt_hc_transform(&sphere, 100.0f, 1e6f), far_cube = lt_hc_transform(&cube, 1.0f, 1e6f);
  lt__grid_config on_edges = config_for(lt_scene_triangle_count(cube.scene), 8);
  closed_mesh("sphere:3, radius 100, at 1e6", &far_sphere, NULL, 3000);
  closed_mesh("cube 8x8 at 1e6", &far_cube, NULL, 3000);
  closed_mesh("cube 8x8 at 1e6, planes on the edges", &far_cube, &on_edges, 3000);
  boundary_case("boundary rays, cube 8x8 at 1e6, planes on the edges", far_cube.scene, &on_edges, 3000);
  lt_hc_free(&sphere), lt_hc_free(&cube), lt_hc_free(&far_sphere), lt_hc_free(&far_cube);
}

/* Triangles spread over +-3e38, so that the grid's extent (6e38) overflows a float and so do
 * crossing distances, and over +-1e24. The triangle test's products overflow for coordinates
 * beyond about 1e19 from the ray's origin, so rays start near a triangle; at 3e38 floats are
 * 2e31 apart and no triangle that small can be hit at all, which checks that overflow gives
 * defined misses; at 1e24 the rays hit. Either way, the reference's answers. */
static void grid_coordinates_near_the_float_limit(void **state) {
  (void)state;
  enum { TRIS = 300 };
  const float spread[2] = {3e38f, 1e24f}, size[2] = {1e33f, 1e18f};
  for (int c = 0; c < 2; c++) {
    float tris[9 * TRIS];
    uint64_t seed = 71;
    for (int i = 0; i < TRIS; i++) {
      float centre[3];
      for (int k = 0; k < 3; k++) centre[k] = (2 * lt__splitmix_unit(&seed) - 1) * spread[c];
      for (int v = 0; v < 3; v++)
        for (int k = 0; k < 3; k++) tris[9 * i + 3 * v + k] = centre[k] + (2 * lt__splitmix_unit(&seed) - 1) * size[c];
    }
    lt_scene *scene;
    assert_int_equal(lt_scene_from_triangles(tris, TRIS, &scene), LT_OK);
    size_t n = 3000;
    lt_ray *rays = malloc(n * sizeof *rays);
    for (size_t i = 0; i < n; i++) {
      const float *t = tris + 9 * (i % TRIS);
      for (int k = 0; k < 3; k++) {
        float centroid = (t[k] + t[3 + k] + t[6 + k]) / 3;
        rays[i].org[k] = centroid + (2 * lt__splitmix_unit(&seed) - 1) * 4 * size[c];
        rays[i].dir[k] = i % 2 ? centroid - rays[i].org[k] : 2 * lt__splitmix_unit(&seed) - 1;
      }
      rays[i].tmin = 0.0f, rays[i].tmax = INFINITY;
    }
    char what[64];
    snprintf(what, sizeof what, "triangles and rays over +-%g", spread[c]);
    totals t = check_scene(what, scene, NULL, rays, n, 0, 0);
    if (c == 1) assert_true(t.hits > n / 10);
    free(rays);
    lt_scene_destroy(scene);
  }
}

/* A sphere whose edges are about 1e-6 long, at the origin and moved to 1 (where its vertices
 * snap to a grid 6e-8 apart): no leak, the reference's answers. */
static void grid_tiny_triangles(void **state) {
  (void)state;
  lt_hc_mesh sphere = lt_hc_sphere(3, 31);
  lt_hc_mesh tiny = lt_hc_transform(&sphere, 8e-6f, 0.0f), tiny_far = lt_hc_transform(&sphere, 8e-6f, 1.0f);
  closed_mesh("sphere:3 with 1e-6 edges", &tiny, NULL, 3000);
  closed_mesh("sphere:3 with 1e-6 edges at 1", &tiny_far, NULL, 3000);
  boundary_case("boundary rays, sphere:3 with 1e-6 edges at 1", tiny_far.scene, NULL, 3000);
  lt_hc_free(&sphere), lt_hc_free(&tiny), lt_hc_free(&tiny_far);
}

/* ---- Ray extents, invalid rays, the fast test ---- */

/* Segments that end exactly at the reference's hit, one float before it, or start exactly at
 * it or one float after: the stop rule (best strictly before the next boundary) and the
 * walk's start at tmin must both be exact. */
static void grid_rays_ending_and_starting_at_hits(void **state) {
  (void)state;
  lt_scene *scene;
  assert_int_equal(lt_scene_load("cornell", &scene), LT_OK);
  size_t m = 1500, n = 0;
  lt_ray *base = malloc(m * sizeof *base), *rays = malloc(5 * m * sizeof *rays);
  lt_hit *hits = malloc(m * sizeof *hits);
  lt_test_random_rays(scene, 53, m, base);
  assert_int_equal(lt_reference_trace(scene, base, m, LT_QUERY_CLOSEST, hits), LT_OK);
  uint64_t seed = 59;
  for (size_t i = 0; i < m; i++) {
    if (hits[i].prim < 0) continue;
    float t = hits[i].t;
    lt_ray r = base[i];
    rays[n] = r, rays[n++].tmax = t;
    rays[n] = r, rays[n++].tmax = nextafterf(t, 0.0f);
    rays[n] = r, rays[n++].tmin = t;
    rays[n] = r, rays[n++].tmin = nextafterf(t, INFINITY);
    rays[n] = r, rays[n].tmin = t * lt__splitmix_unit(&seed), rays[n++].tmax = t * (1 + lt__splitmix_unit(&seed));
  }
  totals tt = check_scene("segments ending and starting at hits, cornell", scene, NULL, rays, n, 0, 0);
  assert_true(tt.hits > n / 2);
  free(base), free(rays), free(hits);
  lt_scene_destroy(scene);
}

/* NaN or infinite components, zero directions of every sign, tmin > tmax: a defined miss. */
static void grid_invalid_rays_miss(void **state) {
  (void)state;
  lt_hc_mesh sphere = lt_hc_sphere(2, 43);
  lt_ray bad[64];
  size_t n = lt_hc_invalid_rays(bad, 64);
  lt__grid grid = build_checked(sphere.scene, NULL);
  lt_hit hits[64];
  for (int any = 0; any < 2; any++) {
    lt_trace_counters counters = {0, 0};
    trace_grid(&grid, lt_scene_triangles(sphere.scene), bad, n, any ? LT_QUERY_FLAG_ANY : 0, hits, &counters);
    for (size_t i = 0; i < n; i++) {
      assert_int_equal(hits[i].prim, -1);
      assert_true(isinf(hits[i].t) && hits[i].u == 0.0f && hits[i].v == 0.0f);
    }
    assert_int_equal(counters.traversal_steps, 0);
  }
  check_rays("invalid rays", sphere.scene, &grid, bad, n, 0);
  lt__grid_free(&grid);
  lt_hc_free(&sphere);
}

/* With the fast (Moller-Trumbore) test the grid still gives exactly the reference's answers
 * for that test, leaks included. */
static void grid_fast_test_agrees_with_its_reference(void **state) {
  (void)state;
  lt_hc_mesh sphere = lt_hc_sphere(3, 53), cube = lt_hc_cube(8, 59);
  size_t n = 3000;
  lt_ray *rays = malloc(n * sizeof *rays);
  lt__grid_config on_edges = config_for(lt_scene_triangle_count(cube.scene), 8);
  assert_int_equal(lt_hc_closed_rays(&sphere, 11, n, rays), n);
  check_scene("sphere:3, fast test", sphere.scene, NULL, rays, n, LT_QUERY_FLAG_FAST_TRIANGLES, 0);
  assert_int_equal(lt_hc_closed_rays(&cube, 11, n, rays), n);
  check_scene("cube 8x8, fast test, planes on the edges", cube.scene, &on_edges, rays, n, LT_QUERY_FLAG_FAST_TRIANGLES,
              0);
  free(rays);
  lt_hc_free(&sphere), lt_hc_free(&cube);
}

/* The grid earns its keep: on a closed sphere it tests a small part of the triangles a ray,
 * and any-hit stops sooner than closest-hit. */
static void grid_tests_few_triangles(void **state) {
  (void)state;
  lt_hc_mesh sphere = lt_hc_sphere(5, 61);
  size_t n = 2000, tris = lt_scene_triangle_count(sphere.scene);
  lt_ray *rays = malloc(n * sizeof *rays);
  lt_hc_random_rays(&sphere, 67, n, rays);
  lt__grid grid = build_checked(sphere.scene, NULL);
  lt_hit *hits = malloc(n * sizeof *hits);
  lt_trace_counters closest = {0, 0}, any = {0, 0};
  trace_grid(&grid, lt_scene_triangles(sphere.scene), rays, n, 0, hits, &closest);
  assert_int_equal(lt_hc_count_misses(hits, n), 0);
  trace_grid(&grid, lt_scene_triangles(sphere.scene), rays, n, LT_QUERY_FLAG_ANY, hits, &any);
  double tests = (double)closest.intersections / (double)n, steps = (double)closest.traversal_steps / (double)n;
  fprintf(stderr,
          "sphere:5 (%zu triangles), rays from inside: %.1f cells and %.1f tests a ray; any hit %.1f and %.1f\n", tris,
          steps, tests, (double)any.traversal_steps / (double)n, (double)any.intersections / (double)n);
  assert_true(tests < 0.01 * (double)tris);
  assert_true(any.intersections <= closest.intersections);
  lt__grid_free(&grid);
  free(rays), free(hits);
  lt_hc_free(&sphere);
}

/* The structure builds its grid through the task pool (the irregular grid's COUNT task): its
 * header, cell offsets and references equal the host build's, on both backends. */
static void grid_built_through_the_pool_equals_the_host_build(void **state) {
  (void)state;
  static const char *const scenes[] = {"house", "sphere:4", "hairball:300", "cornell", "teapot-stadium"};
  static const float densities[] = {3.0f, 0.5f, 7.0f};
  int backends = 1 + lt_test_opencl_available(), quick = getenv("LT_TEST_QUICK") != NULL;
  for (size_t s = 0; s < (quick ? 3u : sizeof scenes / sizeof scenes[0]); s++) {
    lt_scene *scene;
    assert_int_equal(lt_scene_load(scenes[s], &scene), LT_OK);
    size_t n = lt_scene_triangle_count(scene);
    for (int backend = 0; backend < backends; backend++)
      for (size_t d = 0; d < (quick ? 2u : sizeof densities / sizeof densities[0]); d++) {
        lt__grid_config config = lt__grid_config_default();
        config.resolution_factor = densities[d];
        lt__grid host;
        assert_int_equal(lt__grid_build(lt_scene_triangles(scene), n, &config, &host), LT_OK);
        lt_context *ctx;
        lt_context_config cc = {backend ? LT_DEVICE_OPENCL : LT_DEVICE_NATIVE, 0, 0, 0, 1};
        assert_int_equal(lt_context_create(&cc, &ctx), LT_OK);
        lt_structure_config sc = lt_structure_config_default(LT_STRUCTURE_GRID);
        sc.grid_density = densities[d];
        lt_structure *st;
        assert_int_equal(lt_structure_create(ctx, scene, &sc, NULL, &st), LT_OK);
        lt__irgrid *g = lt__uniform_grid_of(st);
        assert_non_null(g);
        assert_memory_equal(&g->fine, &host.header, sizeof host.header);
        lt__irgrid_arrays a;
        assert_int_equal(lt__irgrid_read(g, &a), LT_OK);
        assert_int_equal(g->top_count, host.cell_count);
        lt_i32 base = a.top_begin[0];
        for (int64_t c = 0; c <= host.cell_count; c++) assert_int_equal(a.top_begin[c] - base, host.cell_begin[c]);
        assert_memory_equal(a.refs + base, host.refs, (size_t)host.ref_count * sizeof(lt_i32));
        fprintf(stderr, "grid %s, density %g, %s: %lld cells and %lld references equal the host build's\n", scenes[s],
                (double)densities[d], lt_context_device_name(ctx), (long long)host.cell_count, (long long)host.ref_count);
        lt__irgrid_arrays_free(&a);
        lt_structure_destroy(st);
        lt_context_destroy(ctx);
        lt__grid_free(&host);
      }
    lt_scene_destroy(scene);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(grid_rejects_bad_arguments),
      cmocka_unit_test(grid_built_through_the_pool_equals_the_host_build),
      cmocka_unit_test(grid_resolution_follows_the_thesis),
      cmocka_unit_test(grid_statistics_are_consistent),
      cmocka_unit_test(grid_single_triangle),
      cmocka_unit_test(grid_flat_scene),
      cmocka_unit_test(grid_matches_reference_on_generators),
      cmocka_unit_test(grid_matches_reference_at_any_resolution),
      cmocka_unit_test(grid_closed_meshes_never_leak),
      cmocka_unit_test(grid_sphere_vertex_rays_never_leak),
      cmocka_unit_test(grid_zero_and_negative_zero_direction_components),
      cmocka_unit_test(grid_rays_along_cell_boundaries),
      cmocka_unit_test(grid_nearly_parallel_and_extreme_directions),
      cmocka_unit_test(grid_rays_from_far_away),
      cmocka_unit_test(grid_coincident_triangles_lowest_number_wins),
      cmocka_unit_test(grid_huge_coordinates),
      cmocka_unit_test(grid_coordinates_near_the_float_limit),
      cmocka_unit_test(grid_tiny_triangles),
      cmocka_unit_test(grid_rays_ending_and_starting_at_hits),
      cmocka_unit_test(grid_invalid_rays_miss),
      cmocka_unit_test(grid_fast_test_agrees_with_its_reference),
      cmocka_unit_test(grid_tests_few_triangles),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
