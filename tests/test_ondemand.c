/* The SAH BVH built through the task pool, fully and on demand: closest hits equal the
 * brute-force reference on every generator, mode, backend and launch shape; any-hit agrees;
 * a second batch continues on the partial tree; the nodes built on demand are the full tree's;
 * a pool that fills up is retried larger. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "builders/host/bvh_sah.h"
#include "runtime/bvh_ondemand_host.h"
#include "tests/support.h"

#define CAMERA_SIZE 24
#define RANDOM_RAYS 512
#define RAY_COUNT (2 * CAMERA_SIZE * CAMERA_SIZE + RANDOM_RAYS)

static const char *const specs[] = {"house", "house-row:2", "house-grid:2x2", "hairball:300", "sphere:4", "cornell",
                                    "teapot-stadium"};

typedef lt_test_launch launch;

static lt_structure_config mode_config(lt_build_mode mode) {
  lt_structure_config c = lt_structure_config_default(LT_STRUCTURE_BVH);
  c.build = mode;
  return c;
}

/* Builds in `mode` with one launch shape and traces; returns malloc'ed hits. */
static lt_hit *trace_with(const lt_scene *scene, const launch *l, lt_build_mode mode, const lt_ray *rays, size_t n,
                          int query, lt_stats *stats) {
  lt_structure_config sc = mode_config(mode);
  lt_hit *hits = lt_test_trace_with(scene, l, &sc, rays, n, query, stats);
  assert_non_null(hits);
  return hits;
}

static void make_rays(const lt_scene *scene, uint64_t seed, lt_ray *rays) {
  lt_test_camera_rays(scene, "outer", CAMERA_SIZE, CAMERA_SIZE, rays);
  lt_test_camera_rays(scene, "close", CAMERA_SIZE, CAMERA_SIZE, rays + CAMERA_SIZE * CAMERA_SIZE);
  lt_test_random_rays(scene, seed, RANDOM_RAYS, rays + 2 * CAMERA_SIZE * CAMERA_SIZE);
}

/* Every generator, every mode, several launch shapes on both backends. */
static void ondemand_matches_reference_in_every_mode(void **state) {
  (void)state;
  int have_opencl = lt_test_opencl_available();
  const launch launches[] = {{LT_DEVICE_NATIVE, 2, 1}, {LT_DEVICE_NATIVE, 1, 1}, {LT_DEVICE_NATIVE, 3, 1},
                             {LT_DEVICE_OPENCL, 0, 1}, {LT_DEVICE_OPENCL, 2, 4}};
  /* Under the sanitizers (LT_TEST_QUICK), the small scenes only: brute force is slow there. */
  size_t first = getenv("LT_TEST_QUICK") ? 3 : 0;
  for (size_t s = first; s < sizeof specs / sizeof specs[0]; s++) {
    lt_scene *scene;
    assert_int_equal(lt_scene_load(specs[s], &scene), LT_OK);
    lt_ray *rays = malloc(RAY_COUNT * sizeof *rays);
    lt_hit *ref = malloc(RAY_COUNT * sizeof *ref);
    make_rays(scene, 7 + s, rays);
    assert_int_equal(lt_reference_trace(scene, rays, RAY_COUNT, LT_QUERY_CLOSEST, ref), LT_OK);
    for (int mode = LT_BUILD_FULL; mode <= LT_BUILD_SPECULATIVE; mode++)
      for (size_t l = 0; l < sizeof launches / sizeof launches[0]; l++) {
        if (launches[l].device == LT_DEVICE_OPENCL && !have_opencl) continue;
        char what[128];
        snprintf(what, sizeof what, "%s %s launch %zu", specs[s], lt_build_mode_name((lt_build_mode)mode), l);
        lt_hit *hits = trace_with(scene, &launches[l], (lt_build_mode)mode, rays, RAY_COUNT, LT_QUERY_CLOSEST, NULL);
        assert_int_equal(lt_test_count_mismatches(what, hits, ref, RAY_COUNT), 0);
        lt_hit *any = trace_with(scene, &launches[l], (lt_build_mode)mode, rays, RAY_COUNT, LT_QUERY_ANY, NULL);
        assert_int_equal(lt_test_count_occlusion_mismatches(any, ref, RAY_COUNT), 0);
        free(hits), free(any);
      }
    fprintf(stderr, "%s: %zu triangles: every mode and launch matches the reference\n", specs[s],
            lt_scene_triangle_count(scene));
    free(rays), free(ref);
    lt_scene_destroy(scene);
  }
}

