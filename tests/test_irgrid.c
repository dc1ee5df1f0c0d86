/* The irregular grid built through the task pool, fully and with top cells on demand: closest
 * hits equal the brute-force reference on every generator, mode, backend and launch shape, and
 * for every density, merge and expansion setting; any-hit agrees; every cell references
 * exactly the triangles whose boxes meet its (grown) box, and every voxel maps to a cell whose
 * box holds it; top cells built on demand equal the full build's; on-demand modes build a part
 * of the grid; the statistics say what was built. The hard-case suite (tests/test_robustness.c)
 * and fault injection (tests/test_faults.c) take the irregular grid from the registry like
 * every structure. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "runtime/irgrid_host.h"
#include "runtime/structure_internal.h"
#include "tests/hard_cases.h"
#include "tests/support.h"

#define CAMERA_SIZE 24
#define RANDOM_RAYS 512
#define RAY_COUNT (2 * CAMERA_SIZE * CAMERA_SIZE + RANDOM_RAYS)

static const char *const specs[] = {"house", "house-row:2", "house-grid:2x2", "hairball:300", "sphere:4", "cornell",
                                    "teapot-stadium"};

typedef lt_test_launch launch;

static lt_structure_config irgrid_config(lt_build_mode mode) {
  lt_structure_config c = lt_structure_config_default(LT_STRUCTURE_IRGRID);
  c.build = mode;
  return c;
}

/* Builds with config sc and one launch shape and traces; returns malloc'ed hits. */
static lt_hit *trace_with(const lt_scene *scene, const launch *l, const lt_structure_config *sc, const lt_ray *rays,
                          size_t n, int query, lt_stats *stats) {
  lt_hit *hits = lt_test_trace_with(scene, l, sc, rays, n, query, stats);
  assert_non_null(hits);
  return hits;
}

/* Camera rays from both cameras and random rays, with the reference's answers. */
static void make_rays(const lt_scene *scene, uint64_t seed, lt_ray *rays, lt_hit *ref) {
  lt_test_camera_rays(scene, "outer", CAMERA_SIZE, CAMERA_SIZE, rays);
  lt_test_camera_rays(scene, "close", CAMERA_SIZE, CAMERA_SIZE, rays + CAMERA_SIZE * CAMERA_SIZE);
  lt_test_random_rays(scene, seed, RANDOM_RAYS, rays + 2 * CAMERA_SIZE * CAMERA_SIZE);
  assert_int_equal(lt_reference_trace(scene, rays, RAY_COUNT, LT_QUERY_CLOSEST, ref), LT_OK);
}

/* Every generator, both cameras and random rays, every mode, launch shapes on both backends. */
static void irgrid_matches_reference_in_every_mode(void **state) {
  (void)state;
  int have_opencl = lt_test_opencl_available();
  const launch launches[] = {{LT_DEVICE_NATIVE, 2, 1}, {LT_DEVICE_NATIVE, 1, 1}, {LT_DEVICE_NATIVE, 3, 1},
                             {LT_DEVICE_OPENCL, 0, 1}, {LT_DEVICE_OPENCL, 2, 4}};
  /* Quick (the sanitizers): the small scenes only. */
  int quick = getenv("LT_TEST_QUICK") != NULL;
  size_t first = quick ? 3 : 0, end = quick ? 6 : sizeof specs / sizeof specs[0];
  for (size_t s = first; s < end; s++) {
    lt_scene *scene;
    assert_int_equal(lt_scene_load(specs[s], &scene), LT_OK);
    lt_ray *rays = malloc(RAY_COUNT * sizeof *rays);
    lt_hit *ref = malloc(RAY_COUNT * sizeof *ref);
    make_rays(scene, 11 + s, rays, ref);
    for (int mode = LT_BUILD_FULL; mode <= LT_BUILD_SPECULATIVE; mode++)
      for (size_t l = 0; l < sizeof launches / sizeof launches[0]; l++) {
        if (launches[l].device == LT_DEVICE_OPENCL && !have_opencl) continue;
        char what[128];
        snprintf(what, sizeof what, "irgrid %s %s launch %zu", specs[s], lt_build_mode_name((lt_build_mode)mode), l);
        lt_structure_config sc = irgrid_config((lt_build_mode)mode);
        lt_hit *hits = trace_with(scene, &launches[l], &sc, rays, RAY_COUNT, LT_QUERY_CLOSEST, NULL);
        assert_int_equal(lt_test_count_mismatches(what, hits, ref, RAY_COUNT), 0);
        lt_hit *any = trace_with(scene, &launches[l], &sc, rays, RAY_COUNT, LT_QUERY_ANY, NULL);
        assert_int_equal(lt_test_count_occlusion_mismatches(any, ref, RAY_COUNT), 0);
        free(hits), free(any);
      }
    fprintf(stderr, "irgrid %s: %zu triangles: every mode and launch matches the reference\n", specs[s],
            lt_scene_triangle_count(scene));
    free(rays), free(ref);
    lt_scene_destroy(scene);
  }
}

