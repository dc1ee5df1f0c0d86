/* The escape-index BVH (device/escape_bvh_node.h): the layout (every triangle once, exact
 * boxes, depth-first order, each escape the first node after its subtree), the stackless
 * traversal on the host, the thesis' Kay-Kajiya and Goldsmith-Salmon builders, and closest and
 * any hits against the brute-force reference on both backends, with every builder, on the
 * generators and on closed meshes that must not leak. LT_TEST_QUICK (the sanitizers) runs the
 * small scenes only. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "builders/host/escape_bvh.h"
#include "runtime/structure_internal.h"
#include "tests/hard_cases.h"
#include "tests/support.h"
#include "traversal/escape_bvh_traverse.h"

/* ---- The layout ---- */

typedef struct walk {
  const lt__escape_bvh *e;
  const lt_tri *tris;
  int tri_count, max_children; /* 2 for a binary tree; any number for Goldsmith-Salmon's */
  char *seen_tri;
  int leaves, max_depth;
} walk;

/* Walks the subtree that starts at node `at`, at `depth`; returns the index after it and puts
 * the exact bounds of its triangles in *bounds. */
static int walk_node(walk *w, int at, int depth, lt_box *bounds) {
  assert_true(at >= 0 && at < w->e->node_count);
  if (depth > w->max_depth) w->max_depth = depth;
  const lt_escape_node *n = &w->e->nodes[at];
  lt_box exact = lt_box_empty();
  int end;
  if (n->count > 0) {
    /* A leaf: triangles seen once; what follows it is the next node. */
    assert_true(n->link >= 0 && n->link + n->count <= w->tri_count);
    for (int i = n->link; i < n->link + n->count; i++) {
      assert_false(w->seen_tri[i]);
      w->seen_tri[i] = 1;
      const lt_tri *t = &w->tris[i];
      float v[9] = {t->v0.x, t->v0.y, t->v0.z, t->v1.x, t->v1.y, t->v1.z, t->v2.x, t->v2.y, t->v2.z};
      for (int c = 0; c < 3; c++) {
        lt_box p = {{v[3 * c], v[3 * c + 1], v[3 * c + 2]}, {v[3 * c], v[3 * c + 1], v[3 * c + 2]}};
        lt_box_grow(&exact, &p);
      }
    }
    w->leaves++;
    end = at + 1;
  } else {
    /* An inner node: its children follow it, one subtree after another, up to its escape. */
    assert_int_equal(n->count, 0);
    assert_true(n->link > at + 1 && n->link <= w->e->node_count);
    int children = 0;
    for (end = at + 1; end < n->link; children++) {
      lt_box child;
      end = walk_node(w, end, depth + 1, &child);
      lt_box_grow(&exact, &child);
    }
    assert_int_equal(end, n->link);
    assert_true(children >= 1 && children <= w->max_children);
  }
  lt_box stored = {{n->lo[0], n->lo[1], n->lo[2]}, {n->hi[0], n->hi[1], n->hi[2]}};
  assert_memory_equal(&stored, &exact, sizeof stored);
  *bounds = exact;
  return end;
}

/* Checks a layout over `tri_count` triangles in leaf order; fails on the first flaw. */
static void check_tree_layout(const lt__escape_bvh *e, const lt_tri *tris, int tri_count, int max_children) {
  walk w = {e, tris, tri_count, max_children, calloc((size_t)tri_count + 1, 1), 0, 0};
  assert_non_null(w.seen_tri);
  int tops = 0;
  for (int at = 0; at < e->node_count; tops++) {
    lt_box b;
    at = walk_node(&w, at, 1, &b);
  }
  assert_true(tops >= 1 && tops <= max_children);
  for (int i = 0; i < tri_count; i++) assert_true(w.seen_tri[i]);
  assert_int_equal(w.leaves, e->leaf_count);
  assert_int_equal(w.max_depth, e->max_depth);
  free(w.seen_tri);
}

/* Checks the layout against its binary tree. */
static void check_layout(const lt__escape_bvh *e, const lt__bvh *bvh) {
  check_tree_layout(e, bvh->tris, bvh->tri_count, 2);
  assert_int_equal(e->leaf_count, bvh->leaf_count);
  /* Every binary node's children, the root left out: 2 * inner - 1 nodes at most. */
  assert_true(e->node_count <= 2 * bvh->node_count);
}

