/* The trace kernel of the escape-index BVH (device/escape_bvh_node.h,
 * traversal/escape_bvh_traverse.h): one ray at a time, no stack; leaves are triangles in leaf
 * order. */
#ifndef LT_KERNEL_ESCAPE_BVH_TRACE_H
#define LT_KERNEL_ESCAPE_BVH_TRACE_H

#include "kernels/trace_kernel.h"
#include "traversal/escape_bvh_traverse.h"

typedef struct lt_escape_bvh_trace_view {
  lt_trace_batch batch;
  LT_GLOBAL const lt_escape_node *nodes;
  LT_GLOBAL const lt_tri *tris;
  lt_i32 node_count;
} lt_escape_bvh_trace_view;

#define LT_ESCAPE_BVH_TRACE_ARGS(X)      \
  LT_TRACE_BATCH_ARGS(X, batch)          \
  X(BUF, lt_escape_node, nodes, nodes)   \
  X(BUF, lt_tri, tris, tris)             \
  X(VAL, lt_i32, node_count, node_count)

LT_DEVICE int lt_escape_bvh_trace_one(const lt_escape_bvh_trace_view *v, lt_i32 i, lt_trace_counters *c) {
  LT_GLOBAL const float *ray = v->batch.rays + 8 * (long)i;
  lt_ray_setup r = lt_ray_prepare(ray[0], ray[1], ray[2], ray[3], ray[4], ray[5], ray[6], ray[7]);
  r.flags = v->batch.flags;
  lt_hit_record hit;
  lt_escape_bvh_traverse(v->nodes, v->node_count, v->tris, &r, &hit, c);
  lt_trace_batch_put(&v->batch, i, hit);
  return 0;
}

#endif