/* ---- The grid's arrays, checked on the host ---- */

typedef struct built {
  lt_context *ctx;
  lt_structure *s;
  lt__irgrid *g;
  lt__irgrid_arrays a;
} built;

static built build_grid(const lt_scene *scene, const lt_structure_config *sc, const lt_ray *rays, size_t n) {
  built b;
  lt_context_config config = {LT_DEVICE_NATIVE, 2, 2, 0, 1};
  assert_int_equal(lt_context_create(&config, &b.ctx), LT_OK);
  assert_int_equal(lt_structure_create(b.ctx, scene, sc, NULL, &b.s), LT_OK);
  if (n) {
    lt_hit *hits = malloc(n * sizeof *hits);
    assert_int_equal(lt_structure_trace(b.s, rays, n, LT_QUERY_CLOSEST, hits, NULL), LT_OK);
    free(hits);
  }
  b.g = lt__irgrid_of(b.s);
  assert_non_null(b.g);
  assert_int_equal(lt__irgrid_read(b.g, &b.a), LT_OK);
  return b;
}

static void built_free(built *b) {
  lt__irgrid_arrays_free(&b->a);
  lt_structure_destroy(b->s);
  lt_context_destroy(b->ctx);
}

/* The fine voxels triangle i's box meets (inclusive), decided as the builder decides. */
static void fine_range(const lt_grid_header *h, const float *t, int lo[3], int hi[3]) {
  for (int k = 0; k < 3; k++) {
    float a = t[k] < t[3 + k] ? t[k] : t[3 + k], c = t[k] > t[3 + k] ? t[k] : t[3 + k];
    a = t[6 + k] < a ? t[6 + k] : a, c = t[6 + k] > c ? t[6 + k] : c;
    lt_grid_axis ax = lt_grid_axis_of(h, k);
    lo[k] = lt_grid_first_cell(&ax, a), hi[k] = lt_grid_last_cell(&ax, c);
  }
}

static int meets(const int lo[3], const int hi[3], const lt_i32 blo[3], const lt_i32 bhi[3]) {
  for (int k = 0; k < 3; k++)
    if (lo[k] >= bhi[k] || hi[k] < blo[k]) return 0;
  return 1;
}

/* Checks every built top cell: each voxel's cell holds the voxel; each cell's references are
 * ascending and exactly the triangles that meet its box. Returns the cells checked. */
static int check_cells(const lt_scene *scene, const built *b) {
  const lt_grid_header *h = &b->g->fine;
  const float *tris = lt_scene_triangles(scene);
  size_t n = lt_scene_triangle_count(scene);
  int (*range)[6] = malloc(n * sizeof *range);
  for (size_t i = 0; i < n; i++) fine_range(h, tris + 9 * i, range[i], range[i] + 3);
  char *seen = calloc((size_t)b->a.cell_count + 1, 1);
  int checked = 0, shift = LT_IRG_MAX_LEVEL;
  for (int t = 0; t < b->g->top_count; t++) {
    lt_i32 entry = b->a.top_map[t];
    if (entry < 0) continue;
    /* Fine voxel by fine voxel, through the lookup: a compacted sub-map may be an octree. */
    int side = 1 << shift;
    int top[3] = {t % b->g->top_dims[0], (t / b->g->top_dims[0]) % b->g->top_dims[1],
                  t / (b->g->top_dims[0] * b->g->top_dims[1])};
    for (int s = 0; s < side * side * side; s++) {
      int v[3] = {(top[0] << shift) + s % side, (top[1] << shift) + (s / side) % side,
                  (top[2] << shift) + s / (side * side)};
      lt_i32 id = lt_irg_lookup(b->a.top_map, b->a.sub_maps, 0, h->dims, shift, v[0], v[1], v[2]);
      assert_true(id >= 0 && id < b->a.cell_count);
      const lt_irg_cell *cell = &b->a.cells[id];
      for (int k = 0; k < 3; k++) assert_true(cell->lo[k] <= v[k] && v[k] < cell->hi[k]);
      if (seen[id]) continue;
      seen[id] = 1, checked++;
      assert_true(cell->begin >= 0 && cell->begin <= cell->end && cell->end <= b->a.ref_count);
      lt_i32 at = cell->begin;
      for (size_t i = 0; i < n; i++) {
        if (!meets(range[i], range[i] + 3, cell->lo, cell->hi)) continue;
        if (at >= cell->end || b->a.refs[at] != (lt_i32)i)
          fail_msg("cell %d (top %d): triangle %zu meets its box but is not its next reference", id, t, i);
        at++;
      }
      assert_int_equal(at, cell->end);
    }
  }
  free(range), free(seen);
  return checked;
}

