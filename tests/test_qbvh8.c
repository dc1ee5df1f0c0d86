/* The QBVH's native 8-wide path (device/bvh8_node.h, traversal/bvh8_traverse.h): the
 * collapse's tree (every triangle once, padded leaves and their blocks, exact boxes, siblings
 * together, the depth), the AVX2 box test against the plain per-lane one, the four-triangle
 * watertight test against the one-triangle test (hard cases), the kernel's ray setup against
 * lt_ray_prepare, whole traversals against the 4-wide QBVH's hits bit for bit, and which
 * path the library takes (AVX2 or LT_QBVH_WIDTH=4). Hits against the brute-force reference
 * through the library, on every generator and the closed meshes, are tests/test_qbvh.c's (the
 * native default is this path). Tests that need AVX2 skip without it. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#if !defined(__x86_64__)
/* The 8-wide path is the x86 native backend's: elsewhere there is nothing to test. */
int main(void) { return 0; }
#else

#include "builders/host/bvh8_collapse.h"
#include "builders/host/qbvh_collapse.h"
#include "tests/hard_cases.h"
#include "tests/support.h"
#include "traversal/bvh8_traverse.h"
#include "traversal/qbvh_traverse.h"

/* ---- The collapsed tree ---- */

typedef struct walk {
  const lt__bvh8 *w8;
  const lt__bvh *bvh;
  const float *verts; /* the scene's triangles, 9 floats each */
  char *seen_tri, *seen_node;
  int leaves, max_depth;
  int tris; /* triangles of the leaves walked so far */
} walk;

/* Walks node `at` at `depth`; returns the bounds of its children. */
static lt_box walk_node(walk *w, int at, int depth) {
  assert_true(at >= 0 && at < w->w8->node_count);
  assert_false(w->seen_node[at]);
  w->seen_node[at] = 1;
  if (depth > w->max_depth) w->max_depth = depth;
  const lt_bvh8_node *n = &w->w8->nodes[at];
  lt_box all = lt_box_empty();
  int lanes = 0;
  for (int lane = 0; lane < LT_BVH8_WIDTH; lane++) {
    lt_box stored, exact = lt_box_empty();
    lt_bvh8_child_box(n, lane, stored.lo, stored.hi);
    int first = n->first[lane], count = n->count[lane];
    if (count == 0) {
      lt_box far = LT_BVH8_EMPTY_LANE_BOX; /* an empty lane has the far point box */
      assert_memory_equal(&stored, &far, sizeof stored);
      continue;
    }
    assert_int_equal(lane, lanes); /* siblings are the first lanes, together */
    lanes++;
    if (count > 0) {
      /* A leaf: in the tree's own blocks, within one block if it has at most four triangles,
       * else from a block's start; each scene triangle seen once, its block lane that
       * triangle's vertices; its box the triangles' exact bounds. */
      assert_true(first >= 0 && first + count <= w->w8->tri_slots);
      assert_true(count <= 4 ? first / 4 == (first + count - 1) / 4 : first % 4 == 0);
      for (int i = first; i < first + count; i++) {
        const lt_tri4 *b = &w->w8->blocks[i / 4];
        int prim = b->prim[i % 4];
        assert_true(prim >= 0 && prim < w->bvh->tri_count);
        assert_false(w->seen_tri[prim]);
        w->seen_tri[prim] = 1;
        for (int c = 0; c < 3; c++) {
          const float *xyz = w->verts + 9 * (size_t)prim + 3 * c;
          for (int k = 0; k < 3; k++) assert_memory_equal(&b->v[3 * c + k][i % 4], &xyz[k], sizeof(float));
          lt_box p = {{xyz[0], xyz[1], xyz[2]}, {xyz[0], xyz[1], xyz[2]}};
          lt_box_grow(&exact, &p);
        }
      }
      w->leaves++;
      w->tris += count;
    } else {
      /* An inner child: its children's node uses as many lanes as its count says. */
      assert_true(count >= -LT_BVH8_WIDTH && count <= -2);
      int used = 0;
      for (int l = 0; l < LT_BVH8_WIDTH; l++) used += w->w8->nodes[first].count[l] != 0;
      assert_int_equal(used, -count);
      exact = walk_node(w, first, depth + 1);
    }
    assert_memory_equal(&stored, &exact, sizeof stored);
    lt_box_grow(&all, &exact);
  }
  assert_true(lanes >= 1);
  return all;
}