static void build(const lt_scene *scene, lt__bvh *bvh, lt__escape_bvh *e) {
  lt__sah_config sah = lt__sah_config_default();
  assert_int_equal(lt__bvh_build_sah(lt_scene_triangles(scene), lt_scene_triangle_count(scene), &sah, bvh), LT_OK);
  assert_int_equal(lt__escape_bvh_from_bvh(bvh, e), LT_OK);
  check_layout(e, bvh);
}

/* Traces on the host through the traversal the kernels use. */
static void trace_host(const lt__escape_bvh *e, const lt__bvh *bvh, const lt_ray *rays, size_t n, int flags,
                       lt_hit *hits, lt_trace_counters *c) {
  for (size_t i = 0; i < n; i++) {
    const lt_ray *ray = &rays[i];
    lt_ray_setup r = lt_ray_prepare(ray->org[0], ray->org[1], ray->org[2], ray->tmin, ray->dir[0], ray->dir[1],
                                    ray->dir[2], ray->tmax);
    r.flags = flags;
    lt_hit_record hit;
    lt_escape_bvh_traverse(e->nodes, e->node_count, bvh->tris, &r, &hit, c);
    if (hit.prim < 0) hit.t = INFINITY, hit.u = hit.v = 0.0f;
    hits[i] = (lt_hit){hit.t, hit.u, hit.v, hit.prim};
  }
}

/* The layout of every kind of generator: exact, complete, escapes where they belong. */
static void escape_layout_keeps_every_triangle_and_exact_boxes(void **state) {
  (void)state;
  static const char *const specs[] = {"sphere:3", "cornell", "hairball:300", "house", "house-grid:2x2"};
  for (size_t s = 0; s < sizeof specs / sizeof specs[0]; s++) {
    lt_scene *scene;
    assert_int_equal(lt_scene_load(specs[s], &scene), LT_OK);
    lt__bvh bvh;
    lt__escape_bvh e;
    build(scene, &bvh, &e);
    fprintf(stderr, "%s: binary %d inner nodes (%zu bytes), escape-index %d nodes depth %d (%zu bytes)\n", specs[s],
            bvh.node_count, (size_t)bvh.node_count * sizeof(lt_bvh_node), e.node_count, e.max_depth,
            (size_t)e.node_count * sizeof(lt_escape_node));
    lt__escape_bvh_free(&e);
    lt__bvh_free(&bvh);
    lt_scene_destroy(scene);
  }
}

/* The thesis' builders: Kay-Kajiya binary with one triangle a leaf (unless centroids
 * coincide), Goldsmith-Salmon of any number of children, the same tree from the same seed and a
 * cost no worse than one order's; both laid out complete and exact. */
static void escape_thesis_builders_make_complete_exact_trees(void **state) {
  (void)state;
  static const char *const specs[] = {"sphere:3", "cornell", "hairball:300"};
  for (size_t s = 0; s < sizeof specs / sizeof specs[0]; s++) {
    lt_scene *scene;
    assert_int_equal(lt_scene_load(specs[s], &scene), LT_OK);
    const float *tris = lt_scene_triangles(scene);
    size_t n = lt_scene_triangle_count(scene);
    lt__tree kk, gs, again, one;
    assert_int_equal(lt__tree_build_kay_kajiya(tris, n, &kk), LT_OK);
    assert_int_equal(lt__tree_build_goldsmith_salmon(tris, n, 15, 7, &gs), LT_OK);
    assert_int_equal(lt__tree_build_goldsmith_salmon(tris, n, 15, 7, &again), LT_OK);
    assert_int_equal(lt__tree_build_goldsmith_salmon(tris, n, 1, 7, &one), LT_OK);
    assert_int_equal(gs.node_count, again.node_count);
    assert_true(gs.cost == again.cost);
    assert_true(gs.cost <= one.cost);
    const lt__tree *trees[2] = {&kk, &gs};
    for (int t = 0; t < 2; t++) {
      lt__escape_bvh e;
      lt_tri *copy;
      assert_int_equal(lt__escape_bvh_from_tree(trees[t], tris, &e, &copy), LT_OK);
      check_tree_layout(&e, copy, (int)n, t == 0 ? 2 : 1 << 30);
      fprintf(stderr, "%s: %s %d nodes depth %d cost %.1f\n", specs[s], t ? "Goldsmith-Salmon" : "Kay-Kajiya",
              e.node_count, e.max_depth, trees[t]->cost);
      lt__escape_bvh_free(&e);
      free(copy);
    }
    lt__tree_free(&kk), lt__tree_free(&gs), lt__tree_free(&again), lt__tree_free(&one);
    lt_scene_destroy(scene);
  }
}

