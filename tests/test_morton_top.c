/* The on-demand BVH with its Morton top (--top morton): the pyramid's range boxes and the code
 * split against a plain scan; closest and any hits equal the brute-force reference in every
 * build mode, on both backends, for renders and for collision frames that rebuild; the top is
 * really made of Morton nodes; full and on-demand builds make the same nodes; bad values of the
 * options are refused. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "builders/bvh_morton.h"
#include "builders/host/morton.h"
#include "tests/support.h"

#define CAMERA_SIZE 24
#define RANDOM_RAYS 512
#define RAY_COUNT (2 * CAMERA_SIZE * CAMERA_SIZE + RANDOM_RAYS)

/* A small bound, so that the small test scenes have a Morton top several levels deep. */
static lt_structure_config morton_config(lt_build_mode mode, int above) {
  lt_structure_config c = lt_structure_config_default(LT_STRUCTURE_BVH);
  c.build = mode, c.bvh_top = LT_BVH_TOP_MORTON, c.bvh_morton_above = above;
  return c;
}

static uint64_t next(uint64_t *s) {
  *s = *s * 6364136223846793005ull + 1442695040888963407ull;
  return *s >> 33;
}

/* The sort's order, codes and pyramid: codes ascend, every triangle appears once, and the box of
 * any range from the pyramid is the box of a plain scan; the split is where the highest
 * differing bit turns. Sizes around the block size and its powers, where the levels end odd. */
static void morton_bounds_equal_a_scan(void **state) {
  (void)state;
  const size_t sizes[] = {1, 2, 15, 16, 17, 33, 255, 256, 257, 1000, 40000};
  uint64_t seed = 3;
  lt__executor serial = {1, NULL};
  for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
    size_t n = sizes[s];
    float *boxes = malloc(n * 8 * sizeof *boxes);
    lt_box bounds = lt_box_empty();
    for (size_t i = 0; i < n; i++) {
      float *b = boxes + 8 * i;
      for (int k = 0; k < 3; k++) {
        /* Some triangles share a centre, so equal codes occur. */
        float c = (float)(next(&seed) % (i % 3 == 0 ? 4 : 100000)) / 1000.0f, h = (float)(next(&seed) % 100) / 100.0f;
        b[k] = c - h, b[4 + k] = c + h;
        bounds.lo[k] = fminf(bounds.lo[k], b[k]), bounds.hi[k] = fmaxf(bounds.hi[k], b[4 + k]);
      }
      b[3] = b[7] = 0.0f;
    }
    uint32_t *codes = malloc(n * sizeof *codes);
    int32_t *index = malloc(n * sizeof *index);
    float *blocks = malloc(lt__morton_block_count(n) * 8 * sizeof *blocks);
    double ops = 0;
    assert_int_equal(lt__morton_order(boxes, n, &bounds, &serial, NULL, codes, index, blocks, &ops), LT_OK);
    char *seen = calloc(n, 1);
    for (size_t i = 0; i < n; i++) {
      assert_true(index[i] >= 0 && (size_t)index[i] < n && !seen[index[i]]);
      seen[index[i]] = 1;
      if (i > 0) assert_true(codes[i - 1] < codes[i] || (codes[i - 1] == codes[i] && index[i - 1] < index[i]));
    }
    int blocks_bottom = (int)((n + LT_BVH_MORTON_BLOCK - 1) / LT_BVH_MORTON_BLOCK);
    for (int q = 0; q < 300; q++) {
      int lo = (int)(next(&seed) % n), hi = lo + 1 + (int)(next(&seed) % (n - (size_t)lo));
      if (q == 0) lo = 0, hi = (int)n;
      lt_box got = lt_morton_bounds((const lt_v4 *)boxes, index, (const lt_v4 *)blocks, blocks_bottom, lo, hi);
      lt_box want = lt_box_empty();
      for (int i = lo; i < hi; i++)
        for (int k = 0; k < 3; k++) {
          want.lo[k] = fminf(want.lo[k], boxes[8 * index[i] + k]);
          want.hi[k] = fmaxf(want.hi[k], boxes[8 * index[i] + 4 + k]);
        }
      assert_memory_equal(&got, &want, sizeof got);
      if (hi - lo < 2) continue;
      int mid = lt_morton_split(codes, lo, hi - 1);
      assert_true(mid > lo && mid < hi);
      if (codes[lo] != codes[hi - 1]) {
        uint32_t diff = codes[lo] ^ codes[hi - 1], bit = 1u << (31 - __builtin_clz(diff));
        assert_true(!(codes[mid - 1] & bit) && (codes[mid] & bit));
      }
    }
    free(boxes), free(codes), free(index), free(blocks), free(seen);
  }
}