static void build_with(const lt_scene *scene, float traversal_cost, lt__bvh *bvh, lt__bvh8 *w8) {
  lt__sah_config sah = lt__sah_config_default();
  sah.traversal_cost = traversal_cost;
  assert_int_equal(lt__bvh_build_sah(lt_scene_triangles(scene), lt_scene_triangle_count(scene), &sah, bvh), LT_OK);
  assert_int_equal(lt__bvh8_collapse(bvh, w8), LT_OK);
  walk w = {w8, bvh, lt_scene_triangles(scene), calloc((size_t)bvh->tri_count, 1), calloc((size_t)w8->node_count, 1),
            0, 0, 0};
  assert_non_null(w.seen_tri);
  assert_non_null(w.seen_node);
  walk_node(&w, 0, 1);
  for (int i = 0; i < bvh->tri_count; i++) assert_true(w.seen_tri[i]);
  for (int i = 0; i < w8->node_count; i++) assert_true(w.seen_node[i]);
  assert_int_equal(w.tris, bvh->tri_count);
  assert_int_equal(w.leaves, bvh->leaf_count);
  assert_int_equal(w.leaves, w8->leaf_count);
  assert_int_equal(w.max_depth, w8->max_depth);
  assert_true(w8->max_depth <= (bvh->max_depth > 0 ? bvh->max_depth : 1));
  free(w.seen_tri), free(w.seen_node);
}

static void build(const lt_scene *scene, lt__bvh *bvh, lt__bvh8 *w8) { build_with(scene, 1.0f, bvh, w8); }

/* Triangles in leaves of more than one block of four. */
static int multi_block_triangles(const lt__bvh8 *w8) {
  int n = 0;
  for (int i = 0; i < w8->node_count; i++)
    for (int lane = 0; lane < LT_BVH8_WIDTH; lane++)
      if (w8->nodes[i].count[lane] > 4) n += w8->nodes[i].count[lane];
  return n;
}

/* The tree of every kind of generator: exact, complete, shallower than the 4-wide one. */
static void qbvh8_collapse_keeps_every_triangle_and_exact_boxes(void **state) {
  (void)state;
  static const char *const specs[] = {"sphere:3", "cornell", "hairball:300", "house"};
  for (size_t s = 0; s < sizeof specs / sizeof specs[0]; s++) {
    lt_scene *scene;
    assert_int_equal(lt_scene_load(specs[s], &scene), LT_OK);
    lt__bvh bvh;
    lt__bvh8 w8;
    build(scene, &bvh, &w8);
    lt__qbvh q;
    assert_int_equal(lt__qbvh_collapse(&bvh, LT_QBVH_MAX_NODES, &q), LT_OK);
    assert_true(w8.max_depth <= q.max_depth);
    assert_true(w8.node_count <= q.node_count);
    fprintf(stderr, "%s: QBVH %d nodes depth %d (%zu bytes), 8 wide %d nodes depth %d (%zu bytes)\n", specs[s],
            q.node_count, q.max_depth, (size_t)q.node_count * sizeof(lt_qbvh_node), w8.node_count, w8.max_depth,
            (size_t)w8.node_count * sizeof(lt_bvh8_node));
    lt__qbvh_free(&q);
    lt__bvh8_free(&w8);
    lt__bvh_free(&bvh);
    lt_scene_destroy(scene);
  }
}

/* ---- The AVX2 test, the plain one and the 4-wide traversal ---- */

