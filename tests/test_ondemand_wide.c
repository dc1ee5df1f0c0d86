/* The wide tree of the on-demand BVH (runtime/bvh_wide_host.c): between launches the native
 * backend collapses the built part 8 wide and the next launch's rays cross it with the AVX2
 * traversal, leaving it by its exits. Every launch on one tree, with the collapse on and off,
 * returns the
 * brute-force reference's closest hits (t and prim bit for bit), any-hit agrees, closed meshes
 * do not leak, a wide copy made wrong on purpose shows in the hits (so the rays do go
 * through it), and any-hit queries' guesses keep occlusion as it is. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "runtime/bvh_ondemand_host.h"
#include "tests/hard_cases.h"
#include "tests/support.h"
#include "traversal/bvh_view.h"

static const char *const specs[] = {"house", "house-row:2", "house-grid:2x2", "hairball:300", "sphere:4", "cornell",
                                    "teapot-stadium"};

/* Whether this machine makes a wide tree at all (native backend with AVX2). */
static int wide_here(void) {
  lt_context *ctx;
  lt_context_config config = {LT_DEVICE_NATIVE, 0, 0, 0, 1};
  if (lt_context_create(&config, &ctx) != LT_OK) return 0;
  int wanted = lt__ondemand_wide_wanted(ctx, LT_POOL_REQUESTED);
  lt_context_destroy(ctx);
  return wanted;
}

/* Trees made from now on have the Morton top (--top morton, nodes above 64 triangles). */
static int morton_top;

/* A tree on demand in `mode` on a native context of `groups` work-groups. */
static lt_structure *make_tree(const lt_scene *scene, lt_build_mode mode, int groups, lt_context **ctx) {
  lt_context_config config = {LT_DEVICE_NATIVE, groups, 1, 0, 1};
  assert_int_equal(lt_context_create(&config, ctx), LT_OK);
  lt_structure_config sc = lt_structure_config_default(LT_STRUCTURE_BVH);
  sc.build = mode;
  if (morton_top) sc.bvh_top = LT_BVH_TOP_MORTON, sc.bvh_morton_above = 64;
  lt_structure *bvh;
  assert_int_equal(lt_structure_create(*ctx, scene, &sc, NULL, &bvh), LT_OK);
  return bvh;
}

/* Traces the rays `launches` times on one tree (closest, then any hit on the last launch):
 * every launch's closest hits equal ref, the any-hit answers agree; returns the collapses
 * made. */
static int launches_match(const char *what, const lt_scene *scene, lt_build_mode mode, int groups, const lt_ray *rays,
                          size_t n, const lt_hit *ref, int launches) {
  lt_context *ctx;
  lt_structure *bvh = make_tree(scene, mode, groups, &ctx);
  lt_hit *hits = malloc(n * sizeof *hits);
  for (int l = 0; l < launches; l++) {
    memset(hits, 0xab, n * sizeof *hits);
    assert_int_equal(lt_structure_trace(bvh, rays, n, LT_QUERY_CLOSEST, hits, NULL), LT_OK);
    char label[200];
    snprintf(label, sizeof label, "%s, launch %d", what, l + 1);
    assert_int_equal(lt_test_count_mismatches(label, hits, ref, n), 0);
  }
  assert_int_equal(lt_structure_trace(bvh, rays, n, LT_QUERY_ANY, hits, NULL), LT_OK);
  assert_int_equal(lt_test_count_occlusion_mismatches(hits, ref, n), 0);
  int made = lt__structure_ondemand(bvh)->wide_collapses;
  free(hits);
  lt_structure_destroy(bvh);
  lt_context_destroy(ctx);
  return made;
}

/* Every generator, both on-demand modes, the collapse on and off, one and two work-groups,
 * the SAH and the Morton top: three launches of the generator rays on one tree, each against
 * brute force. */