typedef struct setting {
  const char *what;
  float top_density, cell_density;
  int merge, passes;
} setting;

static const setting settings[] = {
    {"defaults", 0, 0, 0, 0},
    {"merges within top cells", 0, 0, LT_IRGRID_MERGE_TOP, 0},
    {"two-level (no merge, no expansion)", 0, 0, LT_IRGRID_MERGE_OFF, LT_IRGRID_PASSES(0)},
    {"merge, no expansion", 0, 0, 0, LT_IRGRID_PASSES(0)},
    {"8 expansion passes", 0, 0, 0, LT_IRGRID_PASSES(8)},
    {"coarse: lambda1 0.012, lambda2 0.24", 0.012f, 0.24f, 0, 0},
    {"fine: lambda2 24", 0, 24.0f, 0, 0},
};
#define SETTINGS (sizeof settings / sizeof settings[0])

static lt_structure_config config_of(const setting *s, lt_build_mode mode) {
  lt_structure_config c = irgrid_config(mode);
  if (s->top_density > 0) c.irgrid_top_density = s->top_density;
  if (s->cell_density > 0) c.irgrid_cell_density = s->cell_density;
  if (s->merge) c.irgrid_merge = s->merge;
  if (s->passes) c.irgrid_expansion_passes = s->passes;
  return c;
}

static void irgrid_cells_reference_exactly_what_meets_them(void **state) {
  (void)state;
  static const char *const scenes[] = {"sphere:3", "cornell", "hairball:200"};
  int quick = getenv("LT_TEST_QUICK") != NULL;
  for (size_t s = 0; s < (quick ? 2u : sizeof scenes / sizeof scenes[0]); s++) {
    lt_scene *scene;
    assert_int_equal(lt_scene_load(scenes[s], &scene), LT_OK);
    for (size_t v = 0; v < (quick ? 3u : SETTINGS); v++) {
      lt_structure_config sc = config_of(&settings[v], LT_BUILD_FULL);
      built b = build_grid(scene, &sc, NULL, 0);
      int cells = check_cells(scene, &b);
      fprintf(stderr, "irgrid %s, %s: %d top cells, %d cells hold exactly what meets them\n", scenes[s],
              settings[v].what, b.g->top_count, cells);
      assert_true(cells >= b.g->top_count);
      /* A full build is compacted: every cell is some voxel's, the lists are packed (these fine
       * grids fit 16-byte cells) and read back end to end, and a cell whose list an earlier
       * cell holds already shares it. */
      assert_int_equal(cells, b.a.cell_count);
      assert_true(b.g->compacted && b.g->narrow);
      assert_int_equal(b.g->cells.bytes, (size_t)b.a.cell_count * sizeof(lt_irg_cell16));
      int at = 0;
      for (int c = 0; c < b.a.cell_count; c++) {
        const lt_irg_cell *cell = &b.a.cells[c];
        if (cell->begin == at) {
          at = cell->end;
          continue;
        }
        int d = 0;
        while (d < c && (b.a.cells[d].begin != cell->begin || b.a.cells[d].end != cell->end)) d++;
        if (d == c && cell->end > cell->begin) fail_msg("cell %d's list is neither next nor an earlier cell's", c);
      }
      assert_int_equal(at, b.a.ref_count);
      built_free(&b);
    }
    lt_scene_destroy(scene);
  }
}

