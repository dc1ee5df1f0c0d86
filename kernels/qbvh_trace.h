/* The trace kernel of the QBVH (device/qbvh_node.h, traversal/qbvh_traverse.h): one ray at a
 * time through the four-wide traversal; leaves are triangles in leaf order. */
#ifndef LT_KERNEL_QBVH_TRACE_H
#define LT_KERNEL_QBVH_TRACE_H

#include "kernels/trace_kernel.h"
#include "traversal/qbvh_traverse.h"

typedef struct lt_qbvh_trace_view {
  lt_trace_batch batch;
  LT_GLOBAL const lt_qbvh_node *nodes;
  LT_GLOBAL const lt_tri *tris;
} lt_qbvh_trace_view;

#define LT_QBVH_TRACE_ARGS(X)           \
  LT_TRACE_BATCH_ARGS(X, batch)         \
  X(BUF, lt_qbvh_node, nodes, nodes)    \
  X(BUF, lt_tri, tris, tris)

LT_DEVICE int lt_qbvh_trace_one(const lt_qbvh_trace_view *v, lt_i32 i, lt_trace_counters *c) {
  LT_GLOBAL const float *ray = v->batch.rays + 8 * (long)i;
  lt_ray_setup r = lt_ray_prepare(ray[0], ray[1], ray[2], ray[3], ray[4], ray[5], ray[6], ray[7]);
  r.flags = v->batch.flags;
  lt_hit_record hit;
  lt_i32 deepest = 0;
  int status = lt_qbvh_traverse(v->nodes, v->tris, &r, &hit, c, &deepest);
  lt_trace_batch_put(&v->batch, i, hit);
  return status;
}

#endif