static void ondemand_wide_matches_reference_across_launches(void **state) {
  (void)state;
  int wide = wide_here();
  size_t first = getenv("LT_TEST_QUICK") ? 3 : 0;
  for (size_t s = first; s < sizeof specs / sizeof specs[0]; s++) {
    lt_scene *scene;
    assert_int_equal(lt_scene_load(specs[s], &scene), LT_OK);
    size_t n;
    lt_ray *rays = lt_test_generator_rays(scene, 24, 512, 31 + s, &n);
    lt_hit *ref = malloc(n * sizeof *ref);
    assert_int_equal(lt_reference_trace(scene, rays, n, LT_QUERY_CLOSEST, ref), LT_OK);
    for (int mode = LT_BUILD_REQUESTED; mode <= LT_BUILD_SPECULATIVE; mode++)
      for (int variant = 0; variant < 4; variant++) {
        /* 0, 1: wide on one and two work-groups; 2: the switch off; 3: wide, Morton top. */
        if (variant == 2) setenv("LT_BVH_WIDE", "0", 1);
        morton_top = variant == 3;
        char what[160];
        snprintf(what, sizeof what, "%s %s %s%s, %d work-groups", specs[s], lt_build_mode_name((lt_build_mode)mode),
                 variant == 2 ? "binary" : "wide", morton_top ? ", Morton top" : "", 1 + variant % 2);
        int made = launches_match(what, scene, (lt_build_mode)mode, 1 + variant % 2, rays, n, ref, 3);
        unsetenv("LT_BVH_WIDE");
        morton_top = 0;
        fprintf(stderr, "%s: %d collapses\n", what, made);
        if (variant == 2 || !wide) assert_int_equal(made, 0);
        else assert_true(made > 0);
      }
    free(rays), free(ref);
    lt_scene_destroy(scene);
  }
}

/* Rays whose exits do not fit go down the binary subtree instead, keeping the hits the wide
 * traversal found: with room for 0 and for 2 exits, every launch still matches brute force. */
static void ondemand_wide_exits_that_do_not_fit_fall_back(void **state) {
  (void)state;
#if !LT_BVH_WIDE
  skip();
#else
  if (!wide_here()) skip();
  const char *const scenes[] = {"house-grid:2x2", "hairball:300"};
  for (int s = 0; s < 2; s++) {
    lt_scene *scene;
    assert_int_equal(lt_scene_load(scenes[s], &scene), LT_OK);
    size_t n;
    lt_ray *rays = lt_test_generator_rays(scene, 24, 512, 3, &n);
    lt_hit *ref = malloc(n * sizeof *ref);
    assert_int_equal(lt_reference_trace(scene, rays, n, LT_QUERY_CLOSEST, ref), LT_OK);
    for (int limit = 0; limit <= 2; limit += 2) {
      lt__bvh_wide_exit_limit = limit;
      char what[120];
      snprintf(what, sizeof what, "%s, room for %d exits", scenes[s], limit);
      assert_true(launches_match(what, scene, LT_BUILD_SPECULATIVE, 2, rays, n, ref, 2) > 0);
    }
    lt__bvh_wide_exit_limit = LT_BVH_RAY_STACK_SIZE;
    free(rays), free(ref);
    lt_scene_destroy(scene);
  }
#endif
}

/* Closed meshes shot from inside (vertices, edge midpoints, random directions) twice on one
 * tree: the second launch crosses the wide tree and no ray may leave. */
static void ondemand_wide_closed_meshes_never_leak(void **state) {
  (void)state;
  int quick = getenv("LT_TEST_QUICK") != NULL;
  lt_hc_mesh meshes[3] = {lt_hc_sphere(quick ? 3 : 5, 3), lt_hc_torus(48, 24), lt_hc_cube(16, 5)};
  size_t n = quick ? 1000 : 4000;
  lt_ray *rays = malloc(n * sizeof *rays);
  lt_hit *hits = malloc(n * sizeof *hits);
  for (int m = 0; m < 3; m++) {
    size_t count = lt_hc_closed_rays(&meshes[m], 17, n, rays);
    for (int mode = LT_BUILD_REQUESTED; mode <= LT_BUILD_SPECULATIVE; mode++) {
      lt_context *ctx;
      lt_structure *bvh = make_tree(meshes[m].scene, (lt_build_mode)mode, 2, &ctx);
      for (int l = 0; l < 2; l++) {
        assert_int_equal(lt_structure_trace(bvh, rays, count, LT_QUERY_CLOSEST, hits, NULL), LT_OK);
        assert_int_equal(lt_hc_count_misses(hits, count), 0);
      }
      lt_structure_destroy(bvh);
      lt_context_destroy(ctx);
    }
    lt_hc_free(&meshes[m]);
  }
  free(rays), free(hits);
}

/* The rays really cross the wide copies: with every wide triangle's number changed after the
 * collapse, the next launch's hits differ from the reference (and they did not before). */
