/* The SAH kd-tree built through the task pool, fully and on demand: closest hits equal the
 * brute-force reference on every generator, mode, backend and launch shape, any-hit agrees;
 * the cells built on demand have the full tree's split planes and reference lists; on-demand
 * modes build a fraction of the tree; the statistics say what was built. The hard-case suite
 * (tests/test_robustness.c) and fault injection (tests/test_faults.c) take the kd-tree from the
 * registry like every structure. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "runtime/kd_ondemand_host.h"
#include "tests/hard_cases.h"
#include "tests/support.h"

#define CAMERA_SIZE 24
#define RANDOM_RAYS 512
#define RAY_COUNT (2 * CAMERA_SIZE * CAMERA_SIZE + RANDOM_RAYS)

static const char *const specs[] = {"house", "house-row:2", "house-grid:2x2", "hairball:300", "sphere:4", "cornell",
                                    "teapot-stadium"};

typedef lt_test_launch launch;

static lt_structure_config kd_config(lt_build_mode mode) {
  lt_structure_config c = lt_structure_config_default(LT_STRUCTURE_KDTREE);
  c.build = mode;
  return c;
}

/* Builds in `mode` with one launch shape and traces; returns malloc'ed hits. */
static lt_hit *trace_with(const lt_scene *scene, const launch *l, lt_build_mode mode, const lt_ray *rays, size_t n,
                          int query, lt_stats *stats) {
  lt_structure_config sc = kd_config(mode);
  lt_hit *hits = lt_test_trace_with(scene, l, &sc, rays, n, query, stats);
  assert_non_null(hits);
  return hits;
}

/* Every generator, both cameras and random rays, every mode, launch shapes on both backends. */
static void kdtree_matches_reference_in_every_mode(void **state) {
  (void)state;
  int have_opencl = lt_test_opencl_available();
  const launch launches[] = {{LT_DEVICE_NATIVE, 2, 1}, {LT_DEVICE_NATIVE, 1, 1}, {LT_DEVICE_NATIVE, 3, 1},
                             {LT_DEVICE_OPENCL, 0, 1}, {LT_DEVICE_OPENCL, 2, 4}};
  size_t first = getenv("LT_TEST_QUICK") ? 3 : 0;
  for (size_t s = first; s < sizeof specs / sizeof specs[0]; s++) {
    lt_scene *scene;
    assert_int_equal(lt_scene_load(specs[s], &scene), LT_OK);
    lt_ray *rays = malloc(RAY_COUNT * sizeof *rays);
    lt_hit *ref = malloc(RAY_COUNT * sizeof *ref);
    lt_test_camera_rays(scene, "outer", CAMERA_SIZE, CAMERA_SIZE, rays);
    lt_test_camera_rays(scene, "close", CAMERA_SIZE, CAMERA_SIZE, rays + CAMERA_SIZE * CAMERA_SIZE);
    lt_test_random_rays(scene, 11 + s, RANDOM_RAYS, rays + 2 * CAMERA_SIZE * CAMERA_SIZE);
    assert_int_equal(lt_reference_trace(scene, rays, RAY_COUNT, LT_QUERY_CLOSEST, ref), LT_OK);
    for (int mode = LT_BUILD_FULL; mode <= LT_BUILD_SPECULATIVE; mode++)
      for (size_t l = 0; l < sizeof launches / sizeof launches[0]; l++) {
        if (launches[l].device == LT_DEVICE_OPENCL && !have_opencl) continue;
        char what[128];
        snprintf(what, sizeof what, "kd-tree %s %s launch %zu", specs[s], lt_build_mode_name((lt_build_mode)mode), l);
        lt_hit *hits = trace_with(scene, &launches[l], (lt_build_mode)mode, rays, RAY_COUNT, LT_QUERY_CLOSEST, NULL);
        assert_int_equal(lt_test_count_mismatches(what, hits, ref, RAY_COUNT), 0);
        lt_hit *any = trace_with(scene, &launches[l], (lt_build_mode)mode, rays, RAY_COUNT, LT_QUERY_ANY, NULL);
        assert_int_equal(lt_test_count_occlusion_mismatches(any, ref, RAY_COUNT), 0);
        free(hits), free(any);
      }
    fprintf(stderr, "kd-tree %s: %zu triangles: every mode and launch matches the reference\n", specs[s],
            lt_scene_triangle_count(scene));
    free(rays), free(ref);
    lt_scene_destroy(scene);
  }
}