/* Traces on the host through the 8-wide tree (vector or plain boxes) or the 4-wide one. */
enum { WIDE_VECTOR, WIDE_PLAIN, QBVH4 };
static void trace_host(int how, const lt__bvh8 *w8, const lt__qbvh *q, const lt__bvh *bvh, const lt_ray *rays, size_t n,
                       int flags, lt_hit *hits, lt_trace_counters *c) {
  for (size_t i = 0; i < n; i++) {
    const lt_ray *ray = &rays[i];
    lt_ray_setup r = lt_ray_prepare(ray->org[0], ray->org[1], ray->org[2], ray->tmin, ray->dir[0], ray->dir[1],
                                    ray->dir[2], ray->tmax);
    r.flags = flags;
    lt_hit_record hit;
    lt_i32 deepest = 0;
    int status = how == QBVH4 ? lt_qbvh_traverse(q->nodes, bvh->tris, &r, &hit, c, &deepest)
                              : lt_bvh8_traverse_with(w8->nodes, w8->blocks, &r, &hit, c, how == WIDE_VECTOR ? LT_BVH8_VECTOR : LT_BVH8_PLAIN);
    assert_int_equal(status, 0);
    if (hit.prim < 0) hit.t = INFINITY, hit.u = hit.v = 0.0f;
    hits[i] = (lt_hit){hit.t, hit.u, hit.v, hit.prim};
  }
}

/* Two any-hit answers to one ray from traversals that take the triangles in the same order
 * and decide each hit alike: the same triangle with the same barycentrics. The distance may
 * differ in its last bits (lt_bvh8_finish skips its double steps where the hit is certain),
 * never past [tmin, tmax]. */
#define assert_same_any_hit(x, y, tmin, tmax)                              \
  do {                                                                      \
    assert_int_equal((x).prim, (y).prim);                                   \
    assert_memory_equal(&(x).u, &(y).u, sizeof(float));                     \
    assert_memory_equal(&(x).v, &(y).v, sizeof(float));                     \
    if ((x).prim >= 0) assert_true((y).t >= (tmin) && (y).t <= (tmax));     \
  } while (0)

/* Rays with +0 and -0 components, axis-aligned and diagonal, from inside a cube of shared
 * edges (aimed at its vertices and edges), and random ones: both box tests give every node the
 * same mask and entry distances; the 8-wide traversal with vector boxes and the leaves'
 * four-triangle test gives the same hits and counters as with plain boxes and every
 * triangle tested alone, and the same hits as the QBVH, for closest and any hit, watertight
 * and fast triangles, with and without the conservative widening. The trees are built with a
 * high node cost, so that leaves of up to 16 triangles take several blocks. */