/* Packed lists read back exactly through the traversal's reader: the empty list, triangle 0
 * alone, runs longer than a token holds, runs of exactly a token, steps that take one to four
 * bytes, the largest triangle number a packed list holds, and a list after another in the bytes. */
static void irgrid_packed_lists_read_back_exactly(void **state) {
  (void)state;
  static const lt_i32 run9[] = {5, 6, 7, 8, 9, 10, 11, 12, 13};
  static const lt_i32 run4[] = {0, 1, 2, 3, 200, 201, 202, 203};
  static const lt_i32 steps[] = {31, 32, 64, 8000, 8001, 2100000, 2100002, LT_IRG_PACK_MAX - 2, LT_IRG_PACK_MAX - 1};
  static const lt_i32 zero[] = {0};
  const lt_i32 *lists[] = {NULL, zero, run9, run4, steps};
  int lengths[] = {0, 1, 9, 8, 9};
  lt_u8 bytes[4 * 64];
  lt_i32 words[64], offsets[5];
  int size = 0;
  for (int k = 0; k < 5; k++) offsets[k] = size, size += lt_irg_list_pack(lists[k], lengths[k], bytes + size);
  assert_true(size <= (int)sizeof words);
  memcpy(words, bytes, (size_t)size);
  for (int k = 0; k < 5; k++) {
    lt_irg_cell cell = {{0, 0, 0}, {1, 1, 1}, offsets[k], offsets[k]};
    lt_irg_list list = lt_irg_list_open(words, 1, &cell);
    assert_int_equal(list.left, lengths[k]);
    for (int i = 0; i < lengths[k]; i++) assert_int_equal(lt_irg_list_next(words, 1, &list), lists[k][i]);
    assert_int_equal(list.at, k + 1 < 5 ? offsets[k + 1] : size);
  }
  /* A run of nine is three tokens of one byte each, after the count. */
  assert_int_equal(offsets[3] - offsets[2], 1 + 3);
}

/* A row of small triangles along x, one a unit, each within 0.5 of the axis on y and z: at a
 * top density of 1024 cells a triangle the top grid is over 2048 cells long (the flat-scene
 * rule counts the thin axes as 1/64 of the longest), one cell on y and z, so the fine grid is
 * more than 65535 voxels long and its cells' boxes do not fit 16 bits. */
static lt_scene *long_row(int n) {
  float *tris = malloc((size_t)n * 9 * sizeof *tris);
  uint64_t seed = 77;
  for (int i = 0; i < n; i++) {
    float x = (float)i + 0.3f * lt__splitmix_unit(&seed), y = 0.2f * lt__splitmix_unit(&seed);
    float z = 0.2f * lt__splitmix_unit(&seed);
    float t[9] = {x, y, z, x + 0.6f, y + 0.3f * lt__splitmix_unit(&seed), z + 0.05f, x + 0.1f, y + 0.05f,
                  z + 0.3f * lt__splitmix_unit(&seed)};
    memcpy(tris + 9 * (size_t)i, t, sizeof t);
  }
  lt_scene *scene;
  assert_int_equal(lt_scene_from_triangles(tris, (size_t)n, &scene), LT_OK);
  free(tris);
  return scene;
}

/* Compaction keeps the 32-byte cells, their lists without counts, when the fine grid is too
 * long for 16-bit coordinates: the grid holds them, its cells reference exactly what meets
 * them, and both backends' trace kernels return the reference's hits, rays along the row
 * (crossing cells whose boxes lie beyond voxel 65535) among them. */