/* Two trees' snapshots walked side by side from the root. */
typedef struct tree_pair {
  const lt_kd_node *full, *od;
  const int *full_refs, *od_refs;
  int inner, leaves;
} tree_pair;

/* Compares the cell behind link `full_link` of the full tree with the one behind `od_link`
 * of the on-demand tree, where the latter is built; recursion depth is the tree's (< 45). */
static void compare_cells(tree_pair *p, int full_link, int od_link) {
  if (od_link <= -2) return; /* not built on demand: nothing to compare */
  assert_int_equal(full_link < 0, od_link < 0);
  if (od_link < 0) return;
  lt_kd_node f = p->full[full_link], o = p->od[od_link];
  assert_int_equal(f.meta, o.meta);
  if (lt_kd_axis(f.meta) == LT_KD_LEAF_AXIS) {
    lt_i32 count = lt_kd_leaf_count(f.meta);
    assert_memory_equal(p->full_refs + f.link[0], p->od_refs + o.link[0], (size_t)count * sizeof(int));
    p->leaves++;
    return;
  }
  assert_memory_equal(&f.split, &o.split, sizeof f.split);
  p->inner++;
  compare_cells(p, f.link[0], o.link[0]);
  compare_cells(p, f.link[1], o.link[1]);
}

typedef struct snapshot {
  lt_context *ctx;
  lt_structure *s;
  lt_kd_node *nodes;
  int *refs, node_count, ref_count;
} snapshot;

static snapshot build_and_snapshot(const lt_scene *scene, lt_build_mode mode, const lt_ray *rays, size_t n) {
  snapshot t;
  lt_context_config config = {LT_DEVICE_NATIVE, 2, 2, 0, 1};
  assert_int_equal(lt_context_create(&config, &t.ctx), LT_OK);
  lt_structure_config sc = kd_config(mode);
  assert_int_equal(lt_structure_create(t.ctx, scene, &sc, NULL, &t.s), LT_OK);
  lt_hit *hits = malloc(n * sizeof *hits);
  assert_int_equal(lt_structure_trace(t.s, rays, n, LT_QUERY_CLOSEST, hits, NULL), LT_OK);
  free(hits);
  lt__kd *kd = lt__structure_kd(t.s);
  assert_non_null(kd);
  assert_int_equal(lt__kd_snapshot(kd, &t.nodes, &t.node_count, &t.refs, &t.ref_count), LT_OK);
  return t;
}

static void snapshot_free(snapshot *t) {
  free(t->nodes), free(t->refs);
  lt_structure_destroy(t->s);
  lt_context_destroy(t->ctx);
}

/* Every cell built on demand has the split plane, and every leaf the references in the same
 * order, of the same cell of the full tree. */
