/* The LBVH with an SAH top (HLBVH_4) against the brute-force reference: closest hits (prim and
 * t, bitwise) and occlusion from tracing its arrays directly, and the shape of the tree: depth
 * bound, every triangle once in leaf order, exact child boxes, the recorded SAH cost. */
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <cmocka.h>

#include "builders/host/bvh_sah.h"
#include "builders/host/lbvh.h"
#include "device/types.h"
#include "tests/support.h"
#include "traversal/bvh_traverse.h"
#include "traversal/intersect_triangle.h"

#define CAMERA_SIZE 24
#define RANDOM_RAYS 512
#define RAY_COUNT   (2 * CAMERA_SIZE * CAMERA_SIZE + RANDOM_RAYS)

/* ---- Checking the tree ---- */

typedef struct walk {
  const lt__bvh *bvh;
  const float *scene_tris;
  char *seen_prim, *seen_node;
  int next_tri; /* leaves must come in the order of their triangles */
  int leaves, max_depth, largest_leaf;
  double cost;
} walk;

static float area_of(const float lo[3], const float hi[3]) {
  float d[3];
  for (int k = 0; k < 3; k++) d[k] = fmaxf(hi[k] - lo[k], 0.0f);
  return 2.0f * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0]);
}

static void grow(float lo[3], float hi[3], const float p_lo[3], const float p_hi[3]) {
  for (int k = 0; k < 3; k++) {
    lo[k] = fminf(lo[k], p_lo[k]);
    hi[k] = fmaxf(hi[k], p_hi[k]);
  }
}

static void assert_box_equal(const float lo[3], const float hi[3], const float want_lo[3], const float want_hi[3]) {
  assert_memory_equal(lo, want_lo, 3 * sizeof(float));
  assert_memory_equal(hi, want_hi, 3 * sizeof(float));
}

/* Walks the child (link, count) at depth and returns its exact bounds, checking as it goes. */
static void walk_child(walk *w, int link, int count, int depth, float lo[3], float hi[3]) {
  const lt__bvh *bvh = w->bvh;
  for (int k = 0; k < 3; k++) lo[k] = INFINITY, hi[k] = -INFINITY;
  if (depth > w->max_depth) w->max_depth = depth;

  /* An empty child only stands beside the leaf of a one-leaf scene. */
  if (count == 0 && link < 0) {
    assert_int_equal(depth, 1);
    assert_int_equal(bvh->node_count, 1);
    return;
  }

  /* A leaf: the next triangles in order, each a scene triangle seen for the first time. */
  if (count > 0) {
    assert_int_equal(link, w->next_tri);
    assert_true(link + count <= bvh->tri_count);
    for (int i = link; i < link + count; i++) {
      const lt_tri *t = &bvh->tris[i];
      int prim = lt_float_as_int(t->v0.w);
      assert_true(prim >= 0 && prim < bvh->tri_count);
      assert_false(w->seen_prim[prim]);
      w->seen_prim[prim] = 1;
      float v[9] = {t->v0.x, t->v0.y, t->v0.z, t->v1.x, t->v1.y, t->v1.z, t->v2.x, t->v2.y, t->v2.z};
      assert_memory_equal(v, w->scene_tris + 9 * (size_t)prim, sizeof v);
      for (int c = 0; c < 3; c++) grow(lo, hi, v + 3 * c, v + 3 * c);
    }
    w->next_tri += count;
    w->leaves++;
    if (count > w->largest_leaf) w->largest_leaf = count;
    w->cost += (double)count * area_of(lo, hi);
    return;
  }

  /* An inner node, reached once, whose child boxes are exactly its children's bounds. */
  assert_true(link >= 0 && link < bvh->node_count);
  assert_false(w->seen_node[link]);
  w->seen_node[link] = 1;
  const lt_bvh_node *n = &bvh->nodes[link];
  float l_lo[3], l_hi[3], r_lo[3], r_hi[3];
  walk_child(w, n->link[0], n->link[2], depth + 1, l_lo, l_hi);
  walk_child(w, n->link[1], n->link[3], depth + 1, r_lo, r_hi);
  float sl_lo[3] = {n->left_xy.x, n->left_xy.z, n->lr_z.x}, sl_hi[3] = {n->left_xy.y, n->left_xy.w, n->lr_z.y};
  float sr_lo[3] = {n->right_xy.x, n->right_xy.z, n->lr_z.z}, sr_hi[3] = {n->right_xy.y, n->right_xy.w, n->lr_z.w};
  assert_box_equal(sl_lo, sl_hi, l_lo, l_hi);
  if (n->link[3] > 0 || n->link[1] >= 0) assert_box_equal(sr_lo, sr_hi, r_lo, r_hi);
  grow(lo, hi, l_lo, l_hi);
  grow(lo, hi, r_lo, r_hi);
  w->cost += area_of(lo, hi);
}