/* Render rays (two cameras and random rays) on every mode and launch shape of both backends. */
static void morton_top_matches_reference_in_every_mode(void **state) {
  (void)state;
  static const char *const specs[] = {"house", "hairball:300", "sphere:4", "house-grid:2x2", "teapot-stadium"};
  int have_opencl = lt_test_opencl_available();
  const lt_test_launch launches[] = {{LT_DEVICE_NATIVE, 2, 1}, {LT_DEVICE_NATIVE, 1, 1}, {LT_DEVICE_NATIVE, 3, 1},
                                     {LT_DEVICE_OPENCL, 0, 1}, {LT_DEVICE_OPENCL, 2, 4}};
  size_t count = getenv("LT_TEST_QUICK") ? 2 : sizeof specs / sizeof specs[0];
  for (size_t s = 0; s < count; s++) {
    lt_scene *scene;
    assert_int_equal(lt_scene_load(specs[s], &scene), LT_OK);
    size_t n;
    lt_ray *rays = lt_test_generator_rays(scene, CAMERA_SIZE, RANDOM_RAYS, 11 + s, &n);
    assert_non_null(rays);
    assert_int_equal(n, RAY_COUNT);
    lt_hit *ref = malloc(RAY_COUNT * sizeof *ref);
    assert_int_equal(lt_reference_trace(scene, rays, RAY_COUNT, LT_QUERY_CLOSEST, ref), LT_OK);
    for (int mode = LT_BUILD_FULL; mode <= LT_BUILD_SPECULATIVE; mode++)
      for (size_t l = 0; l < sizeof launches / sizeof launches[0]; l++) {
        if (launches[l].device == LT_DEVICE_OPENCL && !have_opencl) continue;
        char what[128];
        snprintf(what, sizeof what, "%s %s launch %zu", specs[s], lt_build_mode_name((lt_build_mode)mode), l);
        lt_structure_config sc = morton_config((lt_build_mode)mode, 64);
        lt_stats *stats;
        lt_stats_create(&stats);
        lt_hit *hits = lt_test_trace_with(scene, &launches[l], &sc, rays, RAY_COUNT, LT_QUERY_CLOSEST, stats);
        assert_non_null(hits);
        assert_int_equal(lt_test_count_mismatches(what, hits, ref, RAY_COUNT), 0);
        assert_true(lt_stats_get(stats, "morton_nodes") > 0);
        lt_hit *any = lt_test_trace_with(scene, &launches[l], &sc, rays, RAY_COUNT, LT_QUERY_ANY, NULL);
        assert_non_null(any);
        assert_int_equal(lt_test_count_occlusion_mismatches(any, ref, RAY_COUNT), 0);
        free(hits), free(any);
        lt_stats_destroy(stats);
      }
    fprintf(stderr, "%s: %zu triangles: the Morton top matches the reference in every mode and launch\n", specs[s],
            lt_scene_triangle_count(scene));
    free(rays), free(ref);
    lt_scene_destroy(scene);
  }
}

/* Collision frames, every frame a new structure (as a moving scene rebuilds): requested and
 * speculative, both backends, against the reference. */