static void kdtree_nodes_equal_the_full_tree(void **state) {
  (void)state;
  lt_scene *scene;
  assert_int_equal(lt_scene_load("house-row:2", &scene), LT_OK);
  int side = getenv("LT_TEST_QUICK") ? 48 : 128;
  size_t n = (size_t)side * side;
  lt_ray *rays = malloc(n * sizeof *rays);
  lt_test_camera_rays(scene, "close", side, side, rays);
  snapshot full = build_and_snapshot(scene, LT_BUILD_FULL, rays, n);
  for (int mode = LT_BUILD_REQUESTED; mode <= LT_BUILD_SPECULATIVE; mode++) {
    snapshot od = build_and_snapshot(scene, (lt_build_mode)mode, rays, n);
    tree_pair p = {full.nodes, od.nodes, full.refs, od.refs, 0, 0};
    compare_cells(&p, full.nodes[0].link[0], od.nodes[0].link[0]);
    fprintf(stderr, "kd-tree %s: %d inner cells and %d leaves equal the full tree's (full: %d nodes)\n",
            lt_build_mode_name((lt_build_mode)mode), p.inner, p.leaves, full.node_count - 1);
    assert_true(p.inner > 10 && p.leaves > 10);
    snapshot_free(&od);
  }
  snapshot_free(&full);
  free(rays);
  lt_scene_destroy(scene);
}

/* Requested builds a small part of the tree from the outer camera of a row of houses, and
 * speculative no less than requested and no more than full. */
static void kdtree_builds_only_what_rays_reach(void **state) {
  (void)state;
  lt_scene *scene;
  int quick = getenv("LT_TEST_QUICK") != NULL;
  assert_int_equal(lt_scene_load(quick ? "house-row:2" : "house-row:4", &scene), LT_OK);
  size_t n = 64 * 64;
  lt_ray *rays = malloc(n * sizeof *rays);
  lt_test_camera_rays(scene, "outer", 64, 64, rays);
  double nodes[LT_BUILD_SPECULATIVE + 1], refs[LT_BUILD_SPECULATIVE + 1];
  for (int mode = LT_BUILD_FULL; mode <= LT_BUILD_SPECULATIVE; mode++) {
    lt_stats *stats;
    lt_stats_create(&stats);
    launch native = {LT_DEVICE_NATIVE, 2, 1};
    free(trace_with(scene, &native, (lt_build_mode)mode, rays, n, LT_QUERY_CLOSEST, stats));
    nodes[mode] = lt_stats_get(stats, "nodes_built");
    refs[mode] = lt_stats_get(stats, "references");
    lt_stats_destroy(stats);
  }
  fprintf(stderr, "kd-tree house-row outer, 64x64: nodes built full %.0f, requested %.0f, speculative %.0f\n",
          nodes[LT_BUILD_FULL], nodes[LT_BUILD_REQUESTED], nodes[LT_BUILD_SPECULATIVE]);
  assert_true(nodes[LT_BUILD_REQUESTED] < 0.1 * nodes[LT_BUILD_FULL]);
  assert_true(nodes[LT_BUILD_SPECULATIVE] >= nodes[LT_BUILD_REQUESTED]);
  assert_true(nodes[LT_BUILD_SPECULATIVE] <= nodes[LT_BUILD_FULL]);
  /* Straddling triangles: a full tree holds more references than triangles. */
  assert_true(refs[LT_BUILD_FULL] > (double)lt_scene_triangle_count(scene));
  free(rays);
  lt_scene_destroy(scene);
}

/* A full build reports what it made: nodes, references, depth within the paper's limit,
 * sort operations, bytes of nodes and references. */
static void kdtree_statistics_are_filled(void **state) {
  (void)state;
  lt_scene *scene;
  assert_int_equal(lt_scene_load("sphere:4", &scene), LT_OK);
  size_t n = 256, tris = lt_scene_triangle_count(scene);
  lt_ray *rays = malloc(n * sizeof *rays);
  lt_test_random_rays(scene, 5, n, rays);
  lt_stats *stats;
  lt_stats_create(&stats);
  launch native = {LT_DEVICE_NATIVE, 2, 1};
  free(trace_with(scene, &native, LT_BUILD_FULL, rays, n, LT_QUERY_CLOSEST, stats));
  double depth = lt_stats_get(stats, "max_depth"), refs = lt_stats_get(stats, "references");
  fprintf(stderr, "kd-tree sphere:4 (%zu triangles): %.0f nodes, %.0f references, depth %.0f, %.0f sort ops\n", tris,
          lt_stats_get(stats, "nodes_built"), refs, depth, lt_stats_get(stats, "sort_ops"));
  assert_true(lt_stats_get(stats, "nodes_built") > 1);
  assert_true(refs >= (double)tris);
  assert_true(depth >= 1 && depth <= lt__kd_max_depth(tris));
  assert_true(lt_stats_get(stats, "sort_ops") >= (double)tris);
  assert_true(lt_stats_get(stats, "node_bytes") > 0 && lt_stats_get(stats, "reference_bytes") >= 4 * refs);
  lt_stats_destroy(stats);
  free(rays);
  lt_scene_destroy(scene);
}

