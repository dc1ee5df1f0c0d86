/* The trace kernels of finished BVHs, one ray at a time through the one BVH traversal body
 * (traversal/bvh_traverse.h): lt_bvh_trace for trees built on the host (the LBVH, the sweep
 * builder; leaves are triangles in leaf order), lt_bvh_trace_index for trees the pool has
 * finished (leaves are triangle numbers into the scene's vertices), which a full build traces
 * with instead of the persistent kernel. */
#ifndef LT_KERNEL_BVH_TRACE_H
#define LT_KERNEL_BVH_TRACE_H

#include "kernels/trace_kernel.h"
#include "traversal/bvh_traverse.h"

typedef struct lt_bvh_trace_view {
  lt_trace_batch batch;
  LT_GLOBAL const lt_bvh_node *nodes;
  LT_GLOBAL const lt_tri *tris;
} lt_bvh_trace_view;

#define LT_BVH_TRACE_ARGS(X)            \
  LT_TRACE_BATCH_ARGS(X, batch)         \
  X(BUF, lt_bvh_node, nodes, nodes)     \
  X(BUF, lt_tri, tris, tris)

LT_DEVICE int lt_bvh_trace_one(const lt_bvh_trace_view *v, lt_i32 i, lt_trace_counters *c) {
  lt_bvh_view tree;
  tree.nodes = v->nodes, tree.tris = v->tris, tree.index = 0, tree.verts = 0, tree.pool = 0;
  lt_bvh_ray q;
  lt_bvh_ray_start(&q, v->batch.rays + 8 * (long)i);
  lt_bvh_advance_tris(&tree, &q, v->batch.flags, c);
  lt_trace_batch_put(&v->batch, i, q.hit);
  return q.overflow ? -1 : 0;
}

typedef struct lt_bvh_index_view {
  lt_trace_batch batch;
  LT_GLOBAL const lt_bvh_node *nodes;
  LT_GLOBAL const lt_i32 *index;
  LT_GLOBAL const float *verts;
} lt_bvh_index_view;

#define LT_BVH_INDEX_ARGS(X)            \
  LT_TRACE_BATCH_ARGS(X, batch)         \
  X(BUF, lt_bvh_node, nodes, nodes)     \
  X(BUF, lt_i32, index, index)          \
  X(BUF, float, verts, verts)

LT_DEVICE int lt_bvh_trace_index_one(const lt_bvh_index_view *v, lt_i32 i, lt_trace_counters *c) {
  lt_bvh_view tree;
  tree.nodes = v->nodes, tree.tris = 0, tree.index = v->index, tree.verts = v->verts, tree.pool = 0;
  lt_bvh_ray q;
  lt_bvh_ray_start(&q, v->batch.rays + 8 * (long)i);
  lt_bvh_advance_index(&tree, &q, v->batch.flags, c);
  lt_trace_batch_put(&v->batch, i, q.hit);
  return q.overflow ? -1 : 0;
}

#endif