static void ondemand_wide_copies_are_what_rays_see(void **state) {
  (void)state;
  if (!wide_here()) skip();
  lt_scene *scene;
  assert_int_equal(lt_scene_load("house-grid:2x2", &scene), LT_OK);
  size_t n;
  lt_ray *rays = lt_test_generator_rays(scene, 24, 0, 1, &n);
  lt_hit *ref = malloc(n * sizeof *ref), *hits = malloc(n * sizeof *hits);
  assert_int_equal(lt_reference_trace(scene, rays, n, LT_QUERY_CLOSEST, ref), LT_OK);
  lt_context *ctx;
  lt_structure *bvh = make_tree(scene, LT_BUILD_REQUESTED, 2, &ctx);
  assert_int_equal(lt_structure_trace(bvh, rays, n, LT_QUERY_CLOSEST, hits, NULL), LT_OK);
  assert_int_equal(lt_test_count_mismatches("first launch", hits, ref, n), 0);

  /* A launch with one ray collapses what the first built; then every copy is made wrong. */
  lt__ondemand *od = lt__structure_ondemand(bvh);
  assert_int_equal(lt_structure_trace(bvh, rays, 1, LT_QUERY_CLOSEST, hits, NULL), LT_OK);
  assert_true(od->wide_collapses > 0 && od->wide.tri_slots > 0);
  for (int i = 0; i < od->wide.tri_slots; i++) od->wide.blocks[i / 4].prim[i % 4] = 1 << 30;
  od->wide_hold = 1; /* the next launch collapses nothing again: it sees the wrong copies */
  assert_int_equal(lt_structure_trace(bvh, rays, n, LT_QUERY_CLOSEST, hits, NULL), LT_OK);
  size_t wrong = 0;
  for (size_t i = 0; i < n; i++) wrong += hits[i].prim == 1 << 30;
  fprintf(stderr, "%zu of %zu hits came from the wide copies\n", wrong, n);
  assert_true(wrong > n / 10);
  lt_structure_destroy(bvh);
  lt_context_destroy(ctx);
  free(rays), free(ref), free(hits);
  lt_scene_destroy(scene);
}

/* Statistics: the wide copy's bytes are part of memory_bytes, and the switch removes them. */
static void ondemand_wide_memory_is_counted(void **state) {
  (void)state;
  if (!wide_here()) skip();
  lt_scene *scene;
  assert_int_equal(lt_scene_load("house-row:2", &scene), LT_OK);
  size_t n;
  lt_ray *rays = lt_test_generator_rays(scene, 32, 0, 1, &n);
  lt_hit *hits = malloc(n * sizeof *hits);
  double memory[2], wide_bytes[2];
  for (int off = 0; off < 2; off++) {
    if (off) setenv("LT_BVH_WIDE", "0", 1);
    lt_context *ctx;
    lt_structure *bvh = make_tree(scene, LT_BUILD_SPECULATIVE, 2, &ctx);
    lt_stats *stats;
    lt_stats_create(&stats);
    for (int l = 0; l < 2; l++) assert_int_equal(lt_structure_trace(bvh, rays, n, LT_QUERY_CLOSEST, hits, stats), LT_OK);
    memory[off] = lt_stats_get(stats, "memory_bytes");
    wide_bytes[off] = lt_stats_get(stats, "wide.bytes");
    lt_stats_destroy(stats);
    lt_structure_destroy(bvh);
    lt_context_destroy(ctx);
    unsetenv("LT_BVH_WIDE");
  }
  fprintf(stderr, "memory %.0f bytes with the wide tree (%.0f of them its), %.0f without\n", memory[0],
          wide_bytes[0], memory[1]);
  assert_true(wide_bytes[0] > 0);
  assert_true(memory[0] >= memory[1] + wide_bytes[0]);
  free(rays), free(hits);
  lt_scene_destroy(scene);
}

/* A batch large enough is traced in two launches (runtime/bvh_ondemand_host.c): every second
 * ray first, then the others on the tree collapsed in between, the sample's answers kept (the
 * hits start as garbage, so a ray answered by no launch shows); the sample is traced so too,
 * while it is large enough. The first trace on a new tree then makes one collapse a sampling
 * stage (none with the sample off), and its hits are brute force's. */
static int sampling_stages(size_t n, int stride) {
  int stages = 0;
  for (; lt__ondemand_wide_sample(stride, (int)n); n = (n + (size_t)stride - 1) / (size_t)stride) stages++;
  return stages;
}