static void irgrid_fine_grid_beyond_16_bits_keeps_wide_cells(void **state) {
  (void)state;
  const int n = 4096;
  lt_scene *scene = long_row(n);
  lt_structure_config sc = irgrid_config(LT_BUILD_FULL);
  sc.irgrid_top_density = 1024.0f;
  built b = build_grid(scene, &sc, NULL, 0);
  fprintf(stderr, "irgrid long row: fine grid %dx%dx%d, %d cells of %zu bytes\n", b.g->fine.dims.x, b.g->fine.dims.y,
          b.g->fine.dims.z, b.a.cell_count, b.g->cells.bytes / (size_t)b.a.cell_count);
  assert_true(b.g->fine.dims.x > LT_IRG_CELL16_MAX);
  assert_true(b.g->compacted && !b.g->narrow);
  assert_int_equal(b.g->cells.bytes, (size_t)b.a.cell_count * sizeof(lt_irg_cell));
  int beyond = 0;
  for (int c = 0; c < b.a.cell_count; c++) beyond += b.a.cells[c].hi[0] > LT_IRG_CELL16_MAX;
  assert_true(beyond > 0);
  assert_int_equal(check_cells(scene, &b), b.a.cell_count);
  built_free(&b);

  /* Random rays over the row's box, and rays nearly along it from anywhere on it, either way. */
  size_t count = 4096;
  lt_ray *rays = malloc(count * sizeof *rays);
  lt_hit *ref = malloc(count * sizeof *ref);
  lt_test_random_rays(scene, 5, count / 2, rays);
  uint64_t seed = 9;
  for (size_t i = count / 2; i < count; i++) {
    float o[3] = {(float)n * lt__splitmix_unit(&seed), 0.5f * lt__splitmix_unit(&seed),
                  0.5f * lt__splitmix_unit(&seed)};
    float d[3] = {i % 2 ? 1.0f : -1.0f, 0.01f * (lt__splitmix_unit(&seed) - 0.5f),
                  0.01f * (lt__splitmix_unit(&seed) - 0.5f)};
    rays[i] = (lt_ray){{o[0], o[1], o[2]}, 0.0f, {d[0], d[1], d[2]}, INFINITY};
  }
  assert_int_equal(lt_reference_trace(scene, rays, count, LT_QUERY_CLOSEST, ref), LT_OK);
  size_t hit = 0;
  for (size_t i = 0; i < count; i++) hit += ref[i].prim >= 0;
  assert_true(hit > count / 4);
  const launch launches[] = {{LT_DEVICE_NATIVE, 2, 1}, {LT_DEVICE_OPENCL, 0, 1}};
  for (size_t l = 0; l < 1 + (size_t)lt_test_opencl_available(); l++) {
    lt_hit *hits = trace_with(scene, &launches[l], &sc, rays, count, LT_QUERY_CLOSEST, NULL);
    lt_hit *any = trace_with(scene, &launches[l], &sc, rays, count, LT_QUERY_ANY, NULL);
    assert_int_equal(lt_test_count_mismatches("irgrid long row", hits, ref, count), 0);
    assert_int_equal(lt_test_count_occlusion_mismatches(any, ref, count), 0);
    free(hits), free(any);
  }
  fprintf(stderr, "irgrid long row: %zu rays (%zu hit) match the reference on %s\n", count, hit,
          lt_test_opencl_available() ? "both backends" : "the native backend");
  free(rays), free(ref);
  lt_scene_destroy(scene);
}

/* Every top cell built on demand has the level of a full build that merges within top cells,
 * and its sub-voxels cells with that build's boxes and references. */
