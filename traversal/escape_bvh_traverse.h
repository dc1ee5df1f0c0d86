/* The stackless traversal of the escape-index BVH (Thrane and Simonsen 2005, algorithm 4;
 * device/escape_bvh_node.h): the nodes are walked in array order; a ray that meets a node's
 * box goes on to the next node, after intersecting the triangles if it is a leaf, and a ray
 * that misses it jumps to its escape index. The order of children is fixed (left first), as
 * in the thesis: no sorting, no stack, one index of state.
 *
 * The box test is the conservative one every BVH traversal uses (traversal/ray_box.h), up to
 * the best hit so far, so a box whose triangles could still win or tie is never skipped and
 * the closest hit is the brute-force reference's. An any-hit query stops at the first hit. */
#ifndef LT_ESCAPE_BVH_TRAVERSE_H
#define LT_ESCAPE_BVH_TRAVERSE_H

#include "device/escape_bvh_node.h"
#include "traversal/ray_box.h"

/* Traces one ray prepared with lt_ray_prepare (its flags set) and writes its hit (prim -1 on a
 * miss). */
LT_DEVICE void lt_escape_bvh_traverse(LT_GLOBAL const lt_escape_node *nodes, lt_i32 node_count,
                                      LT_GLOBAL const lt_tri *tris, const lt_ray_setup *r, lt_hit_record *out,
                                      lt_trace_counters *c) {
  lt_hit_record hit;
  hit.t = r->tmax, hit.u = hit.v = 0.0f, hit.prim = -1;
  int any_hit = r->flags & LT_QUERY_FLAG_ANY;
  lt_i32 i = r->valid ? 0 : node_count;
  while (i < node_count) {
    c->traversal_steps++;
    LT_GLOBAL const lt_escape_node *n = &nodes[i];
    float lo[3] = {n->lo[0], n->lo[1], n->lo[2]}, hi[3] = {n->hi[0], n->hi[1], n->hi[2]};
    lt_i32 link = n->link, count = n->count;
    float t_entry;
    if (!lt_ray_box(r, lo, hi, hit.prim >= 0 ? hit.t : r->tmax, &t_entry)) {
      i = count > 0 ? i + 1 : link;
      continue;
    }
    for (lt_i32 k = link; k < link + count; k++) {
      lt_tri tri = tris[k];
      float v0[3] = {tri.v0.x, tri.v0.y, tri.v0.z}, v1[3] = {tri.v1.x, tri.v1.y, tri.v1.z};
      float v2[3] = {tri.v2.x, tri.v2.y, tri.v2.z};
      c->intersections++;
      lt_intersect_triangle(r, v0, v1, v2, lt_float_as_int(tri.v0.w), &hit);
    }
    if (any_hit && hit.prim >= 0) break;
    i++;
  }
  *out = hit;
}

#endif
