/* kd-tree traversal, front to back with a stack of far cells (the "standard" recursive
 * traversal of Havran's thesis, and of Thrane and Simonsen 2005, section 4.3): a ray visits
 * the cells it crosses in order, and its closest hit is final as soon as no cell still on the
 * stack begins before it, which is the paper's "first hit inside the current leaf" (section
 * 3.5): cells behind a hit are neither visited nor, on a tree still being built, requested.
 * A ray that reaches an unbuilt child requests its task from the pool and suspends, keeping
 * its stack and best hit; a restart re-reads the link. Any-hit queries end at the first hit.
 *
 * Robustness. Cells are closed boxes, and a triangle is referenced by every child whose box
 * its own box reaches into (builders/kd_task.h), so the leaf around any point of the ray where
 * a triangle is hit holds that triangle. What can go wrong is rounding in the distance to a
 * split plane, which decides which children a ray visits and where a cell begins: each plane
 * distance is given a margin that bounds its rounding error (two roundings of the difference
 * and the quotient, relative to the operands), a child is skipped only when the plane lies
 * beyond the ray's interval by more than that margin, and cells are entered at their distance
 * less the margin. A ray parallel to a plane goes to the side its origin is on, and to both
 * when it lies in the plane. The closest hit is then exact (the same as brute force, ties to
 * the lower triangle number): a cell is left unvisited only when it begins beyond the best hit
 * by more than the margins. */
#ifndef LT_KD_TRAVERSE_H
#define LT_KD_TRAVERSE_H

#include "device/box.h"
#include "device/kd_node.h"
#include "device/pool.h"
#include "traversal/intersect_triangle.h"

/* The relative rounding bound given to a plane distance: 4 units in the last place of the
 * larger operand, after the subtraction and the division. */
#define LT_KD_PLANE_EPS 4.8e-7f

/* What a kd traversal reads. */
typedef struct lt_kd_view {
  LT_GLOBAL const lt_kd_node *nodes;
  LT_GLOBAL const lt_i32 *parents; /* per node: its parent (stackless backtracking) */
  LT_GLOBAL const float *cells;    /* per node: its cell, lo xyz hi xyz (stackless backtracking) */
  LT_GLOBAL const lt_i32 *refs;  /* reference arrays (leaves point into them) */
  LT_GLOBAL const float *verts;  /* the scene's vertices, 9 floats a triangle */
  const lt_pool *pool;           /* on demand: where unbuilt children are requested; NULL for a
                                    finished tree (kernels/kd_trace.h) */
  lt_box bounds;                 /* the scene's: the root cell */
} lt_kd_view;

/* A cell still to visit: the link that leads to it and its stretch of the ray. */
typedef struct lt_kd_entry {
  lt_i32 address;
  float t_near, t_far;
} lt_kd_entry;

/* A ray in flight: enough state to suspend on an unbuilt child and resume. */
typedef struct lt_kd_ray {
  lt_ray_setup r;
  lt_hit_record hit;
  lt_kd_entry stack[LT_KD_STACK_SIZE];
  lt_i32 sp;
  lt_kd_entry cur; /* the link to read next and its cell's stretch; address -1: pop */
  lt_i32 wait;     /* link address the ray is suspended on, or -1 */
  lt_i32 overflow; /* the stack would have overflowed: the answer is not to be trusted */
  float t_near, t_far; /* the ray's stretch in the root cell (the stackless traversals) */
} lt_kd_ray;

/* The margin of a plane distance (p - o) / d: see LT_KD_PLANE_EPS. */
LT_DEVICE float lt_kd_margin(float p, float o, float d, float t) {
  return LT_KD_PLANE_EPS * ((lt_fabsf(p) + lt_fabsf(o)) / lt_fabsf(d) + lt_fabsf(t));
}

/* The ray's stretch [t_near, t_far] inside a box (the root cell, or any node's cell), within
 * [tmin, tmax] and widened by the plane margins; 0 when the ray misses the box. */