static void irgrid_top_cells_built_on_demand_equal_the_full_build(void **state) {
  (void)state;
  lt_scene *scene;
  int quick = getenv("LT_TEST_QUICK") != NULL;
  assert_int_equal(lt_scene_load(quick ? "hairball:300" : "house-row:2", &scene), LT_OK);
  int side = quick ? 32 : 96;
  size_t n = (size_t)side * side;
  lt_ray *rays = malloc(n * sizeof *rays);
  lt_test_camera_rays(scene, "close", side, side, rays);
  /* On demand, merges stay within top cells: the full build to compare with does the same. */
  lt_structure_config full_config = irgrid_config(LT_BUILD_FULL);
  full_config.irgrid_merge = LT_IRGRID_MERGE_TOP;
  built full = build_grid(scene, &full_config, NULL, 0);
  for (int mode = LT_BUILD_REQUESTED; mode <= LT_BUILD_SPECULATIVE; mode++) {
    lt_structure_config sc = irgrid_config((lt_build_mode)mode);
    built od = build_grid(scene, &sc, rays, n);
    int tops = 0, cells = 0;
    for (int t = 0; t < full.g->top_count; t++) {
      lt_i32 e = od.a.top_map[t], f = full.a.top_map[t];
      if (e < 0) continue;
      tops++;
      assert_true(f >= 0);
      /* Sub-voxel by sub-voxel of the on-demand top cell, through the voxel maps (the full
       * build's compaction may have coarsened its sub-map). */
      int level = LT_IRG_ENTRY_LEVEL(e), side = 1 << level, step = 1 << (LT_IRG_MAX_LEVEL - level);
      int top[3] = {t % full.g->top_dims[0], (t / full.g->top_dims[0]) % full.g->top_dims[1],
                    t / (full.g->top_dims[0] * full.g->top_dims[1])};
      for (int s = 0; s < side * side * side; s++) {
        int x = (top[0] << LT_IRG_MAX_LEVEL) + s % side * step, y = (top[1] << LT_IRG_MAX_LEVEL) + s / side % side * step;
        int z = (top[2] << LT_IRG_MAX_LEVEL) + s / (side * side) * step;
        lt_int4 dims = full.g->fine.dims;
        lt_i32 in_od = lt_irg_lookup(od.a.top_map, od.a.sub_maps, 0, dims, LT_IRG_MAX_LEVEL, x, y, z);
        lt_i32 in_full = lt_irg_lookup(full.a.top_map, full.a.sub_maps, 0, dims, LT_IRG_MAX_LEVEL, x, y, z);
        const lt_irg_cell *a = &od.a.cells[in_od], *b = &full.a.cells[in_full];
        assert_memory_equal(a->lo, b->lo, sizeof a->lo);
        assert_memory_equal(a->hi, b->hi, sizeof a->hi);
        assert_int_equal(a->end - a->begin, b->end - b->begin);
        assert_memory_equal(od.a.refs + a->begin, full.a.refs + b->begin, (size_t)(a->end - a->begin) * sizeof(lt_i32));
        cells++;
      }
    }
    fprintf(stderr, "irgrid %s: %d of %d top cells built, %d sub-voxels' cells equal the full build's\n",
            lt_build_mode_name((lt_build_mode)mode), tops, full.g->top_count, cells);
    assert_true(tops > 10);
    built_free(&od);
  }
  built_free(&full);
  free(rays);
  lt_scene_destroy(scene);
}

/* Requested builds a part of the grid from the outer camera of a row of houses; speculative
 * no less than requested and no more than full. */
static void irgrid_builds_only_what_rays_reach(void **state) {
  (void)state;
  lt_scene *scene;
  int quick = getenv("LT_TEST_QUICK") != NULL;
  assert_int_equal(lt_scene_load(quick ? "house" : "house-row:4", &scene), LT_OK);
  int side = quick ? 32 : 64;
  size_t n = (size_t)side * side;
  lt_ray *rays = malloc(n * sizeof *rays);
  lt_test_camera_rays(scene, "outer", side, side, rays);
  double tops[LT_BUILD_SPECULATIVE + 1], cells[LT_BUILD_SPECULATIVE + 1];
  for (int mode = LT_BUILD_FULL; mode <= LT_BUILD_SPECULATIVE; mode++) {
    lt_stats *stats;
    lt_stats_create(&stats);
    launch native = {LT_DEVICE_NATIVE, 2, 1};
    lt_structure_config sc = irgrid_config((lt_build_mode)mode);
    free(trace_with(scene, &native, &sc, rays, n, LT_QUERY_CLOSEST, stats));
    tops[mode] = lt_stats_get(stats, "cells.top_built");
    cells[mode] = lt_stats_get(stats, "nodes_built");
    assert_true(lt_stats_get(stats, "cells.top") >= tops[mode]);
    lt_stats_destroy(stats);
  }
  fprintf(stderr, "irgrid %s outer, %dx%d: top cells built full %.0f, requested %.0f, speculative %.0f; "
          "cells %.0f, %.0f, %.0f\n", quick ? "house" : "house-row:4", side, side, tops[LT_BUILD_FULL], tops[LT_BUILD_REQUESTED], tops[LT_BUILD_SPECULATIVE],
          cells[LT_BUILD_FULL], cells[LT_BUILD_REQUESTED], cells[LT_BUILD_SPECULATIVE]);
  assert_true(cells[LT_BUILD_REQUESTED] < 0.5 * cells[LT_BUILD_FULL]);
  assert_true(tops[LT_BUILD_REQUESTED] < tops[LT_BUILD_FULL]);
  assert_true(tops[LT_BUILD_SPECULATIVE] >= tops[LT_BUILD_REQUESTED]);
  assert_true(tops[LT_BUILD_SPECULATIVE] <= tops[LT_BUILD_FULL]);
  free(rays);
  lt_scene_destroy(scene);
}