/* Checks the whole tree; returns the largest leaf. Costs are the default ones (both 1). */
static int check_tree(const lt__bvh *bvh, const float *scene_tris, size_t n, int depth_limit) {
  assert_int_equal(bvh->tri_count, (int)n);
  assert_true(bvh->node_count >= 1 && bvh->node_count <= (int)n);
  walk w = {bvh, scene_tris, calloc(n, 1), calloc(n, 1), 0, 0, 0, 0, 0.0};
  assert_non_null(w.seen_prim);
  assert_non_null(w.seen_node);
  float lo[3], hi[3];
  walk_child(&w, 0, 0, 0, lo, hi);

  /* Every triangle once, every node reached, and the counts the builder reported. */
  assert_int_equal(w.next_tri, (int)n);
  for (size_t i = 0; i < n; i++) assert_true(w.seen_prim[i]);
  for (int i = 0; i < bvh->node_count; i++) assert_true(w.seen_node[i]);
  assert_int_equal(w.leaves, bvh->leaf_count);
  assert_true(w.max_depth < depth_limit);
  assert_true(bvh->max_depth < depth_limit);
  int one_leaf = bvh->nodes[0].link[3] == 0 && bvh->nodes[0].link[1] < 0;
  assert_int_equal(bvh->max_depth, one_leaf ? 0 : w.max_depth);

  /* The SAH cost as bvh_sah.c sums it, where the root added above a one-leaf scene is free. */
  double root_area = area_of(lo, hi);
  if (one_leaf) w.cost -= root_area;
  double cost = root_area > 0.0 ? w.cost / root_area : 0.0;
  assert_true(fabs(cost - bvh->sah_cost) <= 1e-6 * fabs(cost) + 1e-12);
  free(w.seen_prim), free(w.seen_node);
  return w.largest_leaf;
}

/* ---- Tracing the arrays ---- */

/* Through the one traversal body on the host, as the native backend runs it. */
static void trace(const lt__bvh *bvh, const lt_ray *rays, size_t n, int any_hit, lt_hit *hits) {
  lt_bvh_view tree = {.nodes = bvh->nodes, .tris = bvh->tris};
  for (size_t i = 0; i < n; i++) {
    lt_bvh_ray q;
    lt_trace_counters counters = {0, 0};
    lt_bvh_ray_start(&q, (const float *)&rays[i]);
    assert_int_equal(lt_bvh_advance_tris(&tree, &q, any_hit ? LT_QUERY_FLAG_ANY : 0, &counters), 1);
    assert_int_equal(q.overflow, 0);
    lt_hit_record hit = lt_bvh_ray_answer(&q);
    hits[i] = (lt_hit){hit.t, hit.u, hit.v, hit.prim};
  }
}

/* Closest hits bitwise and occlusion against the reference; returns the number of hits. */
static size_t assert_matches_reference(const char *what, const lt_scene *scene, const lt__bvh *bvh, const lt_ray *rays,
                                       size_t n) {
  lt_hit *ref = malloc(n * sizeof *ref), *hits = malloc(n * sizeof *hits);
  assert_non_null(ref);
  assert_non_null(hits);
  assert_int_equal(lt_reference_trace(scene, rays, n, LT_QUERY_CLOSEST, ref), LT_OK);
  trace(bvh, rays, n, 0, hits);
  assert_int_equal(lt_test_count_mismatches(what, hits, ref, n), 0);
  trace(bvh, rays, n, 1, hits);
  assert_int_equal(lt_test_count_occlusion_mismatches(hits, ref, n), 0);
  size_t ref_hits = 0;
  for (size_t i = 0; i < n; i++) ref_hits += ref[i].prim >= 0;
  free(ref), free(hits);
  return ref_hits;
}

static lt_ray *scene_rays(const lt_scene *scene) {
  lt_ray *rays = malloc(RAY_COUNT * sizeof *rays);
  assert_non_null(rays);
  lt_test_camera_rays(scene, "outer", CAMERA_SIZE, CAMERA_SIZE, rays);
  lt_test_camera_rays(scene, "close", CAMERA_SIZE, CAMERA_SIZE, rays + CAMERA_SIZE * CAMERA_SIZE);
  lt_test_random_rays(scene, 7, RANDOM_RAYS, rays + 2 * CAMERA_SIZE * CAMERA_SIZE);
  return rays;
}