/* Ambient-occlusion rays from the primary hits: short rays in random directions. */
static size_t ao_rays(const lt_scene *scene, const lt_ray *primary, const lt_hit *hits, size_t n, lt_ray *out) {
  uint64_t seed = 5;
  size_t m = 0;
  for (size_t i = 0; i < n; i++) {
    if (hits[i].prim < 0) continue;
    const float *t = lt_scene_triangles(scene) + 9 * (size_t)hits[i].prim;
    float p[3], d[3];
    for (int k = 0; k < 3; k++) {
      p[k] = (1 - hits[i].u - hits[i].v) * t[k] + hits[i].u * t[3 + k] + hits[i].v * t[6 + k];
      d[k] = 2 * lt__splitmix_unit(&seed) - 1;
    }
    (void)primary;
    out[m++] = (lt_ray){{p[0], p[1], p[2]}, 1e-3f, {d[0], d[1], d[2]}, 1.0f};
  }
  return m;
}

/* A primary batch, then an AO batch on the same partial tree: the AO hits equal the
 * reference, and the second batch built more nodes on top of the first's. */
static void ondemand_second_batch_continues_on_the_partial_tree(void **state) {
  (void)state;
  int have_opencl = lt_test_opencl_available();
  lt_scene *scene;
  assert_int_equal(lt_scene_load("house-row:2", &scene), LT_OK);
  size_t n = 64 * 64;
  lt_ray *primary = malloc(n * sizeof *primary), *ao = malloc(n * sizeof *ao);
  lt_hit *hits = malloc(n * sizeof *hits), *ao_hits = malloc(n * sizeof *ao_hits), *ref = malloc(n * sizeof *ref);
  lt_test_camera_rays(scene, "outer", 64, 64, primary);
  for (int b = 0; b < 2; b++) {
    if (b == 1 && !have_opencl) continue;
    lt_context *ctx;
    lt_context_config config = {b == 0 ? LT_DEVICE_NATIVE : LT_DEVICE_OPENCL, 0, 0, 0, 1};
    assert_int_equal(lt_context_create(&config, &ctx), LT_OK);
    lt_structure_config sc = mode_config(LT_BUILD_REQUESTED);
    lt_structure *bvh;
    lt_stats *first, *second;
    lt_stats_create(&first), lt_stats_create(&second);
    assert_int_equal(lt_structure_create(ctx, scene, &sc, first, &bvh), LT_OK);
    assert_int_equal(lt_structure_trace(bvh, primary, n, LT_QUERY_CLOSEST, hits, first), LT_OK);
    size_t m = ao_rays(scene, primary, hits, n, ao);
    assert_true(m > n / 4);
    assert_int_equal(lt_structure_trace(bvh, ao, m, LT_QUERY_CLOSEST, ao_hits, second), LT_OK);
    assert_int_equal(lt_reference_trace(scene, ao, m, LT_QUERY_CLOSEST, ref), LT_OK);
    assert_int_equal(lt_test_count_mismatches("AO after primary", ao_hits, ref, m), 0);
    assert_true(lt_stats_get(second, "nodes_built") > lt_stats_get(first, "nodes_built"));
    assert_true(lt_stats_get(second, "pool.tasks") > 0);
    lt_stats_destroy(first), lt_stats_destroy(second);
    lt_structure_destroy(bvh);
    lt_context_destroy(ctx);
  }
  free(primary), free(ao), free(hits), free(ao_hits), free(ref);
  lt_scene_destroy(scene);
}

/* A tree the pool finished, traced again through the persistent kernel: the same closest hits
 * as the reference, every hit written (the native launch writes the caller's array in place,
 * so it starts out as garbage here), and no node requested. */