static void morton_top_collision_frames_match_reference(void **state) {
  (void)state;
  enum { agents = 40, per_agent = 8, frames = 4 };
  int have_opencl = lt_test_opencl_available();
  lt_scene *scene;
  assert_int_equal(lt_scene_load("house-grid:2x2", &scene), LT_OK);
  float paths[6 * agents];
  lt_ray rays[agents * per_agent];
  lt_hit hits[agents * per_agent], ref[agents * per_agent];
  lt_collision_paths(scene, agents, 42, paths);
  for (int f = 0; f < frames; f++) {
    lt_collision_rays(paths, agents, per_agent, f, frames, 43, rays);
    assert_int_equal(lt_reference_trace(scene, rays, agents * per_agent, LT_QUERY_CLOSEST, ref), LT_OK);
    for (int device = 0; device < 2; device++) {
      if (device == 1 && !have_opencl) continue;
      lt_test_launch l = {device == 0 ? LT_DEVICE_NATIVE : LT_DEVICE_OPENCL, 0, 0};
      for (int mode = LT_BUILD_REQUESTED; mode <= LT_BUILD_SPECULATIVE; mode++) {
        lt_structure_config sc = morton_config((lt_build_mode)mode, 256);
        lt_hit *got = lt_test_trace_with(scene, &l, &sc, rays, agents * per_agent, LT_QUERY_CLOSEST, NULL);
        assert_non_null(got);
        char what[96];
        snprintf(what, sizeof what, "frame %d %s %s", f, device ? "opencl" : "native",
                 lt_build_mode_name((lt_build_mode)mode));
        assert_int_equal(lt_test_count_mismatches(what, got, ref, agents * per_agent), 0);
        free(got);
      }
    }
    (void)hits;
  }
  lt_scene_destroy(scene);
}

/* The bound decides how deep the Morton top goes: a full build with a small bound makes many
 * Morton nodes, and one with a bound above the scene's size makes none (the SAH tree). */
static void morton_top_bound_decides_the_morton_nodes(void **state) {
  (void)state;
  lt_scene *scene;
  assert_int_equal(lt_scene_load("house-row:2", &scene), LT_OK);
  lt_test_launch native = {LT_DEVICE_NATIVE, 2, 1};
  lt_ray ray = {{0, 0, 0}, 0, {1, 0, 0}, 0}; /* no ray needs a node: full builds all */
  double morton[2], nodes[2];
  for (int i = 0; i < 2; i++) {
    lt_structure_config sc = morton_config(LT_BUILD_FULL, i == 0 ? 64 : 1 << 30);
    lt_stats *stats;
    lt_stats_create(&stats);
    free(lt_test_trace_with(scene, &native, &sc, &ray, 1, LT_QUERY_CLOSEST, stats));
    morton[i] = lt_stats_get(stats, "morton_nodes"), nodes[i] = lt_stats_get(stats, "nodes_built");
    lt_stats_destroy(stats);
  }
  fprintf(stderr, "house-row:2 full build: %.0f Morton nodes of %.0f (bound 64), %.0f of %.0f (no bound)\n", morton[0],
          nodes[0], morton[1], nodes[1]);
  assert_true(morton[0] > 100);
  assert_true(morton[1] == 0);
  lt_scene_destroy(scene);
}

/* A top that is neither sah nor morton, or a negative bound, is refused with a reason. */
static void morton_top_bad_options_are_refused(void **state) {
  (void)state;
  lt_scene *scene;
  assert_int_equal(lt_scene_load("house", &scene), LT_OK);
  lt_context *ctx;
  lt_context_config cc = {LT_DEVICE_NATIVE, 0, 0, 0, 1};
  assert_int_equal(lt_context_create(&cc, &ctx), LT_OK);
  lt_structure *s = NULL;
  lt_structure_config bad_top = morton_config(LT_BUILD_REQUESTED, 64), bad_bound = bad_top;
  bad_top.bvh_top = LT_BVH_TOP_MORTON + 1;
  bad_bound.bvh_morton_above = -5;
  assert_int_equal(lt_structure_create(ctx, scene, &bad_top, NULL, &s), LT_ERROR_INVALID_ARGUMENT);
  assert_null(s);
  assert_int_equal(lt_structure_create(ctx, scene, &bad_bound, NULL, &s), LT_ERROR_INVALID_ARGUMENT);
  assert_null(s);
  lt_context_destroy(ctx);
  lt_scene_destroy(scene);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(morton_bounds_equal_a_scan),
      cmocka_unit_test(morton_top_bad_options_are_refused),
      cmocka_unit_test(morton_top_bound_decides_the_morton_nodes),
      cmocka_unit_test(morton_top_collision_frames_match_reference),
      cmocka_unit_test(morton_top_matches_reference_in_every_mode),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
