/* The QBVH (device/qbvh_node.h): the paper's stack entries, the collapse's tree (every triangle
 * once, exact boxes, siblings together, the depth), the vector box test against the plain C
 * one, and closest and any hits against the brute-force reference on both backends, on the
 * generators and on closed meshes that must not leak. On a CPU with AVX2 the native backend
 * traces the 8-wide tree (tests/test_qbvh8.c); here the native checks run both on that default
 * and with the 4-wide path forced (LT_QBVH_WIDTH=4), the fallback of CPUs without AVX2.
 * LT_TEST_QUICK (the sanitizers) runs the small scenes only. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "builders/host/qbvh_collapse.h"
#include "runtime/structure_internal.h"
#include "tests/hard_cases.h"
#include "tests/support.h"
#include "traversal/qbvh_traverse.h"

/* ---- The stack entry ---- */

/* Lanes pushed as the traversal pushes them come back in order, and the entry goes after the
 * last one; the node index keeps all its 26 bits. */
static void qbvh_stack_entry_pops_lanes_in_order(void **state) {
  (void)state;
  const int groups[][3] = {{1, 1, 1}, {3, 0, 0}, {2, 3, 3}, {0, 2, 2}, {3, 1, 2}, {1, 2, 0}, {0, 3, 1}};
  const int lengths[] = {1, 1, 2, 2, 3, 3, 3};
  const lt_i32 nodes[] = {0, 1, 12345, LT_QBVH_MAX_NODES - 1};
  for (size_t g = 0; g < sizeof lengths / sizeof lengths[0]; g++)
    for (size_t k = 0; k < sizeof nodes / sizeof nodes[0]; k++) {
      const int *o = groups[g];
      lt_u32 stack[3] = {7u, 0u, 0u};
      lt_i32 sp = 2;
      stack[1] = lt_qbvh_entry(nodes[k], o[0], lengths[g] > 1 ? o[1] : o[0], lengths[g] > 2 ? o[2] : lengths[g] > 1 ? o[1] : o[0]);
      for (int i = 0; i < lengths[g]; i++) {
        assert_int_equal(sp, 2);
        assert_int_equal(lt_qbvh_entry_pop(stack, &sp), nodes[k] * 4 + o[i]);
      }
      assert_int_equal(sp, 1);
      assert_int_equal(stack[0], 7u);
    }
}

/* ---- The collapsed tree ---- */

typedef struct walk {
  const lt__qbvh *q;
  const lt__bvh *bvh;
  char *seen_tri, *seen_node;
  int leaves, max_depth;
} walk;

/* Walks node `at` at `depth`; returns the bounds of its children. */
static lt_box walk_node(walk *w, int at, int depth) {
  assert_true(at >= 0 && at < w->q->node_count);
  assert_false(w->seen_node[at]);
  w->seen_node[at] = 1;
  if (depth > w->max_depth) w->max_depth = depth;
  const lt_qbvh_node *n = &w->q->nodes[at];
  lt_box all = lt_box_empty();
  int lanes = 0;
  for (int lane = 0; lane < 4; lane++) {
    lt_box stored;
    lt_qbvh_child_box(n, lane, stored.lo, stored.hi);
    int first = n->first[lane], count = n->count[lane];
    lt_box exact = lt_box_empty();
    if (count == 0) continue;
    assert_int_equal(lane, lanes); /* siblings are the first lanes, together */
    lanes++;
    if (count > 0) {
      /* A leaf: triangles seen once, and its box their exact bounds. */
      assert_true(first >= 0 && first + count <= w->bvh->tri_count);
      for (int i = first; i < first + count; i++) {
        assert_false(w->seen_tri[i]);
        w->seen_tri[i] = 1;
        const lt_tri *t = &w->bvh->tris[i];
        float v[9] = {t->v0.x, t->v0.y, t->v0.z, t->v1.x, t->v1.y, t->v1.z, t->v2.x, t->v2.y, t->v2.z};
        for (int c = 0; c < 3; c++) {
          lt_box p = {{v[3 * c], v[3 * c + 1], v[3 * c + 2]}, {v[3 * c], v[3 * c + 1], v[3 * c + 2]}};
          lt_box_grow(&exact, &p);
        }
      }
      w->leaves++;
    } else {
      /* An inner child: its children's node says as many lanes as its count. */
      assert_true(count >= -4 && count <= -2);
      const lt_qbvh_node *below = &w->q->nodes[first];
      int used = 0;
      for (int l = 0; l < 4; l++) used += below->count[l] != 0;
      assert_int_equal(used, -count);
      exact = walk_node(w, first, depth + 1);
    }
    assert_memory_equal(&stored, &exact, sizeof stored);
    lt_box_grow(&all, &exact);
  }
  assert_true(lanes >= 1);
  return all;
}