static void qbvh8_vector_and_plain_box_tests_agree(void **state) {
  (void)state;
  if (!lt_bvh8_supported()) skip();
  lt_hc_mesh cube = lt_hc_cube(8, 9);
  lt_scene *hair;
  assert_int_equal(lt_scene_load("hairball:300", &hair), LT_OK);
  const lt_scene *scenes[2] = {cube.scene, hair};
  enum { N = 4096 };
  lt_ray *rays = malloc(N * sizeof *rays);
  lt_hit *a = malloc(N * sizeof *a), *b = malloc(N * sizeof *b), *q4 = malloc(N * sizeof *q4);
  assert_non_null(rays);
  for (int s = 0; s < 2; s++) {
    /* In the cube, rays at its vertices and edges from inside; in the hairball, random ones. */
    if (s == 0)
      assert_int_equal(lt_hc_closed_rays(&cube, 11, N, rays), N);
    else
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
    lt__bvh8 w8;
    build_with(scenes[s], 8.0f, &bvh, &w8);
    lt__qbvh q;
    assert_int_equal(lt__qbvh_collapse(&bvh, LT_QBVH_MAX_NODES, &q), LT_OK);
    assert_true(multi_block_triangles(&w8) > bvh.tri_count / 2);

    /* Node by node. */
    size_t lanes_hit = 0;
    for (size_t i = 0; i < N; i += 7) {
      lt_ray_setup r = lt_ray_prepare(rays[i].org[0], rays[i].org[1], rays[i].org[2], rays[i].tmin, rays[i].dir[0],
                                      rays[i].dir[1], rays[i].dir[2], rays[i].tmax);
      r.flags = (i % 5 == 0) ? LT_QUERY_FLAG_PLAIN_SLABS : 0;
      lt_bvh8_ray r8 = lt_bvh8_ray_make(&r);
      for (int node = 0; node < w8.node_count; node++) {
        float tv[8], tp[8], tmax = (i % 3 == 0) ? 0.5f : INFINITY;
        int mv = lt_bvh8_box8(&r, &r8, &w8.nodes[node], tmax, tv);
        int used = lt_bvh8_child_lanes(&w8.nodes[node]);
        int mp = lt_bvh8_box8_scalar(&r, &w8.nodes[node], tmax, tp) & used;
        /* Empty lanes are rejected by their box alone (no mask in the vector test). */
        assert_int_equal(mv & ~used, 0);
        assert_int_equal(mv, mp);
        for (int lane = 0; lane < LT_BVH8_WIDTH; lane++)
          if (mv >> lane & 1) assert_memory_equal(&tv[lane], &tp[lane], sizeof(float)), lanes_hit++;
      }
    }
    assert_true(lanes_hit > 0);

    /* Whole traversals. */
    const int flag_sets[] = {0, LT_QUERY_FLAG_ANY, LT_QUERY_FLAG_FAST_TRIANGLES, LT_QUERY_FLAG_PLAIN_SLABS};
    lt_u32 closest_steps = 0;
    for (int f = 0; f < 4; f++) {
      lt_trace_counters cv = {0, 0}, cp = {0, 0}, c4 = {0, 0};
      trace_host(WIDE_VECTOR, &w8, &q, &bvh, rays, N, flag_sets[f], a, &cv);
      trace_host(WIDE_PLAIN, &w8, &q, &bvh, rays, N, flag_sets[f], b, &cp);
      trace_host(QBVH4, &w8, &q, &bvh, rays, N, flag_sets[f], q4, &c4);
      if (flag_sets[f] & LT_QUERY_FLAG_ANY)
        for (size_t i = 0; i < N; i++) assert_same_any_hit(a[i], b[i], rays[i].tmin, rays[i].tmax);
      else
        assert_memory_equal(a, b, N * sizeof *a);
      assert_int_equal(cv.traversal_steps, cp.traversal_steps);
      assert_int_equal(cv.intersections, cp.intersections);
      if (flag_sets[f] == 0) closest_steps = cv.traversal_steps;
      if (flag_sets[f] & LT_QUERY_FLAG_ANY) {
        /* Any hit: which one may differ, whether there is one may not; and the any-hit
         * traversal (made apart from the closest-hit one) stops at its first hit. */
        for (size_t i = 0; i < N; i++) assert_int_equal(a[i].prim >= 0, q4[i].prim >= 0);
        assert_true(cv.traversal_steps < closest_steps);
      } else {
        assert_memory_equal(a, q4, N * sizeof *a);
      }
    }
    lt__qbvh_free(&q);
    lt__bvh8_free(&w8);
    lt__bvh_free(&bvh);
  }
  free(rays), free(a), free(b), free(q4);
  lt_scene_destroy(hair);
  lt_hc_free(&cube);
}