static void ondemand_wide_first_launch_runs_after_a_sample(void **state) {
  (void)state;
  if (!wide_here()) skip();
  const char *const scenes[] = {"hairball:300", "house-grid:2x2", "teapot-stadium"};
  int count = getenv("LT_TEST_QUICK") ? 2 : 3; /* the sanitizer runs: no 336k-triangle brute force */
  for (int s = 0; s < count; s++) {
    lt_scene *scene;
    assert_int_equal(lt_scene_load(scenes[s], &scene), LT_OK);
    size_t n;
    lt_ray *rays = lt_test_generator_rays(scene, 64, 512, 5 + s, &n);
    assert_true(sampling_stages(n, 2) >= 2); /* the sample has a sample of its own */
    lt_hit *ref = malloc(n * sizeof *ref), *hits = malloc(n * sizeof *hits);
    assert_int_equal(lt_reference_trace(scene, rays, n, LT_QUERY_CLOSEST, ref), LT_OK);
    for (int mode = LT_BUILD_REQUESTED; mode <= LT_BUILD_SPECULATIVE; mode++)
      for (int sampled = 0; sampled < 2; sampled++) {
        setenv("LT_BVH_WIDE_SAMPLE", sampled ? "2" : "0", 1);
        lt_context *ctx;
        lt_structure *bvh = make_tree(scene, (lt_build_mode)mode, 2, &ctx);
        memset(hits, 0xab, n * sizeof *hits);
        assert_int_equal(lt_structure_trace(bvh, rays, n, LT_QUERY_CLOSEST, hits, NULL), LT_OK);
        char what[160];
        snprintf(what, sizeof what, "%s %s, %s", scenes[s], lt_build_mode_name((lt_build_mode)mode),
                 sampled ? "after a sample" : "one launch");
        assert_int_equal(lt_test_count_mismatches(what, hits, ref, n), 0);
        assert_int_equal(lt__structure_ondemand(bvh)->wide_collapses, sampled ? sampling_stages(n, 2) : 0);
        lt_structure_destroy(bvh);
        lt_context_destroy(ctx);
        unsetenv("LT_BVH_WIDE_SAMPLE");
      }
    free(rays), free(ref), free(hits);
    lt_scene_destroy(scene);
  }
}

/* Guesses (kernels/native_bvh_wide.c): ambient-occlusion rays, eight from each primary hit, in
 * pixel order, traced any-hit on the wide tree with guesses on and off. Both agree with brute
 * force on occlusion and every answer lies within [tmin, tmax]; on the house the rays make
 * fewer node visits with guesses (so the guesses did answer, and were checked above). */
static void ondemand_wide_guesses_keep_occlusion(void **state) {
  (void)state;
  if (!wide_here()) skip();
  const char *const scenes[] = {"house-grid:2x2", "cornell", "hairball:300"};
  for (int s = 0; s < 3; s++) {
    lt_scene *scene;
    assert_int_equal(lt_scene_load(scenes[s], &scene), LT_OK);
    size_t n = 48 * 48, m;
    lt_ray *primary = malloc(n * sizeof *primary), *ao = lt_test_ao_rays(scene, 48, primary, &m);
    assert_non_null(ao);
    lt_hit *ref = malloc(m * sizeof *ref), *hits = malloc(m * sizeof *hits);
    assert_int_equal(lt_reference_trace(scene, ao, m, LT_QUERY_ANY, ref), LT_OK);
    double steps[2];
    for (int off = 0; off < 2; off++) {
      if (off) setenv("LT_BVH_GUESSES", "0", 1);
      lt_context *ctx;
      lt_structure *bvh = make_tree(scene, LT_BUILD_SPECULATIVE, 2, &ctx);
      assert_int_equal(lt_structure_trace(bvh, primary, n, LT_QUERY_CLOSEST, hits, NULL), LT_OK);
      lt_stats *stats;
      lt_stats_create(&stats);
      assert_int_equal(lt_structure_trace(bvh, ao, m, LT_QUERY_ANY, hits, NULL), LT_OK); /* builds */
      assert_int_equal(lt_structure_trace(bvh, ao, m, LT_QUERY_ANY, hits, stats), LT_OK);
      steps[off] = lt_stats_get(stats, "traversal_steps");
      assert_int_equal(lt_test_count_occlusion_mismatches(hits, ref, m), 0);
      for (size_t i = 0; i < m; i++)
        if (hits[i].prim >= 0) assert_true(hits[i].t >= ao[i].tmin && hits[i].t <= ao[i].tmax);
      lt_stats_destroy(stats);
      lt_structure_destroy(bvh);
      lt_context_destroy(ctx);
      unsetenv("LT_BVH_GUESSES");
    }
    fprintf(stderr, "%s: %zu AO rays, %.2f node visits a ray with guesses, %.2f without\n", scenes[s], m,
            steps[0] / (double)m, steps[1] / (double)m);
    if (s == 0) assert_true(steps[0] < 0.9 * steps[1]); /* a house's AO rays: mostly occluded */
    free(primary), free(ao), free(ref), free(hits);
    lt_scene_destroy(scene);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(ondemand_wide_copies_are_what_rays_see),
      cmocka_unit_test(ondemand_wide_memory_is_counted),
      cmocka_unit_test(ondemand_wide_closed_meshes_never_leak),
      cmocka_unit_test(ondemand_wide_matches_reference_across_launches),
      cmocka_unit_test(ondemand_wide_exits_that_do_not_fit_fall_back),
      cmocka_unit_test(ondemand_wide_first_launch_runs_after_a_sample),
      cmocka_unit_test(ondemand_wide_guesses_keep_occlusion),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