LT_DEVICE int lt_kd_box_stretch(const lt_ray_setup *r, const float lo_box[3], const float hi_box[3], float *t_near,
                                float *t_far) {
  float tn = r->tmin, tf = r->tmax;
  for (int k = 0; k < 3; k++) {
    float o = r->org[k], d = r->dir[k];
    if (d == 0.0f) {
      if (o < lo_box[k] || o > hi_box[k]) return 0;
      continue;
    }
    float t0 = (lo_box[k] - o) / d, t1 = (hi_box[k] - o) / d;
    float lo = t0 < t1 ? t0 : t1, hi = t0 < t1 ? t1 : t0;
    lo -= lt_kd_margin(d > 0.0f ? lo_box[k] : hi_box[k], o, d, lo);
    hi += lt_kd_margin(d > 0.0f ? hi_box[k] : lo_box[k], o, d, hi);
    tn = lo > tn ? lo : tn;
    tf = hi < tf ? hi : tf;
  }
  *t_near = tn, *t_far = tf;
  return tn <= tf;
}

/* Starts a ray given in the ray file's layout (8 floats): its stretch inside the scene's box,
 * or done at once when it misses the box. */
LT_DEVICE void lt_kd_ray_start(lt_kd_ray *q, LT_GLOBAL const float *ray, const lt_box *bounds) {
  q->r = lt_ray_prepare(ray[0], ray[1], ray[2], ray[3], ray[4], ray[5], ray[6], ray[7]);
  q->hit.t = q->r.tmax, q->hit.u = q->hit.v = 0.0f, q->hit.prim = -1;
  q->sp = 0, q->wait = -1, q->overflow = 0;
  q->cur.address = -1;
  float t_near, t_far;
  if (!q->r.valid || !lt_kd_box_stretch(&q->r, bounds->lo, bounds->hi, &t_near, &t_far)) return;
  q->cur.address = 0, q->cur.t_near = t_near, q->cur.t_far = t_far;
  q->t_near = t_near, q->t_far = t_far;
}

/* A finished ray's answer in the hit file's layout: a miss is t = +infinity, u = v = 0. */
LT_DEVICE lt_hit_record lt_kd_ray_answer(const lt_kd_ray *q) {
  lt_hit_record hit = q->hit;
  if (hit.prim < 0) hit.t = INFINITY, hit.u = hit.v = 0.0f;
  return hit;
}

/* How far a cell may begin and still hold a hit that beats or ties the best: the best hit's
 * distance and its own rounding (the triangle test's distance is computed in double and kept
 * in the triangle box's slab interval, whose bound is LT_SLAB_ROUNDING_EPS). */
LT_DEVICE float lt_kd_reach(const lt_kd_ray *q, const lt_hit_record *hit) {
  if (hit->prim < 0) return q->r.tmax;
  return hit->t + lt_fabsf(hit->t) * (2.0f * LT_SLAB_ROUNDING_EPS);
}

/* Intersects a leaf's references. */
LT_DEVICE void lt_kd_leaf(const lt_kd_view *v, const lt_ray_setup *r, lt_hit_record *hit, lt_i32 first, lt_i32 count,
                          lt_trace_counters *c) {
  for (lt_i32 i = first; i < first + count; i++) {
    lt_i32 prim = v->refs[i];
    LT_GLOBAL const float *t = v->verts + 9 * (long)prim;
    float v0[3] = {t[0], t[1], t[2]}, v1[3] = {t[3], t[4], t[5]}, v2[3] = {t[6], t[7], t[8]};
    c->intersections++;
    lt_intersect_triangle(r, v0, v1, v2, prim, hit);
  }
}

/* Which children of an inner cell a ray visits, and in which order. Along the ray, the child
 * below the plane comes first when the ray runs up the axis (up to the plane's distance), the
 * one above first when it runs down; a ray parallel to the plane stays on its origin's side, or
 * in the plane, in both. A child is skipped only when the plane lies beyond the cell's stretch
 * [t_near, t_far] by more than the plane distance's margin. */
typedef struct lt_kd_step {
  int first_side, visit_first, visit_second;
  float t_split, margin; /* the plane's distance and margin (t_near and 0 for a parallel ray) */
} lt_kd_step;