/* A one-triangle scene: one leaf node; hits, a miss, and a hit beyond tmax. */
static void escape_single_triangle(void **state) {
  (void)state;
  const float tri[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  lt_scene *scene;
  assert_int_equal(lt_scene_from_triangles(tri, 1, &scene), LT_OK);
  lt__bvh bvh;
  lt__escape_bvh e;
  build(scene, &bvh, &e);
  assert_int_equal(e.node_count, 1);
  assert_int_equal(e.nodes[0].count, 1);
  lt_ray rays[3] = {{{0.25f, 0.25f, -1}, 0, {0, 0, 1}, INFINITY},
                    {{2, 2, -1}, 0, {0, 0, 1}, INFINITY},
                    {{0.25f, 0.25f, -1}, 0, {0, 0, 1}, 0.5f}};
  lt_hit hits[3];
  lt_trace_counters c = {0, 0};
  trace_host(&e, &bvh, rays, 3, 0, hits, &c);
  assert_int_equal(hits[0].prim, 0);
  assert_true(hits[0].t == 1.0f);
  assert_int_equal(hits[1].prim, -1);
  assert_int_equal(hits[2].prim, -1);
  assert_int_equal(c.traversal_steps, 3);
  lt__escape_bvh_free(&e);
  lt__bvh_free(&bvh);
  lt_scene_destroy(scene);
}

/* The walk only goes forwards: a ray takes at most one step per node, and a ray that misses
 * the scene's box takes one step per top node. */
static void escape_traversal_visits_each_node_at_most_once(void **state) {
  (void)state;
  lt_scene *scene;
  assert_int_equal(lt_scene_load("hairball:300", &scene), LT_OK);
  lt__bvh bvh;
  lt__escape_bvh e;
  build(scene, &bvh, &e);
  enum { N = 2048 };
  lt_ray *rays = malloc(N * sizeof *rays);
  lt_hit *hits = malloc(N * sizeof *hits);
  assert_non_null(rays);
  assert_non_null(hits);
  lt_test_random_rays(scene, 21, N, rays);
  for (size_t i = 0; i < N; i++) {
    lt_trace_counters c = {0, 0};
    trace_host(&e, &bvh, &rays[i], 1, 0, &hits[i], &c);
    assert_true(c.traversal_steps <= (uint64_t)e.node_count);
  }
  int tops = e.nodes[0].count > 0 ? 1 : e.nodes[0].link < e.node_count ? 2 : 1;
  lt_ray away = {{1.0e6f, 1.0e6f, 1.0e6f}, 0, {1, 0, 0}, INFINITY};
  lt_trace_counters c = {0, 0};
  trace_host(&e, &bvh, &away, 1, 0, hits, &c);
  assert_int_equal(hits[0].prim, -1);
  assert_int_equal(c.traversal_steps, (uint64_t)tops);
  lt__escape_bvh_free(&e);
  lt__bvh_free(&bvh);
  free(rays), free(hits);
  lt_scene_destroy(scene);
}

/* ---- Against the reference, through the library, on both backends ---- */

/* Closest hits bitwise and occlusion against the reference on every backend; returns the hits. */
/* `thesis`: the Kay-Kajiya and Goldsmith-Salmon builders too, not only the SAH one. */
static size_t check_scene(const char *what, const lt_scene *scene, const lt_ray *rays, size_t n, int thesis) {
  lt_hit *ref = malloc(n * sizeof *ref), *ref_any = malloc(n * sizeof *ref_any);
  assert_non_null(ref);
  assert_non_null(ref_any);
  assert_int_equal(lt_reference_trace(scene, rays, n, LT_QUERY_CLOSEST, ref), LT_OK);
  assert_int_equal(lt_reference_trace(scene, rays, n, LT_QUERY_ANY, ref_any), LT_OK);
  lt_structure_config sc = lt_structure_config_default(LT_STRUCTURE_ESCAPE_BVH);
  int last = thesis ? LT_BVH_BUILDER_GOLDSMITH_SALMON : LT_BVH_BUILDER_SAH;
  for (int builder = LT_BVH_BUILDER_SAH; builder <= last; builder++) {
    sc.bvh_builder = builder;
    char label[160];
    snprintf(label, sizeof label, "%s (builder %d)", what, builder);
    assert_int_equal(lt_test_backend_mismatches(label, scene, &sc, rays, n, ref, ref_any), 0);
  }
  size_t hit = 0;
  for (size_t i = 0; i < n; i++) hit += ref[i].prim >= 0;
  free(ref), free(ref_any);
  return hit;
}

/* Every generator, its cameras and random rays. */
static void escape_matches_reference_on_generators(void **state) {
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
    size_t hits = check_scene(specs[s], scene, rays, n, s < 3); /* the thesis' builders on the small ones */
    assert_true(hits > n / 10);
    fprintf(stderr, "%s: %zu rays, %zu hits match the reference\n", specs[s], n, hits);
    free(rays);
    lt_scene_destroy(scene);
  }
}