/* Every setting in a full and a requested build, on generators and on closed meshes, against
 * brute force (closed meshes: no leaks), on both backends. */
static void check_settings(const char *what, const lt_scene *scene, const lt_ray *rays, size_t n, const lt_hit *ref) {
  int have_opencl = lt_test_opencl_available();
  const launch launches[] = {{LT_DEVICE_NATIVE, 0, 0}, {LT_DEVICE_OPENCL, 0, 0}};
  size_t settings_run = getenv("LT_TEST_QUICK") ? 3 : SETTINGS;
  for (size_t l = 0; l < 1 + (size_t)have_opencl; l++)
    for (size_t v = 0; v < settings_run; v++)
      for (int mode = LT_BUILD_FULL; mode <= LT_BUILD_REQUESTED; mode++) {
        lt_structure_config sc = config_of(&settings[v], (lt_build_mode)mode);
        char label[256];
        snprintf(label, sizeof label, "irgrid %s %s, %s, launch %zu", settings[v].what,
                 lt_build_mode_name((lt_build_mode)mode), what, l);
        lt_hit *hits = trace_with(scene, &launches[l], &sc, rays, n, LT_QUERY_CLOSEST, NULL);
        lt_hit *any = trace_with(scene, &launches[l], &sc, rays, n, LT_QUERY_ANY, NULL);
        assert_int_equal(lt_test_count_mismatches(label, hits, ref, n), 0);
        assert_int_equal(lt_test_count_occlusion_mismatches(any, ref, n), 0);
        free(hits), free(any);
      }
}

static void irgrid_settings_match_reference(void **state) {
  (void)state;
  static const char *const scenes[] = {"hairball:300", "cornell", "house"};
  int quick = getenv("LT_TEST_QUICK") != NULL;
  size_t count = quick ? 1 : 3;
  for (size_t s = 0; s < count; s++) {
    lt_scene *scene;
    assert_int_equal(lt_scene_load(scenes[s], &scene), LT_OK);
    lt_ray *rays = malloc(RAY_COUNT * sizeof *rays);
    lt_hit *ref = malloc(RAY_COUNT * sizeof *ref);
    make_rays(scene, 21 + s, rays, ref);
    check_settings(scenes[s], scene, rays, RAY_COUNT, ref);
    fprintf(stderr, "irgrid settings on %s: every one matches the reference\n", scenes[s]);
    free(rays), free(ref);
    lt_scene_destroy(scene);
  }
  lt_hc_mesh meshes[3] = {lt_hc_sphere(3, 3), lt_hc_torus(48, 24), lt_hc_cube(16, 5)};
  const char *names[3] = {"sphere:3", "torus 48x24", "cube 16x16"};
  for (int m = 0; m < (quick ? 1 : 3); m++) {
    size_t n = 1500;
    lt_ray *rays = malloc(n * sizeof *rays);
    lt_hit *ref = malloc(n * sizeof *ref);
    n = lt_hc_closed_rays(&meshes[m], 9, n, rays);
    assert_int_equal(lt_reference_trace(meshes[m].scene, rays, n, LT_QUERY_CLOSEST, ref), LT_OK);
    assert_int_equal(lt_hc_count_misses(ref, n), 0);
    check_settings(names[m], meshes[m].scene, rays, n, ref);
    fprintf(stderr, "irgrid settings on %s: %zu rays from inside, no leaks\n", names[m], n);
    free(rays), free(ref);
    lt_hc_free(&meshes[m]);
  }
  for (int m = quick ? 1 : 3; m < 3; m++) lt_hc_free(&meshes[m]);
}

