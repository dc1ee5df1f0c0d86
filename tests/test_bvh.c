/* The full SAH BVH (built through the task pool) against the brute-force reference: closest hits (prim and t) on camera and
 * random rays for every generator, on both backends and several launch shapes; any-hit
 * answers against closest-hit occlusion. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "tests/support.h"

#define CAMERA_SIZE 24
#define RANDOM_RAYS 512
#define RAY_COUNT (2 * CAMERA_SIZE * CAMERA_SIZE + RANDOM_RAYS)

/* Small instances of every generator, so that brute force stays cheap. */
static const char *const specs[] = {"house", "house-row:2", "house-grid:2x2", "hairball:300", "teapot-stadium",
                                    "sphere:4", "cornell"};

typedef struct launch {
  lt_device_kind device;
  int work_groups, local_size;
} launch;

static const launch launches[] = {
    {LT_DEVICE_NATIVE, 1, 0}, {LT_DEVICE_NATIVE, 3, 0}, {LT_DEVICE_OPENCL, 0, 1},
    {LT_DEVICE_OPENCL, 0, 7}, {LT_DEVICE_OPENCL, 0, 64},
};

static void make_rays(const lt_scene *scene, lt_ray *rays) {
  lt_test_camera_rays(scene, "outer", CAMERA_SIZE, CAMERA_SIZE, rays);
  lt_test_camera_rays(scene, "close", CAMERA_SIZE, CAMERA_SIZE, rays + CAMERA_SIZE * CAMERA_SIZE);
  lt_test_random_rays(scene, 7, RANDOM_RAYS, rays + 2 * CAMERA_SIZE * CAMERA_SIZE);
}

/* Traces with one launch shape; returns the hits (caller frees) or NULL when skipped. */
static lt_hit *trace_with(const lt_scene *scene, const launch *l, const lt_ray *rays, size_t n, int query) {
  lt_context *ctx;
  lt_context_config config = {l->device, 0, l->work_groups, l->local_size, 1};
  assert_int_equal(lt_context_create(&config, &ctx), LT_OK);
  lt_structure *bvh;
  lt_structure_config full = lt_structure_config_default(LT_STRUCTURE_BVH);
  full.build = LT_BUILD_FULL;
  assert_int_equal(lt_structure_create(ctx, scene, &full, NULL, &bvh), LT_OK);
  lt_hit *hits = malloc(n * sizeof *hits);
  assert_non_null(hits);
  assert_int_equal(lt_structure_trace(bvh, rays, n, query, hits, NULL), LT_OK);
  lt_structure_destroy(bvh);
  lt_context_destroy(ctx);
  return hits;
}

static void bvh_matches_reference_on_every_generator(void **state) {
  (void)state;
  int have_opencl = lt_test_opencl_available();
  for (size_t s = 0; s < sizeof specs / sizeof specs[0]; s++) {
    lt_scene *scene;
    assert_int_equal(lt_scene_load(specs[s], &scene), LT_OK);
    lt_ray *rays = malloc(RAY_COUNT * sizeof *rays);
    lt_hit *ref = malloc(RAY_COUNT * sizeof *ref);
    make_rays(scene, rays);
    assert_int_equal(lt_reference_trace(scene, rays, RAY_COUNT, LT_QUERY_CLOSEST, ref), LT_OK);
    size_t ref_hits = 0;
    for (size_t i = 0; i < RAY_COUNT; i++) ref_hits += ref[i].prim >= 0;
    assert_true(ref_hits > RAY_COUNT / 10); /* the rays must actually meet the scene */

    /* Every launch shape gives exactly the reference's closest hits, and occlusion agrees. */
    for (size_t l = 0; l < sizeof launches / sizeof launches[0]; l++) {
      if (launches[l].device == LT_DEVICE_OPENCL && !have_opencl) continue;
      char what[96];
      snprintf(what, sizeof what, "%s launch %zu", specs[s], l);
      lt_hit *hits = trace_with(scene, &launches[l], rays, RAY_COUNT, LT_QUERY_CLOSEST);
      assert_int_equal(lt_test_count_mismatches(what, hits, ref, RAY_COUNT), 0);
      lt_hit *any = trace_with(scene, &launches[l], rays, RAY_COUNT, LT_QUERY_ANY);
      assert_int_equal(lt_test_count_occlusion_mismatches(any, ref, RAY_COUNT), 0);
      free(hits);
      free(any);
    }
    fprintf(stderr, "%s: %zu triangles, %d rays, %zu hits: all launches match\n", specs[s],
            lt_scene_triangle_count(scene), RAY_COUNT, ref_hits);
    free(rays), free(ref);
    lt_scene_destroy(scene);
  }
  if (!have_opencl) fprintf(stderr, "note: no OpenCL device; only the native backend was checked\n");
}

/* On a bigger scene, too big for brute force, the two backends agree bit for bit on 64k rays. */
static void bvh_backends_agree_bitwise_on_house_grid(void **state) {
  (void)state;
  if (!lt_test_opencl_available()) skip();
  lt_scene *scene;
  assert_int_equal(lt_scene_load("house-grid:3x3", &scene), LT_OK);
  size_t n = 256 * 256 + 4096;
  lt_ray *rays = malloc(n * sizeof *rays);
  lt_test_camera_rays(scene, "outer", 256, 256, rays);
  lt_test_random_rays(scene, 11, 4096, rays + 256 * 256);
  launch native = {LT_DEVICE_NATIVE, 2, 0}, opencl = {LT_DEVICE_OPENCL, 0, 32};
  lt_hit *a = trace_with(scene, &native, rays, n, LT_QUERY_CLOSEST);
  lt_hit *b = trace_with(scene, &opencl, rays, n, LT_QUERY_CLOSEST);
  assert_memory_equal(a, b, n * sizeof *a);
  free(a), free(b), free(rays);
  lt_scene_destroy(scene);
}

