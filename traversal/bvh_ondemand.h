/* Traversal of a BVH that is still being built (the on-demand paper, section 3.3, after Aila
 * and Laine 2009): a child whose link is unbuilt is requested from the task pool and the ray
 * suspends there, keeping its stack and its best hit; a restart re-reads the parent's link.
 * Stack entries are node indices, or references to unbuilt links (-2 - address). */
#ifndef LT_BVH_ONDEMAND_H
#define LT_BVH_ONDEMAND_H

#include "builders/bvh_task.h"
#include "traversal/ray_box.h"

/* A ray in flight: enough state to suspend and resume. */
typedef struct lt_od_ray {
  lt_ray_setup r;
  lt_hit_record hit;
  lt_i32 stack[LT_BVH_STACK_SIZE];
  float stack_t[LT_BVH_STACK_SIZE]; /* each far child's entry distance */
  lt_i32 sp;
  lt_i32 cur;  /* next node, a link reference (<= -2), or -1 when done */
  lt_i32 wait; /* link address the ray is suspended on, or -1 */
} lt_od_ray;

LT_DEVICE void lt_od_leaf(const lt_bvh_build *b, lt_od_ray *q, lt_i32 first, lt_i32 count, lt_trace_counters *c) {
  for (lt_i32 i = first; i < first + count; i++) {
    lt_i32 prim = b->index[i];
    LT_GLOBAL const float *t = b->verts + 9 * (long)prim;
    float v0[3] = {t[0], t[1], t[2]}, v1[3] = {t[3], t[4], t[5]}, v2[3] = {t[6], t[7], t[8]};
    c->intersections++;
    lt_intersect_triangle(&q->r, v0, v1, v2, prim, &q->hit);
  }
}

LT_DEVICE void lt_od_start(lt_od_ray *q, LT_GLOBAL const float *ray) {
  q->r = lt_ray_prepare(ray[0], ray[1], ray[2], ray[3], ray[4], ray[5], ray[6], ray[7]);
  q->hit.t = q->r.tmax, q->hit.u = q->hit.v = 0.0f, q->hit.prim = -1;
  q->sp = 0, q->wait = -1;
  q->cur = q->r.valid ? 0 : -1;
}

/* The distance a box must be entered by to matter: the best hit so far, or the ray's end. */
LT_DEVICE float lt_od_best(const lt_od_ray *q) { return q->hit.prim >= 0 ? q->hit.t : q->r.tmax; }

/* The next far child that the best hit so far has not ruled out: its entry distance against
 * the best is the box test it passed when it was pushed, redone with the best as it is now,
 * so a far child that a closer hit has since hidden is neither visited nor requested. */
LT_DEVICE lt_i32 lt_od_pop(lt_od_ray *q) {
  float best = lt_od_best(q);
  while (q->sp > 0) {
    q->sp--;
    if (q->stack_t[q->sp] <= best) return q->stack[q->sp];
  }
  return -1;
}

/* Advances a ray; returns 1 when it is done, 0 when it waits for an unbuilt node. flags are
 * the query flags (LT_QUERY_FLAG_*: any hit, the triangle test, the slab test), which the
 * persistent kernel passes in its any-hit argument. */
LT_DEVICE int lt_od_trace(const lt_bvh_build *b, lt_od_ray *q, int flags, lt_trace_counters *c) {
  LT_GLOBAL const lt_bvh_node *nodes = b->nodes;
  int any_hit = flags & LT_QUERY_FLAG_ANY;
  q->r.flags = flags;
  for (;;) {
    if (any_hit && q->hit.prim >= 0) return 1;

    /* A link reference: resolve it, or suspend on it. */
    if (q->cur <= -2) {
      lt_i32 address = -2 - q->cur, link, count;
      int kind = lt_bvh_read_link(nodes, address, &link, &count);
      if (kind == LT_CHILD_UNBUILT) {
        if (q->wait != address) {
          lt_pool_request(&b->pool, -2 - link, address);
          lt_pool_count(&b->pool, LT_POOL_STAT_STALLS, 1);
          q->wait = address;
        }
        return 0;
      }
      q->wait = -1;
      if (kind == LT_CHILD_LEAF) lt_od_leaf(b, q, link, count, c);
      q->cur = kind == LT_CHILD_INNER ? link : lt_od_pop(q);
      continue;
    }
    if (q->cur < 0) return 1;

    /* Both children's boxes against the ray, up to the best hit so far. */
    c->traversal_steps++;
    LT_GLOBAL const lt_bvh_node *n = &nodes[q->cur];
    lt_float4 lxy = n->left_xy, rxy = n->right_xy, z = n->lr_z;
    float lo[2][3] = {{lxy.x, lxy.z, z.x}, {rxy.x, rxy.z, z.z}};
    float hi[2][3] = {{lxy.y, lxy.w, z.y}, {rxy.y, rxy.w, z.w}};
    float best = lt_od_best(q);
    lt_i32 next[2];
    float t_entry[2];
    int go[2];
    for (int side = 0; side < 2; side++) {
      lt_i32 address = q->cur * 2 + side, link, count;
      int kind = lt_bvh_read_link(nodes, address, &link, &count);
      go[side] = kind != LT_CHILD_EMPTY && lt_ray_box(&q->r, lo[side], hi[side], best, &t_entry[side]);
      if (!go[side]) continue;

      /* Leaves now; inner nodes go on; an unbuilt child is requested when the ray gets
       * there (the far one may be hidden by then). */
      if (kind == LT_CHILD_LEAF) {
        lt_od_leaf(b, q, link, count, c);
        go[side] = 0;
      } else if (kind == LT_CHILD_UNBUILT) {
        next[side] = -2 - address;
      } else {
        next[side] = link;
      }
    }
    if (any_hit && q->hit.prim >= 0) return 1;

    /* The nearer child next, the farther one on the stack. */
    if (go[0] && go[1]) {
      int near_side = t_entry[0] <= t_entry[1] ? 0 : 1;
      if (q->sp == LT_BVH_STACK_SIZE) {
        lt_pool_fail(&b->pool, LT_POOL_ERROR_STACK);
        return 1;
      }
      q->stack[q->sp] = next[1 - near_side], q->stack_t[q->sp] = t_entry[1 - near_side];
      q->sp++;
      q->cur = next[near_side];
    } else if (go[0] || go[1]) {
      q->cur = go[0] ? next[0] : next[1];
    } else {
      q->cur = lt_od_pop(q);
    }
  }
}

#endif