/* ---- Tests ---- */

/* Generated scenes of every kind of layout: closed surface, long thin strands, a room, a house. */
static void lbvh_matches_reference_on_generators(void **state) {
  (void)state;
  static const char *const specs[] = {"sphere:4", "hairball:300", "cornell", "house"};
  for (size_t s = 0; s < sizeof specs / sizeof specs[0]; s++) {
    lt_scene *scene;
    assert_int_equal(lt_scene_load(specs[s], &scene), LT_OK);
    size_t n = lt_scene_triangle_count(scene);
    lt__bvh bvh;
    assert_int_equal(lt__bvh_build_lbvh(lt_scene_triangles(scene), n, NULL, &bvh), LT_OK);
    int largest = check_tree(&bvh, lt_scene_triangles(scene), n, LT_BVH_MAX_DEPTH);
    assert_true(largest <= 4); /* nowhere near the depth bound: leaves keep their size */
    assert_true(bvh.sort_ops >= n);

    lt_ray *rays = scene_rays(scene);
    size_t hits = assert_matches_reference(specs[s], scene, &bvh, rays, RAY_COUNT);
    assert_true(hits > RAY_COUNT / 10); /* the rays must actually meet the scene */
    fprintf(stderr, "%s: %zu triangles, %d inner nodes, %d leaves, depth %d, SAH cost %.2f, %zu hits match\n", specs[s],
            n, bvh.node_count, bvh.leaf_count, bvh.max_depth, bvh.sah_cost, hits);
    free(rays);
    lt__bvh_free(&bvh);
    lt_scene_destroy(scene);
  }
}

/* Copies of one triangle: every Morton code is equal, so ranges split at their middle. */
static void lbvh_identical_triangles_share_one_code(void **state) {
  (void)state;
  enum { copies = 1000, rays_n = 256 };
  float *tris = malloc(copies * 9 * sizeof *tris);
  assert_non_null(tris);
  const float tri[9] = {0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f};
  for (int i = 0; i < copies; i++) memcpy(tris + 9 * i, tri, sizeof tri);
  lt_scene *scene;
  assert_int_equal(lt_scene_from_triangles(tris, copies, &scene), LT_OK);
  lt__bvh bvh;
  assert_int_equal(lt__bvh_build_lbvh(tris, copies, NULL, &bvh), LT_OK);
  assert_true(check_tree(&bvh, tris, copies, LT_BVH_MAX_DEPTH) <= 4);
  assert_true(bvh.max_depth <= 10); /* middle splits: balanced */

  /* Rays down onto the plane of the triangles, some of them outside it; ties go to prim 0. */
  lt_ray rays[rays_n];
  uint64_t seed = 5;
  for (int i = 0; i < rays_n; i++) {
    float x = 1.2f * lt__splitmix_unit(&seed) - 0.1f, y = 1.2f * lt__splitmix_unit(&seed) - 0.1f;
    rays[i] = (lt_ray){{x, y, 1.0f}, 0.0f, {0.1f * lt__splitmix_unit(&seed), 0.0f, -1.0f}, INFINITY};
  }
  assert_true(assert_matches_reference("identical", scene, &bvh, rays, rays_n) > rays_n / 5);
  lt__bvh_free(&bvh);
  lt_scene_destroy(scene);
  free(tris);
}