/* A full build reports what it made. */
static void irgrid_statistics_are_filled(void **state) {
  (void)state;
  lt_scene *scene;
  assert_int_equal(lt_scene_load("sphere:4", &scene), LT_OK);
  size_t n = 256, tris = lt_scene_triangle_count(scene);
  lt_ray *rays = malloc(n * sizeof *rays);
  lt_test_random_rays(scene, 5, n, rays);
  lt_stats *stats;
  lt_stats_create(&stats);
  launch native = {LT_DEVICE_NATIVE, 2, 1};
  lt_structure_config sc = irgrid_config(LT_BUILD_FULL);
  free(trace_with(scene, &native, &sc, rays, n, LT_QUERY_CLOSEST, stats));
  double top = lt_stats_get(stats, "cells.top"), initial = lt_stats_get(stats, "cells.initial");
  double final = lt_stats_get(stats, "cells.final"), merges = lt_stats_get(stats, "cells.merges");
  fprintf(stderr, "irgrid sphere:4 (%zu triangles): %.0f top cells, %.0f initial, %.0f after %.0f merges, %.0f layers "
          "grown, %.0f references, %.0f map bytes\n", tris, top, initial, final, merges,
          lt_stats_get(stats, "cells.expansions"), lt_stats_get(stats, "references"), lt_stats_get(stats, "map_bytes"));
  assert_true(top >= 1 && lt_stats_get(stats, "cells.top_built") == top);
  assert_true(initial >= top && final <= initial && final >= top);
  assert_true(merges == initial - final);
  assert_true(lt_stats_get(stats, "nodes_built") == final && lt_stats_get(stats, "nodes_full") == final);
  assert_true(lt_stats_get(stats, "references") >= (double)tris);
  assert_true(lt_stats_get(stats, "sort_ops") >= (double)tris);
  /* The top map, and at least one sub-map entry for each cell kept (a compacted sub-map is an
   * octree: merged cells take fewer entries than the voxels they cover). */
  assert_true(lt_stats_get(stats, "map_bytes") >= 4 * (top + final));
  /* The cells kept, compacted to 16 bytes each (sphere:4's fine grid fits 16 bits). */
  assert_true(lt_stats_get(stats, "node_bytes") == 16 * final);
  assert_true(lt_stats_get(stats, "traversal_steps") > 0 && lt_stats_get(stats, "intersections") > 0);
  lt_stats_destroy(stats);
  free(rays);
  lt_scene_destroy(scene);
}

/* A pool of 2 slots fills at once; the grid retries larger and answers correctly. */
static void irgrid_full_pool_is_retried_larger(void **state) {
  (void)state;
  assert_int_equal(lt_test_small_pool_mismatches(LT_STRUCTURE_IRGRID), 0);
}

/* Settings out of range are refused with a message. */
static void irgrid_bad_settings_are_refused(void **state) {
  (void)state;
  lt_scene *scene;
  assert_int_equal(lt_scene_load("sphere:2", &scene), LT_OK);
  lt_context *ctx;
  lt_context_config config = {LT_DEVICE_NATIVE, 0, 0, 0, 1};
  assert_int_equal(lt_context_create(&config, &ctx), LT_OK);
  lt_structure *g;
  lt_structure_config bad[4];
  for (int i = 0; i < 4; i++) bad[i] = irgrid_config(LT_BUILD_FULL);
  bad[0].irgrid_top_density = -1.0f / 0.0f;
  bad[1].irgrid_merge_alpha = 1.5f;
  bad[2].irgrid_merge = LT_IRGRID_MERGE_TOP + 1;
  bad[3].irgrid_expansion_passes = LT_IRGRID_PASSES(LT_IRGRID_MAX_PASSES + 1);
  for (int i = 0; i < 4; i++) {
    assert_int_equal(lt_structure_create(ctx, scene, &bad[i], NULL, &g), LT_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(lt_last_error(), "irregular grid"));
  }
  lt_context_destroy(ctx);
  lt_scene_destroy(scene);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(irgrid_statistics_are_filled),
      cmocka_unit_test(irgrid_bad_settings_are_refused),
      cmocka_unit_test(irgrid_cells_reference_exactly_what_meets_them),
      cmocka_unit_test(irgrid_packed_lists_read_back_exactly),
      cmocka_unit_test(irgrid_fine_grid_beyond_16_bits_keeps_wide_cells),
      cmocka_unit_test(irgrid_top_cells_built_on_demand_equal_the_full_build),
      cmocka_unit_test(irgrid_builds_only_what_rays_reach),
      cmocka_unit_test(irgrid_full_pool_is_retried_larger),
      cmocka_unit_test(irgrid_matches_reference_in_every_mode),
      cmocka_unit_test(irgrid_settings_match_reference),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