/* A pool of 2 slots fills at once; the structure retries larger and answers correctly. */
static void kdtree_full_pool_is_retried_larger(void **state) {
  (void)state;
  assert_int_equal(lt_test_small_pool_mismatches(LT_STRUCTURE_KDTREE), 0);
}

/* The kd-tree's options, each against brute force: the stackless traversals on a full tree,
 * the exact sweep and clipping in every mode; on generators (cameras and random rays) and on
 * closed meshes, whose rays must never leak. */
typedef struct variant {
  const char *what;
  lt_build_mode build;
  int traversal, split, clip;
} variant;

static const variant variants[] = {
    {"restart", LT_BUILD_FULL, LT_KD_TRAVERSAL_RESTART, 0, 0},
    {"backtrack", LT_BUILD_FULL, LT_KD_TRAVERSAL_BACKTRACK, 0, 0},
    {"sweep full", LT_BUILD_FULL, 0, LT_KD_SPLIT_SWEEP, 0},
    {"sweep speculative", LT_BUILD_SPECULATIVE, 0, LT_KD_SPLIT_SWEEP, 0},
    {"clip full", LT_BUILD_FULL, 0, 0, LT_KD_CLIP_ON},
    {"clip requested", LT_BUILD_REQUESTED, 0, 0, LT_KD_CLIP_ON},
    {"sweep + clip + backtrack", LT_BUILD_FULL, LT_KD_TRAVERSAL_BACKTRACK, LT_KD_SPLIT_SWEEP, LT_KD_CLIP_ON},
    {"sweep + clip + restart", LT_BUILD_FULL, LT_KD_TRAVERSAL_RESTART, LT_KD_SPLIT_SWEEP, LT_KD_CLIP_ON},
};
#define VARIANTS (sizeof variants / sizeof variants[0])

/* Every variant on every context against `ref`; returns the most misses any variant had. */
static size_t check_variants(const char *what, const lt_scene *scene, const lt_ray *rays, size_t n, const lt_hit *ref) {
  int have_opencl = lt_test_opencl_available();
  lt_hit *hits = malloc(n * sizeof *hits), *any = malloc(n * sizeof *any);
  size_t worst = 0;
  for (int backend = 0; backend < 1 + have_opencl; backend++) {
    lt_context *ctx;
    lt_context_config config = {backend ? LT_DEVICE_OPENCL : LT_DEVICE_NATIVE, 0, 0, 0, 1};
    assert_int_equal(lt_context_create(&config, &ctx), LT_OK);
    for (size_t v = 0; v < VARIANTS; v++) {
      lt_structure_config sc = kd_config(variants[v].build);
      sc.kd_traversal = variants[v].traversal, sc.kd_split = variants[v].split, sc.kd_clip = variants[v].clip;
      char label[256];
      snprintf(label, sizeof label, "kd-tree %s, %s on %s", variants[v].what, what, lt_context_device_name(ctx));
      lt_structure *kd;
      lt_status status = lt_structure_create(ctx, scene, &sc, NULL, &kd);
      if (status) fprintf(stderr, "%s: %s\n", label, lt_last_error());
      assert_int_equal(status, LT_OK);
      assert_int_equal(lt_structure_trace(kd, rays, n, LT_QUERY_CLOSEST, hits, NULL), LT_OK);
      assert_int_equal(lt_structure_trace(kd, rays, n, LT_QUERY_ANY, any, NULL), LT_OK);
      lt_structure_destroy(kd);
      assert_int_equal(lt_test_count_mismatches(label, hits, ref, n), 0);
      assert_int_equal(lt_test_count_occlusion_mismatches(any, ref, n), 0);
      size_t misses = lt_hc_count_misses(hits, n);
      worst = misses > worst ? misses : worst;
    }
    lt_context_destroy(ctx);
  }
  free(hits), free(any);
  return worst;
}