/* One triangle: the root is a leaf beside an empty child, as from the SAH builder. */
static void lbvh_single_triangle_scene(void **state) {
  (void)state;
  const float tri[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  lt_scene *scene;
  assert_int_equal(lt_scene_from_triangles(tri, 1, &scene), LT_OK);
  lt__bvh bvh;
  assert_int_equal(lt__bvh_build_lbvh(tri, 1, NULL, &bvh), LT_OK);
  check_tree(&bvh, tri, 1, LT_BVH_MAX_DEPTH);
  assert_int_equal(bvh.node_count, 1);
  assert_int_equal(bvh.leaf_count, 1);
  assert_int_equal(bvh.nodes[0].link[0], 0);
  assert_int_equal(bvh.nodes[0].link[2], 1);
  assert_true(bvh.nodes[0].link[1] < 0 && bvh.nodes[0].link[3] == 0);

  lt_ray rays[2] = {{{0.25f, 0.25f, -1}, 0, {0, 0, 1}, INFINITY}, {{2, 2, -1}, 0, {0, 0, 1}, INFINITY}};
  lt_hit hits[2];
  trace(&bvh, rays, 2, 0, hits);
  assert_int_equal(hits[0].prim, 0);
  assert_true(hits[0].t == 1.0f);
  assert_int_equal(hits[1].prim, -1);
  assert_int_equal(assert_matches_reference("single", scene, &bvh, rays, 2), 1);
  lt__bvh_free(&bvh);
  lt_scene_destroy(scene);
}

/* A tight depth bound forces leaves of whatever remains, in the top (several clusters in one
 * leaf) and inside clusters; the tree must still be exact and give the reference's hits. */
static void lbvh_depth_bound_forces_big_leaves(void **state) {
  (void)state;
  lt_scene *scene;
  assert_int_equal(lt_scene_load("hairball:300", &scene), LT_OK);
  size_t n = lt_scene_triangle_count(scene);
  lt_ray *rays = scene_rays(scene);
  static const int limits[] = {2, 3, 6, 12, 20};
  for (size_t l = 0; l < sizeof limits / sizeof limits[0]; l++) {
    lt__bvh bvh;
    assert_int_equal(lt__bvh_build_lbvh_limited(lt_scene_triangles(scene), n, NULL, limits[l], &bvh), LT_OK);
    int largest = check_tree(&bvh, lt_scene_triangles(scene), n, limits[l]);
    assert_true(largest > 4);
    char what[64];
    snprintf(what, sizeof what, "hairball depth limit %d", limits[l]);
    assert_matches_reference(what, scene, &bvh, rays, RAY_COUNT);
    lt__bvh_free(&bvh);
  }
  free(rays);
  lt_scene_destroy(scene);
}

/* Arguments are checked before anything is built; NULL config means the defaults. */
static void lbvh_rejects_bad_arguments(void **state) {
  (void)state;
  const float tri[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  lt__bvh bvh;
  lt__sah_config config = lt__sah_config_default();
  assert_int_equal(lt__bvh_build_lbvh(tri, 0, &config, &bvh), LT_ERROR_INVALID_ARGUMENT);
  assert_int_equal(lt__bvh_build_lbvh(NULL, 1, &config, &bvh), LT_ERROR_INVALID_ARGUMENT);
  config.bins = 1;
  assert_int_equal(lt__bvh_build_lbvh(tri, 1, &config, &bvh), LT_ERROR_INVALID_ARGUMENT);
  config = lt__sah_config_default(), config.max_leaf_size = 0;
  assert_int_equal(lt__bvh_build_lbvh(tri, 1, &config, &bvh), LT_ERROR_INVALID_ARGUMENT);
  assert_int_equal(lt__bvh_build_lbvh_limited(tri, 1, NULL, 1, &bvh), LT_ERROR_INVALID_ARGUMENT);
  assert_int_equal(lt__bvh_build_lbvh_limited(tri, 1, NULL, LT_BVH_MAX_DEPTH + 1, &bvh), LT_ERROR_INVALID_ARGUMENT);
  config = lt__sah_config_default(), config.max_leaf_size = 1;
  assert_int_equal(lt__bvh_build_lbvh(tri, 1, &config, &bvh), LT_OK);
  lt__bvh_free(&bvh);
}

/* An executor for the tests: fn on `workers` threads, one of them the caller. */
typedef struct thread_call {
  void (*fn)(void *arg);
  void *arg;
} thread_call;

static void *thread_main(void *p) {
  const thread_call *call = p;
  call->fn(call->arg);
  return NULL;
}

static lt_status run_threads(int workers, void (*fn)(void *arg), void *arg) {
  pthread_t threads[16];
  thread_call call = {fn, arg};
  assert_true(workers >= 1 && workers <= 16);
  for (int t = 1; t < workers; t++) assert_int_equal(pthread_create(&threads[t], NULL, thread_main, &call), 0);
  fn(arg);
  for (int t = 1; t < workers; t++) pthread_join(threads[t], NULL);
  return LT_OK;
}

/* An executor whose threads never start: the build must run its loops on the caller instead. */
static lt_status run_refused(int workers, void (*fn)(void *arg), void *arg) {
  (void)workers, (void)fn, (void)arg;
  return LT_ERROR_OUT_OF_MEMORY;
}

static void assert_same_tree(const lt__bvh *a, const lt__bvh *b) {
  assert_int_equal(a->node_count, b->node_count);
  assert_int_equal(a->tri_count, b->tri_count);
  assert_int_equal(a->leaf_count, b->leaf_count);
  assert_int_equal(a->max_depth, b->max_depth);
  assert_true(a->sort_ops == b->sort_ops);
  assert_true(a->sah_cost == b->sah_cost);
  assert_memory_equal(a->nodes, b->nodes, (size_t)a->node_count * sizeof *a->nodes);
  assert_memory_equal(a->tris, b->tris, (size_t)a->tri_count * sizeof *a->tris);
}

/* The build's loops on several threads (a scene of several sort chunks and many clusters, and
 * one under a tight depth bound) give the serial build's tree node for node, and so the
 * reference's hits; an executor that cannot start its threads falls back to the caller. */
static void lbvh_parallel_build_matches_serial(void **state) {
  (void)state;
  static const char *const specs[] = {"hairball:1000", "house"};
  static const int depth_limits[] = {LT_BVH_MAX_DEPTH, 8};
  for (size_t s = 0; s < sizeof specs / sizeof specs[0]; s++) {
    lt_scene *scene;
    assert_int_equal(lt_scene_load(specs[s], &scene), LT_OK);
    size_t n = lt_scene_triangle_count(scene);
    const float *tris = lt_scene_triangles(scene);
    lt_ray *rays = scene_rays(scene);
    for (int d = 0; d < 2; d++) {
      lt__bvh serial;
      assert_int_equal(lt__bvh_build_lbvh_with(tris, n, NULL, depth_limits[d], NULL, &serial), LT_OK);
      static const int workers[] = {2, 3, 8};
      for (int w = 0; w < 4; w++) {
        lt__executor ex = {w < 3 ? workers[w] : 4, w < 3 ? run_threads : run_refused};
        lt__bvh parallel;
        assert_int_equal(lt__bvh_build_lbvh_with(tris, n, NULL, depth_limits[d], &ex, &parallel), LT_OK);
        assert_same_tree(&parallel, &serial);
        check_tree(&parallel, tris, n, depth_limits[d]);
        lt__bvh_free(&parallel);
      }
      char what[64];
      snprintf(what, sizeof what, "%s depth limit %d", specs[s], depth_limits[d]);
      assert_matches_reference(what, scene, &serial, rays, RAY_COUNT);
      fprintf(stderr, "%s: %zu triangles, depth limit %d: the same tree on 1, 2, 3 and 8 threads\n", specs[s], n,
              depth_limits[d]);
      lt__bvh_free(&serial);
    }
    free(rays);
    lt_scene_destroy(scene);
  }
}

static double seconds(void) {
  struct timespec ts;
  timespec_get(&ts, TIME_UTC);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The point of the baseline: it builds much faster than full SAH, for a tree that costs not
 * much more to trace. Margins are loose, so that sanitizer builds pass too. */
static void lbvh_builds_faster_than_sah(void **state) {
  (void)state;
  lt_scene *scene;
  assert_int_equal(lt_scene_load("sphere:7", &scene), LT_OK);
  size_t n = lt_scene_triangle_count(scene);
  lt__bvh sah, lbvh;
  lt__sah_config config = lt__sah_config_default();
  double t0 = seconds();
  assert_int_equal(lt__bvh_build_sah(lt_scene_triangles(scene), n, &config, &sah), LT_OK);
  double t1 = seconds();
  assert_int_equal(lt__bvh_build_lbvh(lt_scene_triangles(scene), n, &config, &lbvh), LT_OK);
  double t2 = seconds();
  check_tree(&lbvh, lt_scene_triangles(scene), n, LT_BVH_MAX_DEPTH);
  fprintf(stderr, "sphere:7, %zu triangles: SAH %.3f s (cost %.2f), LBVH %.3f s (cost %.2f)\n", n, t1 - t0,
          sah.sah_cost, t2 - t1, lbvh.sah_cost);
  assert_true(t2 - t1 < t1 - t0);
  assert_true(lbvh.sah_cost < 2.0 * sah.sah_cost);
  lt__bvh_free(&sah);
  lt__bvh_free(&lbvh);
  lt_scene_destroy(scene);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(lbvh_rejects_bad_arguments),
      cmocka_unit_test(lbvh_single_triangle_scene),
      cmocka_unit_test(lbvh_identical_triangles_share_one_code),
      cmocka_unit_test(lbvh_matches_reference_on_generators),
      cmocka_unit_test(lbvh_depth_bound_forces_big_leaves),
      cmocka_unit_test(lbvh_parallel_build_matches_serial),
      cmocka_unit_test(lbvh_builds_faster_than_sah),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