static void ondemand_finished_tree_through_the_persistent_kernel(void **state) {
  (void)state;
  int have_opencl = lt_test_opencl_available();
  lt_scene *scene;
  assert_int_equal(lt_scene_load("house-row:2", &scene), LT_OK);
  lt_ray *rays = malloc(RAY_COUNT * sizeof *rays);
  lt_hit *hits = malloc(RAY_COUNT * sizeof *hits), *ref = malloc(RAY_COUNT * sizeof *ref);
  make_rays(scene, 11, rays);
  assert_int_equal(lt_reference_trace(scene, rays, RAY_COUNT, LT_QUERY_CLOSEST, ref), LT_OK);
  for (int b = 0; b < 2; b++) {
    if (b == 1 && !have_opencl) continue;
    lt_context *ctx;
    lt_context_config config = {b == 0 ? LT_DEVICE_NATIVE : LT_DEVICE_OPENCL, 0, 0, 0, 1};
    assert_int_equal(lt_context_create(&config, &ctx), LT_OK);
    lt_structure_config sc = mode_config(LT_BUILD_FULL);
    lt_structure *bvh;
    assert_int_equal(lt_structure_create(ctx, scene, &sc, NULL, &bvh), LT_OK);
    lt_stats *stats;
    lt_stats_create(&stats);
    memset(hits, 0xab, RAY_COUNT * sizeof *hits);
    assert_int_equal(lt__ondemand_launch(lt__structure_ondemand(bvh), rays, RAY_COUNT, LT_QUERY_CLOSEST, hits, 0, stats),
                     LT_OK);
    assert_int_equal(lt_test_count_mismatches("persistent kernel, finished tree", hits, ref, RAY_COUNT), 0);
    assert_true(lt_stats_get(stats, "pool.stalls") == 0);
    lt_stats_destroy(stats);
    lt_structure_destroy(bvh);
    lt_context_destroy(ctx);
  }
  free(rays), free(hits), free(ref);
  lt_scene_destroy(scene);
}

/* Walks the on-demand tree beside the host's full tree: every node built on demand has the
 * full tree's child boxes, and every leaf built holds the same triangles in the same order. */
typedef struct tree_pair {
  const lt__bvh *full;
  const lt_bvh_node *od_nodes;
  const int *od_index;
  int compared_nodes, compared_leaves;
} tree_pair;

static void child_box(const lt_bvh_node *n, int side, float box[6]) {
  const lt_float4 xy = side ? n->right_xy : n->left_xy;
  box[0] = xy.x, box[1] = xy.y, box[2] = xy.z, box[3] = xy.w;
  box[4] = side ? n->lr_z.z : n->lr_z.x, box[5] = side ? n->lr_z.w : n->lr_z.y;
}

static void compare_child(tree_pair *p, const lt_bvh_node *full, const lt_bvh_node *od, int side) {
  int od_link = od->link[side], od_count = od->link[2 + side];
  int full_link = full->link[side], full_count = full->link[2 + side];
  if (od_link <= -2) return; /* not built on demand: nothing to compare */
  float a[6], b[6];
  child_box(full, side, a), child_box(od, side, b);
  assert_memory_equal(a, b, sizeof a);
  assert_int_equal(od_count, full_count);
  if (od_count > 0) {
    for (int i = 0; i < od_count; i++)
      assert_int_equal(p->od_index[od_link + i], lt_float_as_int(p->full->tris[full_link + i].v0.w));
    p->compared_leaves++;
    return;
  }
  if (od_link < 0) return;
  p->compared_nodes++;
  compare_child(p, &p->full->nodes[full_link], &p->od_nodes[od_link], 0);
  compare_child(p, &p->full->nodes[full_link], &p->od_nodes[od_link], 1);
}