/* Closed meshes shot from inside, at vertices, edge midpoints and random directions: no ray
 * may leave, and every hit is the reference's. */
static void escape_closed_meshes_never_leak(void **state) {
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
    check_scene(names[m], meshes[m].scene, rays, count, 1);
    lt_test_launch l = {LT_DEVICE_NATIVE, 0, 0};
    lt_structure_config sc = lt_structure_config_default(LT_STRUCTURE_ESCAPE_BVH);
    lt_hit *hits = lt_test_trace_with(meshes[m].scene, &l, &sc, rays, count, LT_QUERY_CLOSEST, NULL);
    assert_non_null(hits);
    assert_int_equal(lt_hc_count_misses(hits, count), 0);
    free(hits);
    lt_hc_free(&meshes[m]);
  }
  free(rays);
}

/* ---- Statistics ---- */

/* The statistics say what the arrays hold: 32 bytes a node, 48 a triangle, the depth. */
static void escape_statistics_describe_the_arrays(void **state) {
  (void)state;
  lt_scene *scene;
  assert_int_equal(lt_scene_load("hairball:300", &scene), LT_OK);
  lt_structure_config sc = lt_structure_config_default(LT_STRUCTURE_ESCAPE_BVH);
  lt_stats *stats;
  assert_int_equal(lt_stats_create(&stats), LT_OK);
  lt_ray rays[64];
  lt_test_random_rays(scene, 3, 64, rays);
  lt_test_launch native = {LT_DEVICE_NATIVE, 0, 0};
  lt_hit *hits = lt_test_trace_with(scene, &native, &sc, rays, 64, LT_QUERY_CLOSEST, stats);
  assert_non_null(hits);
  free(hits);

  lt__bvh bvh;
  lt__escape_bvh e;
  build(scene, &bvh, &e);
  double tris = (double)lt_scene_triangle_count(scene);
  assert_true(lt_stats_get(stats, "node_bytes") == 32.0 * e.node_count);
  assert_true(lt_stats_get(stats, "reference_bytes") == 48.0 * tris);
  assert_true(lt_stats_get(stats, "memory_bytes") == 32.0 * e.node_count + 48.0 * tris);
  assert_true(lt_stats_get(stats, "max_depth") == e.max_depth);
  assert_true(lt_stats_get(stats, "nodes_built") == (double)e.node_count);
  assert_true(lt_stats_get(stats, "build_ms") >= 0);
  assert_true(lt_stats_get(stats, "trace_ms") >= 0);
  assert_true(lt_stats_get(stats, "traversal_steps") > 0);
  assert_true(lt_stats_get(stats, "intersections") > 0);
  lt__escape_bvh_free(&e);
  lt__bvh_free(&bvh);
  lt_stats_destroy(stats);
  lt_scene_destroy(scene);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(escape_layout_keeps_every_triangle_and_exact_boxes),
      cmocka_unit_test(escape_thesis_builders_make_complete_exact_trees),
      cmocka_unit_test(escape_single_triangle),
      cmocka_unit_test(escape_traversal_visits_each_node_at_most_once),
      cmocka_unit_test(escape_matches_reference_on_generators),
      cmocka_unit_test(escape_closed_meshes_never_leak),
      cmocka_unit_test(escape_statistics_describe_the_arrays),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