LT_DEVICE lt_kd_step lt_kd_decide(const lt_ray_setup *r, int axis, float p, float t_near, float t_far) {
  float o = r->org[axis], d = r->dir[axis];
  lt_kd_step st;
  st.first_side = d > 0.0f ? 0 : 1;
  st.visit_first = 1, st.visit_second = 1;
  st.t_split = t_near, st.margin = 0.0f;
  if (d == 0.0f) {
    st.first_side = o <= p ? 0 : 1;
    st.visit_second = o == p;
  } else {
    st.t_split = (p - o) / d;
    st.margin = lt_kd_margin(p, o, d, st.t_split);
    st.visit_first = t_near <= st.t_split + st.margin;
    st.visit_second = t_far >= st.t_split - st.margin;
  }
  return st;
}

/* Advances a ray started with lt_kd_ray_start; returns 1 when it is done, 0 when it waits for
 * an unbuilt node. flags are the query flags (LT_QUERY_FLAG_*). */
LT_DEVICE int lt_kd_advance(const lt_kd_view *v, lt_kd_ray *q, int flags, lt_trace_counters *c) {
  LT_GLOBAL const lt_kd_node *nodes = v->nodes;
  int any_hit = flags & LT_QUERY_FLAG_ANY;
  q->r.flags = flags;
  const lt_ray_setup *r = &q->r;
  lt_hit_record hit = q->hit;
  lt_kd_entry cur = q->cur;
  lt_i32 sp = q->sp;
  int done = 1;
  for (;;) {
    if (any_hit && hit.prim >= 0) break;

    /* The next cell from the stack that may still hold a better hit; none: done. */
    if (cur.address < 0) {
      float reach = lt_kd_reach(q, &hit);
      while (sp > 0 && cur.address < 0) {
        lt_kd_entry e = q->stack[--sp];
        if (e.t_near <= reach) cur = e;
      }
      if (cur.address < 0) break;
    }

    lt_i32 link = lt_kd_read_link(nodes, cur.address);
    if (link <= -2) {
      if (q->wait != cur.address) {
        lt_pool_request(v->pool, lt_kd_unbuilt_slot(link), cur.address);
        lt_pool_count(v->pool, LT_POOL_STAT_STALLS, 1);
        q->wait = cur.address;
      }
      done = 0;
      break;
    }
    q->wait = -1;
    if (link == LT_KD_LINK_EMPTY) {
      cur.address = -1;
      continue;
    }
    c->traversal_steps++;
    /* A node's own fields never change once it is linked; its links may (they are read
     * through lt_kd_read_link), so the node is not copied whole. */
    LT_GLOBAL const lt_kd_node *n = &nodes[link];
    lt_i32 meta = n->meta;
    int axis = lt_kd_axis(meta);
    if (axis == LT_KD_LEAF_AXIS) {
      lt_kd_leaf(v, r, &hit, n->link[0], lt_kd_leaf_count(meta), c);
      cur.address = -1;
      continue;
    }

    lt_kd_step st = lt_kd_decide(r, axis, n->split, cur.t_near, cur.t_far);
    int first_side = st.first_side, visit_first = st.visit_first, visit_second = st.visit_second;
    float t_split = st.t_split, margin = st.margin, d = r->dir[axis];
    lt_i32 first_address = link * 2 + first_side, second_address = link * 2 + 1 - first_side;
    if (visit_first && visit_second) {
      if (sp == LT_KD_STACK_SIZE) {
        if (v->pool) lt_pool_fail(v->pool, LT_POOL_ERROR_STACK);
        q->overflow = 1;
        break;
      }
      lt_kd_entry second;
      second.address = second_address;
      second.t_near = t_split - margin > cur.t_near ? t_split - margin : cur.t_near;
      second.t_far = cur.t_far;
      q->stack[sp++] = second;
      cur.address = first_address;
      if (d != 0.0f && t_split + margin < cur.t_far) cur.t_far = t_split + margin;
    } else {
      cur.address = visit_first ? first_address : second_address;
    }
  }
  q->cur = cur, q->sp = sp, q->hit = hit;
  return done;
}

#endif