/* Checks the tree against its binary one; returns nothing, fails on the first flaw. */
static void check_qbvh(const lt__qbvh *q, const lt__bvh *bvh) {
  walk w = {q, bvh, calloc((size_t)bvh->tri_count, 1), calloc((size_t)q->node_count, 1), 0, 0};
  assert_non_null(w.seen_tri);
  assert_non_null(w.seen_node);
  walk_node(&w, 0, 1);
  for (int i = 0; i < bvh->tri_count; i++) assert_true(w.seen_tri[i]);
  for (int i = 0; i < q->node_count; i++) assert_true(w.seen_node[i]);
  assert_int_equal(w.leaves, bvh->leaf_count);
  assert_int_equal(w.leaves, q->leaf_count);
  assert_int_equal(w.max_depth, q->max_depth);
  /* Never deeper than the binary tree, and about half as deep. */
  assert_true(q->max_depth <= (bvh->max_depth > 0 ? bvh->max_depth : 1));
  assert_true(q->node_count <= bvh->node_count);
  free(w.seen_tri), free(w.seen_node);
}

static void build(const lt_scene *scene, lt__bvh *bvh, lt__qbvh *q) {
  lt__sah_config sah = lt__sah_config_default();
  assert_int_equal(lt__bvh_build_sah(lt_scene_triangles(scene), lt_scene_triangle_count(scene), &sah, bvh), LT_OK);
  assert_int_equal(lt__qbvh_collapse(bvh, LT_QBVH_MAX_NODES, q), LT_OK);
  check_qbvh(q, bvh);
}

/* Traces on the host with the vector or the plain box test. */
static void trace_host(const lt__qbvh *q, const lt__bvh *bvh, const lt_ray *rays, size_t n, int flags, int plain,
                       lt_hit *hits, lt_trace_counters *c, lt_i32 *deepest) {
  for (size_t i = 0; i < n; i++) {
    const lt_ray *ray = &rays[i];
    lt_ray_setup r = lt_ray_prepare(ray->org[0], ray->org[1], ray->org[2], ray->tmin, ray->dir[0], ray->dir[1],
                                    ray->dir[2], ray->tmax);
    r.flags = flags;
    lt_hit_record hit;
    int status = plain ? lt_qbvh_traverse_scalar(q->nodes, bvh->tris, &r, &hit, c, deepest)
                       : lt_qbvh_traverse(q->nodes, bvh->tris, &r, &hit, c, deepest);
    assert_int_equal(status, 0);
    if (hit.prim < 0) hit.t = INFINITY, hit.u = hit.v = 0.0f;
    hits[i] = (lt_hit){hit.t, hit.u, hit.v, hit.prim};
  }
}

/* The tree of every kind of generator: exact, complete, shallower than the binary one. */
static void qbvh_collapse_keeps_every_triangle_and_exact_boxes(void **state) {
  (void)state;
  static const char *const specs[] = {"sphere:3", "cornell", "hairball:300", "house"};
  for (size_t s = 0; s < sizeof specs / sizeof specs[0]; s++) {
    lt_scene *scene;
    assert_int_equal(lt_scene_load(specs[s], &scene), LT_OK);
    lt__bvh bvh;
    lt__qbvh q;
    build(scene, &bvh, &q);
    assert_int_equal(lt__qbvh_count_nodes(&bvh), q.node_count);
    fprintf(stderr, "%s: binary %d nodes depth %d (%zu bytes), QBVH %d nodes depth %d (%zu bytes)\n", specs[s],
            bvh.node_count, bvh.max_depth, (size_t)bvh.node_count * sizeof(lt_bvh_node), q.node_count, q.max_depth,
            (size_t)q.node_count * sizeof(lt_qbvh_node));
    lt__qbvh_free(&q);
    lt__bvh_free(&bvh);
    lt_scene_destroy(scene);
  }
}