static void kdtree_options_match_reference_on_generators(void **state) {
  (void)state;
  static const char *const scenes[] = {"house", "hairball:300", "sphere:4", "cornell"};
  for (size_t s = 0; s < sizeof scenes / sizeof scenes[0]; s++) {
    lt_scene *scene;
    assert_int_equal(lt_scene_load(scenes[s], &scene), LT_OK);
    lt_ray *rays = malloc(RAY_COUNT * sizeof *rays);
    lt_hit *ref = malloc(RAY_COUNT * sizeof *ref);
    lt_test_camera_rays(scene, "outer", CAMERA_SIZE, CAMERA_SIZE, rays);
    lt_test_camera_rays(scene, "close", CAMERA_SIZE, CAMERA_SIZE, rays + CAMERA_SIZE * CAMERA_SIZE);
    lt_test_random_rays(scene, 21 + s, RANDOM_RAYS, rays + 2 * CAMERA_SIZE * CAMERA_SIZE);
    assert_int_equal(lt_reference_trace(scene, rays, RAY_COUNT, LT_QUERY_CLOSEST, ref), LT_OK);
    check_variants(scenes[s], scene, rays, RAY_COUNT, ref);
    fprintf(stderr, "kd-tree options on %s: every variant matches the reference\n", scenes[s]);
    free(rays), free(ref);
    lt_scene_destroy(scene);
  }
}

/* Closed meshes (rays at vertices, edge midpoints and random points from inside): no variant
 * leaks, every one answers as brute force. */
static void kdtree_options_never_leak_from_closed_meshes(void **state) {
  (void)state;
  lt_hc_mesh meshes[3] = {lt_hc_sphere(3, 3), lt_hc_torus(48, 24), lt_hc_cube(16, 5)};
  const char *names[3] = {"sphere:3", "torus 48x24", "cube 16x16"};
  for (int m = 0; m < 3; m++) {
    size_t n = 1500;
    lt_ray *rays = malloc(n * sizeof *rays);
    lt_hit *ref = malloc(n * sizeof *ref);
    n = lt_hc_closed_rays(&meshes[m], 9, n, rays);
    assert_int_equal(lt_reference_trace(meshes[m].scene, rays, n, LT_QUERY_CLOSEST, ref), LT_OK);
    assert_int_equal(lt_hc_count_misses(ref, n), 0);
    assert_int_equal(check_variants(names[m], meshes[m].scene, rays, n, ref), 0);
    fprintf(stderr, "kd-tree options on %s: %zu rays, no leaks\n", names[m], n);
    free(rays), free(ref);
    lt_hc_free(&meshes[m]);
  }
}

/* The stackless traversals need a full tree, and say so. */
static void kdtree_stackless_traversal_needs_a_full_build(void **state) {
  (void)state;
  lt_scene *scene;
  assert_int_equal(lt_scene_load("sphere:2", &scene), LT_OK);
  lt_context *ctx;
  lt_context_config config = {LT_DEVICE_NATIVE, 0, 0, 0, 1};
  assert_int_equal(lt_context_create(&config, &ctx), LT_OK);
  lt_structure_config sc = kd_config(LT_BUILD_SPECULATIVE);
  sc.kd_traversal = LT_KD_TRAVERSAL_RESTART;
  lt_structure *kd;
  assert_int_equal(lt_structure_create(ctx, scene, &sc, NULL, &kd), LT_ERROR_UNSUPPORTED);
  assert_non_null(strstr(lt_last_error(), "--build full"));
  sc.kd_traversal = 7;
  assert_int_equal(lt_structure_create(ctx, scene, &sc, NULL, &kd), LT_ERROR_INVALID_ARGUMENT);
  lt_context_destroy(ctx);
  lt_scene_destroy(scene);
}

