/* Closest-hit and any-hit traversal of a binary BVH: nearest child first with an explicit
 * stack of far children (Aila and Laine, "Understanding the Efficiency of Ray Traversal on
 * GPUs", 2009). Leaf children are intersected as soon as their box is hit. */
#ifndef LT_BVH_TRAVERSE_H
#define LT_BVH_TRAVERSE_H

#include "device/bvh_node.h"
#include "traversal/ray_box.h"

LT_DEVICE void lt_leaf_intersect(const lt_ray_setup *r, LT_GLOBAL const lt_tri *tris, int first,
                                 int count, lt_hit_record *hit, lt_trace_counters *counters) {
  for (int i = first; i < first + count; i++) {
    lt_tri tri = tris[i];
    float v0[3] = {tri.v0.x, tri.v0.y, tri.v0.z};
    float v1[3] = {tri.v1.x, tri.v1.y, tri.v1.z};
    float v2[3] = {tri.v2.x, tri.v2.y, tri.v2.z};
    counters->intersections++;
    lt_intersect_triangle(r, v0, v1, v2, lt_float_as_int(tri.v0.w), hit);
  }
}

/* Traces one ray; any_hit stops at the first hit found. A miss leaves prim = -1 and t = tmax.
 * Returns 0, or -1 if the stack would overflow (impossible for trees from our builders, which
 * bound the depth). */
LT_DEVICE int lt_bvh_traverse(const lt_ray_setup *r, LT_GLOBAL const lt_bvh_node *nodes,
                              LT_GLOBAL const lt_tri *tris, int any_hit, lt_hit_record *hit,
                              lt_trace_counters *counters) {
  hit->t = r->tmax;
  hit->u = hit->v = 0.0f;
  hit->prim = -1;
  if (!r->valid) return 0;

  int stack[LT_BVH_STACK_SIZE];
  int sp = 0;
  int node = 0;
  while (node >= 0) {
    counters->traversal_steps++;
    lt_bvh_node n = nodes[node];
    float best = hit->prim >= 0 ? hit->t : r->tmax;

    /* Both child boxes against the ray, up to the best hit so far. */
    float lo_l[3] = {n.left_xy.x, n.left_xy.z, n.lr_z.x}, hi_l[3] = {n.left_xy.y, n.left_xy.w, n.lr_z.y};
    float lo_r[3] = {n.right_xy.x, n.right_xy.z, n.lr_z.z}, hi_r[3] = {n.right_xy.y, n.right_xy.w, n.lr_z.w};
    float t_l = 0.0f, t_r = 0.0f;
    int hit_l = (n.link[2] > 0 || n.link[0] >= 0) && lt_ray_box(r, lo_l, hi_l, best, &t_l);
    int hit_r = (n.link[3] > 0 || n.link[1] >= 0) && lt_ray_box(r, lo_r, hi_r, best, &t_r);

    /* Leaves are intersected right away; only inner children go on. */
    if (hit_l && n.link[2] > 0) {
      lt_leaf_intersect(r, tris, n.link[0], n.link[2], hit, counters);
      hit_l = 0;
    }
    if (hit_r && n.link[3] > 0) {
      lt_leaf_intersect(r, tris, n.link[1], n.link[3], hit, counters);
      hit_r = 0;
    }
    if (any_hit && hit->prim >= 0) return 0;

    /* Descend into the nearer inner child and keep the farther one for later. */
    if (hit_l && hit_r) {
      int near_child = t_l <= t_r ? n.link[0] : n.link[1];
      int far_child = t_l <= t_r ? n.link[1] : n.link[0];
      if (sp == LT_BVH_STACK_SIZE) return -1;
      stack[sp++] = far_child;
      node = near_child;
    } else if (hit_l) {
      node = n.link[0];
    } else if (hit_r) {
      node = n.link[1];
    } else {
      node = sp > 0 ? stack[--sp] : -1;
    }
  }
  return 0;
}

#endif