/* A degenerate scene of one triangle: the root is a leaf beside an empty child. */
static void bvh_single_triangle_scene(void **state) {
  (void)state;
  const float tri[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  lt_scene *scene;
  assert_int_equal(lt_scene_from_triangles(tri, 1, &scene), LT_OK);
  lt_ray rays[2] = {{{0.25f, 0.25f, -1}, 0, {0, 0, 1}, INFINITY}, {{2, 2, -1}, 0, {0, 0, 1}, INFINITY}};
  launch native = {LT_DEVICE_NATIVE, 1, 0};
  lt_hit *hits = trace_with(scene, &native, rays, 2, LT_QUERY_CLOSEST);
  assert_int_equal(hits[0].prim, 0);
  assert_true(hits[0].t == 1.0f);
  assert_int_equal(hits[1].prim, -1);
  free(hits);
  lt_scene_destroy(scene);
}

/* Statistics of a build carry the contract's keys with real values. */
static void bvh_statistics_are_filled(void **state) {
  (void)state;
  lt_scene *scene;
  assert_int_equal(lt_scene_load("sphere:3", &scene), LT_OK);
  lt_context *ctx;
  lt_context_config config = {LT_DEVICE_NATIVE, 0, 0, 0, 1};
  assert_int_equal(lt_context_create(&config, &ctx), LT_OK);
  lt_stats *stats;
  assert_int_equal(lt_stats_create(&stats), LT_OK);
  lt_structure *bvh;
  lt_structure_config full = lt_structure_config_default(LT_STRUCTURE_BVH);
  full.build = LT_BUILD_FULL;
  assert_int_equal(lt_structure_create(ctx, scene, &full, stats, &bvh), LT_OK);
  lt_ray rays[64];
  lt_hit hits[64];
  lt_test_random_rays(scene, 3, 64, rays);
  assert_int_equal(lt_structure_trace(bvh, rays, 64, LT_QUERY_CLOSEST, hits, stats), LT_OK);
  assert_true(lt_stats_get(stats, "triangles") == 1280);
  assert_true(lt_stats_get(stats, "references") == 1280);
  assert_true(lt_stats_get(stats, "nodes_built") > 1280 / 16);
  assert_true(lt_stats_get(stats, "rays") == 64);
  assert_true(lt_stats_get(stats, "traversal_steps") >= 64);
  assert_true(lt_stats_get(stats, "sort_ops") >= 2 * 1280);
  assert_true(lt_stats_get(stats, "memory_bytes") > 0);
  lt_structure_destroy(bvh);
  lt_stats_destroy(stats);
  lt_context_destroy(ctx);
  lt_scene_destroy(scene);
}

/* A zeroed config is the default BVH; negative, NaN or unknown values are refused, never taken. */
static void bvh_config_zero_means_default_and_nonsense_is_refused(void **state) {
  (void)state;
  lt_context *ctx;
  lt_context_config native = {LT_DEVICE_NATIVE, 0, 2, 0, 1};
  assert_int_equal(lt_context_create(&native, &ctx), LT_OK);
  lt_scene *scene;
  assert_int_equal(lt_scene_load("sphere:1", &scene), LT_OK);
  lt_structure_config zero;
  memset(&zero, 0, sizeof zero);
  lt_structure *s;
  lt_stats *stats;
  lt_stats_create(&stats);
  assert_int_equal(lt_structure_create(ctx, scene, &zero, stats, &s), LT_OK);
  lt_structure_destroy(s);
  lt_structure_config d = lt_structure_config_default(LT_STRUCTURE_BVH);
  assert_int_equal(d.build, LT_BUILD_SPECULATIVE);
  assert_int_equal(d.max_leaf_size, 16);
  assert_int_equal(d.sah_bins, 32);
  assert_int_equal(lt_structure_config_default(LT_STRUCTURE_LBVH).build, LT_BUILD_FULL);

  lt_structure_config bad[5];
  for (int i = 0; i < 5; i++) bad[i] = zero;
  bad[0].max_leaf_size = -1, bad[1].sah_bins = -5, bad[2].traversal_cost = NAN, bad[3].build = (lt_build_mode)99;
  bad[4].kind = (lt_structure_kind)99;
  for (int i = 0; i < 5; i++) assert_int_equal(lt_structure_create(ctx, scene, &bad[i], NULL, &s), LT_ERROR_INVALID_ARGUMENT);
  lt_stats_destroy(stats);
  lt_scene_destroy(scene);
  lt_context_destroy(ctx);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(bvh_single_triangle_scene),
      cmocka_unit_test(bvh_config_zero_means_default_and_nonsense_is_refused),
      cmocka_unit_test(bvh_statistics_are_filled),
      cmocka_unit_test(bvh_matches_reference_on_every_generator),
      cmocka_unit_test(bvh_backends_agree_bitwise_on_house_grid),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