/* A tree the pool finished, traced again through the persistent kernel with each traversal
 * (the native backend runs it out of line, OpenCL inlined): the reference's closest hits,
 * every hit written (the native launch writes the caller's array in place, so it starts out as
 * garbage here), and no node requested. */
static void kdtree_finished_tree_through_the_persistent_kernel(void **state) {
  (void)state;
  int have_opencl = lt_test_opencl_available();
  lt_scene *scene;
  assert_int_equal(lt_scene_load("house-row:2", &scene), LT_OK);
  lt_ray *rays = malloc(RAY_COUNT * sizeof *rays);
  lt_hit *hits = malloc(RAY_COUNT * sizeof *hits), *ref = malloc(RAY_COUNT * sizeof *ref);
  lt_test_camera_rays(scene, "outer", CAMERA_SIZE, CAMERA_SIZE, rays);
  lt_test_camera_rays(scene, "close", CAMERA_SIZE, CAMERA_SIZE, rays + CAMERA_SIZE * CAMERA_SIZE);
  lt_test_random_rays(scene, 5, RANDOM_RAYS, rays + 2 * CAMERA_SIZE * CAMERA_SIZE);
  assert_int_equal(lt_reference_trace(scene, rays, RAY_COUNT, LT_QUERY_CLOSEST, ref), LT_OK);
  for (int b = 0; b < 2; b++)
    for (int traversal = LT_KD_TRAVERSAL_STACK; traversal <= LT_KD_TRAVERSAL_BACKTRACK; traversal++) {
      if (b == 1 && !have_opencl) continue;
      lt_context *ctx;
      lt_context_config config = {b == 0 ? LT_DEVICE_NATIVE : LT_DEVICE_OPENCL, 0, 0, 0, 1};
      assert_int_equal(lt_context_create(&config, &ctx), LT_OK);
      lt_structure_config sc = kd_config(LT_BUILD_FULL);
      sc.kd_traversal = traversal;
      lt_structure *kd;
      assert_int_equal(lt_structure_create(ctx, scene, &sc, NULL, &kd), LT_OK);
      lt_stats *stats;
      lt_stats_create(&stats);
      memset(hits, 0xab, RAY_COUNT * sizeof *hits);
      assert_int_equal(lt__kd_launch(lt__structure_kd(kd), rays, RAY_COUNT, LT_QUERY_CLOSEST, hits, 0, stats), LT_OK);
      assert_int_equal(lt_test_count_mismatches("persistent kernel, finished kd-tree", hits, ref, RAY_COUNT), 0);
      assert_true(lt_stats_get(stats, "pool.stalls") == 0);
      lt_stats_destroy(stats);
      lt_structure_destroy(kd);
      lt_context_destroy(ctx);
    }
  free(rays), free(hits), free(ref);
  lt_scene_destroy(scene);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(kdtree_statistics_are_filled),
      cmocka_unit_test(kdtree_nodes_equal_the_full_tree),
      cmocka_unit_test(kdtree_builds_only_what_rays_reach),
      cmocka_unit_test(kdtree_full_pool_is_retried_larger),
      cmocka_unit_test(kdtree_matches_reference_in_every_mode),
      cmocka_unit_test(kdtree_stackless_traversal_needs_a_full_build),
      cmocka_unit_test(kdtree_finished_tree_through_the_persistent_kernel),
      cmocka_unit_test(kdtree_options_match_reference_on_generators),
      cmocka_unit_test(kdtree_options_never_leak_from_closed_meshes),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