/* A one-triangle scene: node 0 holds one leaf beside seven empty lanes. */
static void qbvh8_single_triangle(void **state) {
  (void)state;
  if (!lt_bvh8_supported()) skip();
  const float tri[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  lt_scene *scene;
  assert_int_equal(lt_scene_from_triangles(tri, 1, &scene), LT_OK);
  lt__bvh bvh;
  lt__bvh8 w8;
  build(scene, &bvh, &w8);
  assert_int_equal(w8.node_count, 1);
  assert_int_equal(w8.nodes[0].count[0], 1);
  lt_ray rays[3] = {{{0.25f, 0.25f, -1}, 0, {0, 0, 1}, INFINITY},
                    {{2, 2, -1}, 0, {0, 0, 1}, INFINITY},
                    {{0.25f, 0.25f, -1}, 0, {0, 0, 1}, 0.5f}};
  lt_hit hits[3];
  lt_trace_counters c = {0, 0};
  trace_host(WIDE_VECTOR, &w8, NULL, &bvh, rays, 3, 0, hits, &c);
  assert_int_equal(hits[0].prim, 0);
  assert_true(hits[0].t == 1.0f);
  assert_int_equal(hits[1].prim, -1);
  assert_int_equal(hits[2].prim, -1);
  lt__bvh8_free(&w8);
  lt__bvh_free(&bvh);
  lt_scene_destroy(scene);
}

/* ---- The four-triangle test against the one-triangle test ---- */

/* Triangles that break a watertight test: the cube's faces (edges and vertices shared by up to
 * six triangles), triangles without area (a repeated vertex, collinear vertices, one point),
 * +0 and -0 coordinates, triangles in axis planes through the origin, a long sliver, and
 * copies of faces (ties broken by the triangle number). */
static int hard_triangles(const lt_scene *cube, lt_tri **out) {
  static const float extra[][9] = {
      {0, 0, 0, 1, 1, 1, 2, 2, 2},             /* collinear */
      {0, 0, 0, 0, 0, 0, 1, 0, 0},             /* a repeated vertex */
      {0.5f, 0.5f, 1, 0.5f, 0.5f, 1, 0.5f, 0.5f, 1}, /* one point */
      {-0.0f, -0.0f, 1, 1, -0.0f, 1, -0.0f, 1, 1},
      {0.0f, 0.0f, 1, 1, 0.0f, 1, 0.0f, 1, 1},
      {-0.0f, 0, 0, -0.0f, 1, 0, 0, 0, 1},     /* in the plane x = 0, +0 and -0 mixed */
      {0, -0.0f, 0, 1, 0, 0, 0, -0.0f, 1},     /* in the plane y = 0 */
      {-30, 0, 1.5f, 30, 0.01f, 1.5f, 30, 0.02f, 1.5001f}, /* a sliver */
  };
  enum { COPIES = 8 };
  int n = (int)lt_scene_triangle_count(cube), m = (int)(sizeof extra / sizeof extra[0]) + COPIES;
  lt_tri *t = malloc((size_t)(n + m) * sizeof *t);
  assert_non_null(t);
  const float *v = lt_scene_triangles(cube);
  for (int i = 0; i < n + m; i++) {
    const float *f = i < n ? v + 9 * i : i < n + m - COPIES ? extra[i - n] : v + 9 * (i - (n + m - COPIES));
    /* Numbered backwards: the copies of the cube's first triangles at the end tie with them
     * and win by their lower numbers, in later blocks. */
    t[i].v0 = (lt_float4){f[0], f[1], f[2], lt_int_as_float(n + m - 1 - i)};
    t[i].v1 = (lt_float4){f[3], f[4], f[5], 0};
    t[i].v2 = (lt_float4){f[6], f[7], f[8], 0};
  }
  *out = t;
  return n + m;
}

/* Rays at the hard triangles: the cube's closed-mesh rays (at its vertices and edges from
 * inside), rays from the origin and from (0.25, 0.25, -2) along the 26 axis and diagonal
 * directions with +0 and -0 components, and rays that start on the cube's grid points (on
 * shared vertices and edges, as AO rays start on a surface) with tmin 0 and the smallest
 * positive float. */
static size_t hard_rays(lt_hc_mesh *cube, lt_ray *rays, size_t max) {
  size_t n = lt_hc_closed_rays(cube, 5, max / 2, rays);
  const float origins[3][3] = {{0, 0, 0}, {0.25f, 0.25f, -2}, {-0.0f, -0.0f, 0.5f}};
  for (int o = 0; o < 3; o++)
    for (int code = 0; code < 27 && n < max; code++)
      for (int sign = 0; sign < 8 && n < max; sign++) {
        if (code == 13) continue;
        lt_ray *r = &rays[n++];
        for (int k = 0; k < 3; k++) {
          int comp = (code / (k == 0 ? 1 : k == 1 ? 3 : 9)) % 3 - 1;
          r->org[k] = origins[o][k];
          r->dir[k] = comp ? (float)comp : (sign >> k & 1 ? -0.0f : 0.0f);
        }
        r->tmin = 0, r->tmax = INFINITY;
      }
  for (int i = 0; n < max; i++) {
    lt_ray *r = &rays[n++];
    for (int k = 0; k < 3; k++) r->org[k] = (float)((i / (k == 0 ? 1 : k == 1 ? 5 : 25)) % 5 - 2);
    r->org[i % 3] = i & 8 ? -2.0f : 2.0f; /* on a face of the cube [-2, 2]^3 */
    for (int k = 0; k < 3; k++) r->dir[k] = (float)((i * 7 + 3 * k) % 5 - 2) + 0.25f * (float)k;
    r->tmin = i & 1 ? 0.0f : 1.4e-45f, r->tmax = i & 2 ? 1.5f : INFINITY;
  }
  return n;
}


/* The four-triangle test as the traversal runs it (inlined into code of the 8-wide path's
 * target only), in the common ray's form where the ray has no zero direction component. */
LT_BVH8_TARGET static int tri4_test(const lt_ray_setup *r, const lt_bvh8_ray *q, const lt_tri4 *b, int any,
                                    lt_hit_record *hit) {
  return lt_bvh8_tri4_watertight(r, q, b, 15, any, !r->parallel, hit);
}
/* The four-triangle watertight test, block by block, against the one-triangle test lane by
 * lane in index order on the hard cases: after every block the hit records are identical bit
 * for bit, for closest hits (each block starting from the best hit of the ones before) and
 * for any hit (stopping at the same triangle). */
static void qbvh8_four_triangle_test_matches_the_one_triangle_test(void **state) {
  (void)state;
  if (!lt_bvh8_supported()) skip();
  lt_hc_mesh cube = lt_hc_cube(4, 5);
  lt_tri *tris;
  int n = hard_triangles(cube.scene, &tris), blocks = (n + 3) / 4;
  lt_tri4 *b = aligned_alloc(64, (size_t)blocks * sizeof *b);
  lt_tri *padded = malloc((size_t)blocks * 4 * sizeof *padded);
  assert_non_null(b);
  assert_non_null(padded);
  for (int i = 0; i < 4 * blocks; i++) {
    const lt_tri *t = &tris[i < n ? i : n - 1];
    padded[i] = *t;
    const lt_float4 *v[3] = {&t->v0, &t->v1, &t->v2};
    for (int j = 0; j < 3; j++) {
      lt_tri4 *block = &b[i / 4];
      block->v[3 * j][i % 4] = v[j]->x, block->v[3 * j + 1][i % 4] = v[j]->y, block->v[3 * j + 2][i % 4] = v[j]->z;
    }
    b[i / 4].prim[i % 4] = lt_float_as_int(t->v0.w);
  }
  enum { N = 2048 };
  lt_ray *rays = malloc(N * sizeof *rays);
  assert_non_null(rays);
  size_t count = hard_rays(&cube, rays, N), hits = 0, stops = 0;
  for (size_t i = 0; i < count; i++) {
    lt_ray_setup r = lt_ray_prepare(rays[i].org[0], rays[i].org[1], rays[i].org[2], rays[i].tmin, rays[i].dir[0],
                                    rays[i].dir[1], rays[i].dir[2], rays[i].tmax);
    if (!r.valid) continue;
    lt_bvh8_ray q = lt_bvh8_ray_make(&r);
    for (int any = 0; any < 2; any++) {
      lt_hit_record one = {r.tmax, 0, 0, -1}, four = one;
      int one_stop = 0;
      for (int k = 0; k < blocks && !one_stop; k++) {
        for (int lane = 0; lane < 4 && !one_stop; lane++) {
          const lt_tri *t = &padded[4 * k + lane];
          float v0[3] = {t->v0.x, t->v0.y, t->v0.z}, v1[3] = {t->v1.x, t->v1.y, t->v1.z};
          float v2[3] = {t->v2.x, t->v2.y, t->v2.z};
          lt_intersect_watertight(&r, v0, v1, v2, lt_float_as_int(t->v0.w), &one);
          one_stop = any && one.prim >= 0;
        }
        int four_stop = tri4_test(&r, &q, &b[k], any, &four);
        assert_int_equal(four_stop, one_stop);
        if (any)
          assert_same_any_hit(one, four, r.tmin, r.tmax);
        else
          assert_memory_equal(&one, &four, sizeof one);
      }
      hits += one.prim >= 0, stops += one_stop;
    }
  }
  assert_true(hits > count / 2);
  assert_true(stops > count / 4);
  free(rays), free(padded), free(tris), free(b);
  lt_hc_free(&cube);
}

/* The 8-wide kernel's ray setup is lt_ray_prepare's, field for field and bit for bit, on the
 * hard rays (+0 and -0 direction components, rays along axes), random ones, rays with tiny
 * and huge direction components, and the invalid ones (NaN, infinities, a zero direction,
 * tmin > tmax). */
static void qbvh8_ray_setup_matches_lt_ray_prepare(void **state) {
  (void)state;
  if (!lt_bvh8_supported()) skip();
  lt_hc_mesh cube = lt_hc_cube(4, 5);
  enum { N = 1024 };
  lt_ray *rays = malloc(N * sizeof *rays);
  assert_non_null(rays);
  size_t n = hard_rays(&cube, rays, N / 2);
  lt_hc_random_rays(&cube, 9, N / 4, rays + n);
  n += N / 4;
  for (int i = 0; i < 16; i++, n++) {
    rays[n] = rays[i];
    rays[n].dir[i % 3] = i & 4 ? 1e-45f : -3e38f; /* reciprocals that overflow, and huge ones */
    rays[n].tmax = i & 8 ? -1.0f : rays[n].tmax;
  }
  n += lt_hc_invalid_rays(rays + n, N - n);
  int invalid = 0;
  for (size_t i = 0; i < n; i++) {
    const lt_ray *ray = &rays[i];
    const float packed[8] = {ray->org[0], ray->org[1], ray->org[2], ray->tmin,
                             ray->dir[0], ray->dir[1], ray->dir[2], ray->tmax};
    lt_ray_setup a =
        lt_ray_prepare(packed[0], packed[1], packed[2], packed[3], packed[4], packed[5], packed[6], packed[7]);
    a.flags = (int)i & 7;
    lt_ray_setup b;
    memset(&b, 0x5a, sizeof b);
    lt_bvh8_ray_prepare(packed, (int)i & 7, &b);
    invalid += !a.valid;
    assert_int_equal(a.valid, b.valid);
    assert_memory_equal(&a.org4, &b.org4, sizeof a.org4);
    assert_memory_equal(&a.inv4, &b.inv4, sizeof a.inv4);
    assert_memory_equal(a.org, b.org, sizeof a.org);
    assert_memory_equal(a.dir, b.dir, sizeof a.dir);
    assert_memory_equal(a.inv_dir, b.inv_dir, sizeof a.inv_dir);
    assert_memory_equal(&a.tmin, &b.tmin, sizeof a.tmin);
    assert_memory_equal(&a.tmax, &b.tmax, sizeof a.tmax);
    assert_int_equal(a.kx, b.kx), assert_int_equal(a.ky, b.ky), assert_int_equal(a.kz, b.kz);
    assert_memory_equal(&a.sx, &b.sx, sizeof a.sx);
    assert_memory_equal(&a.sy, &b.sy, sizeof a.sy);
    assert_memory_equal(&a.sz, &b.sz, sizeof a.sz);
    assert_int_equal(a.parallel, b.parallel);
    assert_int_equal(a.flags, b.flags);
  }
  assert_true(invalid > 8);
  free(rays);
  lt_hc_free(&cube);
}

/* ---- Which path the library takes ---- */

/* On the native backend with AVX2 the statistics describe the 8-wide tree (256 bytes a node);
 * with LT_QBVH_WIDTH=4, or without AVX2, the QBVH's (128). Hits are the same either way. */
static void qbvh8_native_path_follows_the_cpu_and_the_switch(void **state) {
  (void)state;
  lt_scene *scene;
  assert_int_equal(lt_scene_load("hairball:300", &scene), LT_OK);
  lt_structure_config sc = lt_structure_config_default(LT_STRUCTURE_QBVH);
  enum { N = 256 };
  lt_ray rays[N];
  lt_test_random_rays(scene, 3, N, rays);
  lt__bvh bvh;
  lt__bvh8 w8;
  build(scene, &bvh, &w8);
  lt__qbvh q;
  assert_int_equal(lt__qbvh_collapse(&bvh, LT_QBVH_MAX_NODES, &q), LT_OK);
  lt_hit *hits[2];
  for (int forced = 0; forced < 2; forced++) {
    lt_stats *stats;
    assert_int_equal(lt_stats_create(&stats), LT_OK);
    if (forced) setenv("LT_QBVH_WIDTH", "4", 1);
    lt_test_launch native = {LT_DEVICE_NATIVE, 0, 0};
    hits[forced] = lt_test_trace_with(scene, &native, &sc, rays, N, LT_QUERY_CLOSEST, stats);
    unsetenv("LT_QBVH_WIDTH");
    assert_non_null(hits[forced]);
    int wide = !forced && lt_bvh8_supported();
    double tris = (double)lt_scene_triangle_count(scene);
    double node_bytes = wide ? 256.0 * w8.node_count : 128.0 * q.node_count;
    assert_true(lt_stats_get(stats, "node_bytes") == node_bytes);
    double ref_bytes = wide ? 40.0 * w8.tri_slots : 48.0 * tris;
    assert_true(lt_stats_get(stats, "reference_bytes") == ref_bytes);
    assert_true(lt_stats_get(stats, "memory_bytes") == node_bytes + ref_bytes);
    assert_true(lt_stats_get(stats, "max_depth") == (wide ? w8.max_depth : q.max_depth));
    assert_true(lt_stats_get(stats, "nodes_built") ==
                (wide ? (double)w8.node_count + w8.leaf_count : (double)q.node_count + q.leaf_count));
    assert_true(lt_stats_get(stats, "traversal_steps") > 0);
    lt_stats_destroy(stats);
  }
  assert_memory_equal(hits[0], hits[1], N * sizeof(lt_hit));
  free(hits[0]), free(hits[1]);
  lt__qbvh_free(&q);
  lt__bvh8_free(&w8);
  lt__bvh_free(&bvh);
  lt_scene_destroy(scene);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(qbvh8_collapse_keeps_every_triangle_and_exact_boxes),
      cmocka_unit_test(qbvh8_vector_and_plain_box_tests_agree),
      cmocka_unit_test(qbvh8_single_triangle),
      cmocka_unit_test(qbvh8_four_triangle_test_matches_the_one_triangle_test),
      cmocka_unit_test(qbvh8_ray_setup_matches_lt_ray_prepare),
      cmocka_unit_test(qbvh8_native_path_follows_the_cpu_and_the_switch),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}

#endif