/* A one-triangle scene: node 0 holds one leaf beside three empty lanes. */
static void qbvh_single_triangle(void **state) {
  (void)state;
  const float tri[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  lt_scene *scene;
  assert_int_equal(lt_scene_from_triangles(tri, 1, &scene), LT_OK);
  lt__bvh bvh;
  lt__qbvh q;
  build(scene, &bvh, &q);
  assert_int_equal(q.node_count, 1);
  assert_int_equal(q.nodes[0].count[0], 1);
  for (int lane = 1; lane < 4; lane++) assert_int_equal(q.nodes[0].count[lane], 0);
  lt_ray rays[3] = {{{0.25f, 0.25f, -1}, 0, {0, 0, 1}, INFINITY},
                    {{2, 2, -1}, 0, {0, 0, 1}, INFINITY},
                    {{0.25f, 0.25f, -1}, 0, {0, 0, 1}, 0.5f}};
  lt_hit hits[3];
  lt_trace_counters c = {0, 0};
  lt_i32 deepest = 0;
  trace_host(&q, &bvh, rays, 3, 0, 0, hits, &c, &deepest);
  assert_int_equal(hits[0].prim, 0);
  assert_true(hits[0].t == 1.0f);
  assert_int_equal(hits[1].prim, -1);
  assert_int_equal(hits[2].prim, -1);
  assert_int_equal(deepest, 0);
  lt__qbvh_free(&q);
  lt__bvh_free(&bvh);
  lt_scene_destroy(scene);
}

/* ---- The vector test and the plain one ---- */

/* Rays with +0 and -0 components, axis-aligned and diagonal, from inside a cube of shared
 * edges, and random ones: both box tests give every node the same mask and entry distances,
 * and the traversals the same hits, counters and stack depth. */
static void qbvh_vector_and_plain_box_tests_agree(void **state) {
  (void)state;
  lt_hc_mesh cube = lt_hc_cube(8, 9);
  lt_scene *hair;
  assert_int_equal(lt_scene_load("hairball:300", &hair), LT_OK);
  const lt_scene *scenes[2] = {cube.scene, hair};
  enum { N = 4096 };
  lt_ray *rays = malloc(N * sizeof *rays);
  lt_hit *a = malloc(N * sizeof *a), *b = malloc(N * sizeof *b);
  assert_non_null(rays);
  for (int s = 0; s < 2; s++) {
    lt_test_random_rays(scenes[s], 11 + (uint64_t)s, N, rays);
    /* A quarter of the rays along axes and diagonals, zero components signed both ways. */
    for (size_t i = 0; i < N / 4; i++) {
      int d = (int)(i % 26), code = d < 13 ? d : d + 1;
      for (int k = 0; k < 3; k++) {
        int comp = (code / (k == 0 ? 1 : k == 1 ? 3 : 9)) % 3 - 1;
        rays[i].dir[k] = comp ? (float)comp : ((i / 26) & (1u << k) ? -0.0f : 0.0f);
      }
    }
    lt__bvh bvh;
    lt__qbvh q;
    build(scenes[s], &bvh, &q);

    /* Node by node. */
    size_t lanes_hit = 0;
    for (size_t i = 0; i < N; i += 7) {
      lt_ray_setup r = lt_ray_prepare(rays[i].org[0], rays[i].org[1], rays[i].org[2], rays[i].tmin, rays[i].dir[0],
                                      rays[i].dir[1], rays[i].dir[2], rays[i].tmax);
      lt_qbvh_ray4 r4 = lt_qbvh_ray4_make(&r);
      for (int node = 0; node < q.node_count; node++) {
        float tv[4], tp[4], tmax = (i % 3 == 0) ? 0.5f : INFINITY;
        int mv = lt_qbvh_box4(&r, &r4, &q.nodes[node], tmax, tv);
        int mp = lt_qbvh_box4_scalar(&r, &q.nodes[node], tmax, tp);
        assert_int_equal(mv, mp);
        for (int lane = 0; lane < 4; lane++)
          if (mv >> lane & 1) assert_memory_equal(&tv[lane], &tp[lane], sizeof(float)), lanes_hit++;
      }
    }
    assert_true(lanes_hit > 0);

    /* Whole traversals, closest and any hit. */
    for (int flags = 0; flags <= LT_QUERY_FLAG_ANY; flags++) {
      lt_trace_counters cv = {0, 0}, cp = {0, 0};
      lt_i32 dv = 0, dp = 0;
      trace_host(&q, &bvh, rays, N, flags, 0, a, &cv, &dv);
      trace_host(&q, &bvh, rays, N, flags, 1, b, &cp, &dp);
      assert_memory_equal(a, b, N * sizeof *a);
      assert_int_equal(cv.traversal_steps, cp.traversal_steps);
      assert_int_equal(cv.intersections, cp.intersections);
      assert_int_equal(dv, dp);
    }
    lt__qbvh_free(&q);
    lt__bvh_free(&bvh);
  }
  free(rays), free(a), free(b);
  lt_scene_destroy(hair);
  lt_hc_free(&cube);
}

/* ---- Against the reference, through the library, on both backends ---- */

/* Closest-hit and occlusion mismatches against the reference on the native backend with the
 * 4-wide path forced, as on a CPU without AVX2. */
static size_t native_fallback_mismatches(const char *what, const lt_scene *scene, const lt_structure_config *sc,
                                         const lt_ray *rays, size_t n, const lt_hit *ref, const lt_hit *ref_any) {
  lt_test_launch native = {LT_DEVICE_NATIVE, 0, 0};
  char label[160];
  snprintf(label, sizeof label, "%s on native, 4 wide", what);
  size_t mismatches = 0;
  setenv("LT_QBVH_WIDTH", "4", 1);
  for (int query = LT_QUERY_CLOSEST; query <= LT_QUERY_ANY; query++) {
    lt_hit *hits = lt_test_trace_with(scene, &native, sc, rays, n, query, NULL);
    assert_non_null(hits);
    mismatches += query == LT_QUERY_CLOSEST ? lt_test_count_mismatches(label, hits, ref, n)
                                            : lt_test_count_occlusion_mismatches(hits, ref_any, n);
    free(hits);
  }
  unsetenv("LT_QBVH_WIDTH");
  return mismatches;
}

/* Closest hits bitwise and occlusion against the reference on every backend and both native
 * widths; returns the hits. */
static size_t check_scene(const char *what, const lt_scene *scene, const lt_ray *rays, size_t n) {
  lt_hit *ref = malloc(n * sizeof *ref), *ref_any = malloc(n * sizeof *ref_any);
  assert_non_null(ref);
  assert_non_null(ref_any);
  assert_int_equal(lt_reference_trace(scene, rays, n, LT_QUERY_CLOSEST, ref), LT_OK);
  assert_int_equal(lt_reference_trace(scene, rays, n, LT_QUERY_ANY, ref_any), LT_OK);
  lt_structure_config sc = lt_structure_config_default(LT_STRUCTURE_QBVH);
  assert_int_equal(lt_test_backend_mismatches(what, scene, &sc, rays, n, ref, ref_any), 0);
  assert_int_equal(native_fallback_mismatches(what, scene, &sc, rays, n, ref, ref_any), 0);
  size_t hit = 0;
  for (size_t i = 0; i < n; i++) hit += ref[i].prim >= 0;
  free(ref), free(ref_any);
  return hit;
}

/* Any-hit guesses on the native 8-wide trace (traversal/bvh8_guess.h): a house's AO rays in pixel
 * order, with guesses on and off (LT_BVH_GUESSES=0). Occlusion equals brute force's both ways, every
 * answer lies within [tmin, tmax], and the guesses spare node visits. */
static void qbvh_any_hit_guesses_keep_occlusion(void **state) {
  (void)state;
  lt_scene *scene;
  assert_int_equal(lt_scene_load("house-grid:2x2", &scene), LT_OK);
  size_t m;
  lt_ray *primary = malloc(48 * 48 * sizeof *primary), *ao = lt_test_ao_rays(scene, 48, primary, &m);
  assert_non_null(ao);
  lt_hit *ref = malloc(m * sizeof *ref);
  assert_int_equal(lt_reference_trace(scene, ao, m, LT_QUERY_ANY, ref), LT_OK);
  lt_structure_config sc = lt_structure_config_default(LT_STRUCTURE_QBVH);
  lt_test_launch native = {LT_DEVICE_NATIVE, 0, 0};
  double steps[2];
  for (int off = 0; off < 2; off++) {
    if (off) setenv("LT_BVH_GUESSES", "0", 1);
    lt_stats *stats;
    lt_stats_create(&stats);
    lt_hit *hits = lt_test_trace_with(scene, &native, &sc, ao, m, LT_QUERY_ANY, stats);
    assert_non_null(hits);
    assert_int_equal(lt_test_count_occlusion_mismatches(hits, ref, m), 0);
    for (size_t i = 0; i < m; i++)
      if (hits[i].prim >= 0) assert_true(hits[i].t >= ao[i].tmin && hits[i].t <= ao[i].tmax);
    steps[off] = lt_stats_get(stats, "traversal_steps");
    free(hits);
    lt_stats_destroy(stats);
    unsetenv("LT_BVH_GUESSES");
  }
  fprintf(stderr, "house-grid:2x2 AO rays: %.2f node visits a ray with guesses, %.2f without\n", steps[0] / (double)m,
          steps[1] / (double)m);
#if defined(__x86_64__)
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx2")) assert_true(steps[0] < 0.9 * steps[1]); /* the 8-wide path guesses */
#endif
  free(primary), free(ao), free(ref);
  lt_scene_destroy(scene);
}

/* Every generator, its cameras and random rays. */
static void qbvh_matches_reference_on_generators(void **state) {
  (void)state;
  static const char *const specs[] = {"sphere:2", "cornell", "hairball:300", "house", "sphere:5", "house-row:2",
                                      "teapot-stadium"};
  int quick = getenv("LT_TEST_QUICK") != NULL, side = quick ? 16 : 40;
  size_t count = quick ? 4 : sizeof specs / sizeof specs[0], random = quick ? 256 : 2048;
  for (size_t s = 0; s < count; s++) {
    lt_scene *scene;
    assert_int_equal(lt_scene_load(specs[s], &scene), LT_OK);
    size_t n;
    lt_ray *rays = lt_test_generator_rays(scene, side, random, 5 + s, &n);
    assert_non_null(rays);
    size_t hits = check_scene(specs[s], scene, rays, n);
    assert_true(hits > n / 10);
    fprintf(stderr, "%s: %zu rays, %zu hits match the reference\n", specs[s], n, hits);
    free(rays);
    lt_scene_destroy(scene);
  }
}

/* Closed meshes shot from inside, at vertices, edge midpoints and random directions: no ray
 * may leave, and every hit is the reference's. */
static void qbvh_closed_meshes_never_leak(void **state) {
  (void)state;
  int quick = getenv("LT_TEST_QUICK") != NULL;
  lt_hc_mesh meshes[4] = {lt_hc_sphere(quick ? 3 : 5, 3), lt_hc_torus(48, 24), lt_hc_cube(16, 5), {0}};
  meshes[3] = lt_hc_transform(&meshes[0], 1000.0f, 1.0e6f);
  const char *names[4] = {"sphere", "torus 48x24", "cube of shared edges 16x16", "sphere far away and large"};
  size_t n = quick ? 1000 : 4000;
  lt_ray *rays = malloc(n * sizeof *rays);
  assert_non_null(rays);
  for (int m = 0; m < 4; m++) {
    size_t count = lt_hc_closed_rays(&meshes[m], 17, n, rays);
    check_scene(names[m], meshes[m].scene, rays, count);
    lt_test_launch l = {LT_DEVICE_NATIVE, 0, 0};
    lt_structure_config sc = lt_structure_config_default(LT_STRUCTURE_QBVH);
    for (int forced = 0; forced < 2; forced++) {
      /* The default native path (8 wide with AVX2), then the 4-wide fallback. */
      if (forced) setenv("LT_QBVH_WIDTH", "4", 1);
      lt_hit *hits = lt_test_trace_with(meshes[m].scene, &l, &sc, rays, count, LT_QUERY_CLOSEST, NULL);
      unsetenv("LT_QBVH_WIDTH");
      assert_non_null(hits);
      assert_int_equal(lt_hc_count_misses(hits, count), 0);
      free(hits);
    }
    lt_hc_free(&meshes[m]);
  }
  free(rays);
}

/* ---- Limits and statistics ---- */

/* A tree that needs more nodes than the stack entries can name is refused with a sentence
 * that says why and what to use instead; the real bound is 2^26, lowered here. */
static void qbvh_refuses_trees_beyond_its_stack_entries(void **state) {
  (void)state;
  lt_scene *scene;
  assert_int_equal(lt_scene_load("sphere:3", &scene), LT_OK);
  lt_context *ctx;
  lt_context_config cc = {LT_DEVICE_NATIVE, 0, 0, 0, 1};
  assert_int_equal(lt_context_create(&cc, &ctx), LT_OK);
  lt_structure_config sc = lt_structure_config_default(LT_STRUCTURE_QBVH);
  lt_structure *s;
  lt__structure_qbvh_max_nodes = 8;
  assert_int_equal(lt_structure_create(ctx, scene, &sc, NULL, &s), LT_ERROR_UNSUPPORTED);
  lt__structure_qbvh_max_nodes = LT_QBVH_MAX_NODES;
  assert_non_null(strstr(lt_last_error(), "26 bits"));
  assert_non_null(strstr(lt_last_error(), "--structure bvh"));
  assert_int_equal(lt_structure_create(ctx, scene, &sc, NULL, &s), LT_OK);
  lt_structure_destroy(s);
  lt_context_destroy(ctx);
  lt_scene_destroy(scene);
}

/* The statistics say what the arrays hold: 128 bytes a node, 48 a triangle, the depth (the
 * 4-wide path; tests/test_qbvh8.c checks the 8-wide one's). */
static void qbvh_statistics_describe_the_arrays(void **state) {
  (void)state;
  lt_scene *scene;
  assert_int_equal(lt_scene_load("hairball:300", &scene), LT_OK);
  lt_structure_config sc = lt_structure_config_default(LT_STRUCTURE_QBVH);
  lt_stats *stats;
  assert_int_equal(lt_stats_create(&stats), LT_OK);
  lt_ray rays[64];
  lt_test_random_rays(scene, 3, 64, rays);
  lt_test_launch native = {LT_DEVICE_NATIVE, 0, 0};
  setenv("LT_QBVH_WIDTH", "4", 1);
  lt_hit *hits = lt_test_trace_with(scene, &native, &sc, rays, 64, LT_QUERY_CLOSEST, stats);
  unsetenv("LT_QBVH_WIDTH");
  assert_non_null(hits);
  free(hits);

  lt__bvh bvh;
  lt__qbvh q;
  build(scene, &bvh, &q);
  double tris = (double)lt_scene_triangle_count(scene);
  assert_true(lt_stats_get(stats, "node_bytes") == 128.0 * q.node_count);
  assert_true(lt_stats_get(stats, "reference_bytes") == 48.0 * tris);
  assert_true(lt_stats_get(stats, "memory_bytes") == 128.0 * q.node_count + 48.0 * tris);
  assert_true(lt_stats_get(stats, "max_depth") == q.max_depth);
  assert_true(lt_stats_get(stats, "nodes_built") == (double)q.node_count + q.leaf_count);
  assert_true(lt_stats_get(stats, "traversal_steps") > 0);
  lt__qbvh_free(&q);
  lt__bvh_free(&bvh);
  lt_stats_destroy(stats);
  lt_scene_destroy(scene);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(qbvh_stack_entry_pops_lanes_in_order),
      cmocka_unit_test(qbvh_collapse_keeps_every_triangle_and_exact_boxes),
      cmocka_unit_test(qbvh_single_triangle),
      cmocka_unit_test(qbvh_vector_and_plain_box_tests_agree),
      cmocka_unit_test(qbvh_matches_reference_on_generators),
      cmocka_unit_test(qbvh_closed_meshes_never_leak),
      cmocka_unit_test(qbvh_refuses_trees_beyond_its_stack_entries),
      cmocka_unit_test(qbvh_statistics_describe_the_arrays),
      cmocka_unit_test(qbvh_any_hit_guesses_keep_occlusion),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