static void ondemand_nodes_equal_the_full_tree(void **state) {
  (void)state;
  lt_scene *scene;
  assert_int_equal(lt_scene_load("house", &scene), LT_OK);
  lt__bvh full;
  lt__sah_config sah = lt__sah_config_default();
  assert_int_equal(lt__bvh_build_sah(lt_scene_triangles(scene), lt_scene_triangle_count(scene), &sah, &full), LT_OK);
  int side = getenv("LT_TEST_QUICK") ? 48 : 128;
  size_t n = (size_t)side * side;
  lt_ray *rays = malloc(n * sizeof *rays);
  lt_hit *hits = malloc(n * sizeof *hits);
  lt_test_camera_rays(scene, "close", side, side, rays);
  /* Every mode with the usual bin slabs, then full and speculative without any, so that every
   * large node is split in one go by one work-item (its bins sampled, as the chunks do). */
  for (int run = 0; run < 5; run++) {
    int mode = run < 3 ? run : run == 3 ? LT_BUILD_FULL : LT_BUILD_SPECULATIVE;
    lt__ondemand_slab_count = run < 3 ? 64 : 0;
    lt_context *ctx;
    lt_context_config config = {LT_DEVICE_NATIVE, 2, 1, 0, 1};
    assert_int_equal(lt_context_create(&config, &ctx), LT_OK);
    lt_structure_config sc = mode_config((lt_build_mode)mode);
    lt_structure *bvh;
    assert_int_equal(lt_structure_create(ctx, scene, &sc, NULL, &bvh), LT_OK);
    assert_int_equal(lt_structure_trace(bvh, rays, n, LT_QUERY_CLOSEST, hits, NULL), LT_OK);

    /* The super-root's left child is the scene's root: the full tree's node 0. */
    lt_bvh_node *nodes;
    int count, *index;
    assert_int_equal(lt__ondemand_snapshot(lt__structure_ondemand(bvh), &nodes, &count, &index), LT_OK);
    tree_pair p = {&full, nodes, index, 0, 0};
    /* (Natively a large batch leaves the root's link marked wide: a collapse ran after the
     * batch's sample; the binary nodes under it are the same.) */
    assert_true(nodes[0].link[0] >= 0 && (nodes[0].link[2] == 0 || lt_bvh_child_is_wide(nodes[0].link[2])));
    p.compared_nodes = 1;
    compare_child(&p, &full.nodes[0], &nodes[nodes[0].link[0]], 0);
    compare_child(&p, &full.nodes[0], &nodes[nodes[0].link[0]], 1);
    fprintf(stderr, "%s, %d slabs: %d inner nodes and %d leaves equal the full tree's (full: %d inner)\n",
            lt_build_mode_name((lt_build_mode)mode), lt__ondemand_slab_count, p.compared_nodes, p.compared_leaves,
            full.node_count);
    assert_true(p.compared_nodes > 10);
    if (mode == LT_BUILD_FULL) assert_int_equal(p.compared_nodes, full.node_count);
    free(nodes), free(index);
    lt_structure_destroy(bvh);
    lt_context_destroy(ctx);
  }
  lt__ondemand_slab_count = 64;
  lt__bvh_free(&full);
  free(rays), free(hits);
  lt_scene_destroy(scene);
}

/* A pool of 2 slots fills at once; the structure retries larger and answers correctly (every mode). */
static void ondemand_full_pool_is_retried_larger(void **state) {
  (void)state;
  assert_int_equal(lt_test_small_pool_mismatches(LT_STRUCTURE_BVH), 0);
}

/* Requested builds fewer nodes than speculative, which builds no more than full. */
static void ondemand_builds_only_what_rays_reach(void **state) {
  (void)state;
  lt_scene *scene;
  int quick = getenv("LT_TEST_QUICK") != NULL;
  assert_int_equal(lt_scene_load(quick ? "house-row:2" : "house-row:4", &scene), LT_OK);
  size_t n = 64 * 64;
  lt_ray *rays = malloc(n * sizeof *rays);
  lt_test_camera_rays(scene, "outer", 64, 64, rays);
  double nodes[LT_BUILD_SPECULATIVE + 1];
  for (int mode = LT_BUILD_FULL; mode <= LT_BUILD_SPECULATIVE; mode++) {
    lt_stats *stats;
    lt_stats_create(&stats);
    launch native = {LT_DEVICE_NATIVE, 2, 1};
    free(trace_with(scene, &native, (lt_build_mode)mode, rays, n, LT_QUERY_CLOSEST, stats));
    nodes[mode] = lt_stats_get(stats, "nodes_built");
    lt_stats_destroy(stats);
  }
  fprintf(stderr, "house-row outer, 64x64: nodes built full %.0f, requested %.0f, speculative %.0f\n",
          nodes[LT_BUILD_FULL], nodes[LT_BUILD_REQUESTED], nodes[LT_BUILD_SPECULATIVE]);
  assert_true(nodes[LT_BUILD_REQUESTED] < 0.1 * nodes[LT_BUILD_FULL]);
  assert_true(nodes[LT_BUILD_SPECULATIVE] >= nodes[LT_BUILD_REQUESTED] && nodes[LT_BUILD_SPECULATIVE] <= nodes[LT_BUILD_FULL]);
  free(rays);
  lt_scene_destroy(scene);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(ondemand_nodes_equal_the_full_tree),
      cmocka_unit_test(ondemand_full_pool_is_retried_larger),
      cmocka_unit_test(ondemand_builds_only_what_rays_reach),
      cmocka_unit_test(ondemand_second_batch_continues_on_the_partial_tree),
      cmocka_unit_test(ondemand_finished_tree_through_the_persistent_kernel),
      cmocka_unit_test(ondemand_matches_reference_in_every_mode),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
