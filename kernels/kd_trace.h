/* The trace kernel of a finished kd-tree (a full build): one ray at a time through the stack
 * traversal (traversal/kd_traverse.h) or a stackless one (traversal/kd_stackless.h), without
 * the persistent kernel's rounds. */
#ifndef LT_KERNEL_KD_TRACE_H
#define LT_KERNEL_KD_TRACE_H

#include "kernels/trace_kernel.h"
#include "traversal/kd_stackless.h"

typedef struct lt_kd_trace_view {
  lt_trace_batch batch;
  LT_GLOBAL const lt_kd_node *nodes;
  LT_GLOBAL const lt_i32 *refs;
  LT_GLOBAL const float *verts;
  LT_GLOBAL const lt_i32 *parents;
  LT_GLOBAL const float *cells;
  lt_float4 root_lo, root_hi; /* the scene's bounds: the root cell */
  lt_i32 traversal;           /* LT_KD_TRAVERSE_* */
} lt_kd_trace_view;

#define LT_KD_TRACE_ARGS(X)                \
  LT_TRACE_BATCH_ARGS(X, batch)            \
  X(BUF, lt_kd_node, nodes, nodes)         \
  X(BUF, lt_i32, refs, refs)               \
  X(BUF, float, verts, verts)              \
  X(BUF, lt_i32, parents, parents)         \
  X(BUF, float, cells, cells)              \
  X(VAL, lt_float4, root_lo, root_lo)      \
  X(VAL, lt_float4, root_hi, root_hi)      \
  X(VAL, lt_i32, traversal, traversal)

LT_DEVICE int lt_kd_trace_one(const lt_kd_trace_view *v, lt_i32 i, lt_trace_counters *c) {
  lt_kd_view tree;
  tree.nodes = v->nodes, tree.refs = v->refs, tree.verts = v->verts, tree.parents = v->parents;
  tree.cells = v->cells, tree.pool = 0;
  tree.bounds.lo[0] = v->root_lo.x, tree.bounds.lo[1] = v->root_lo.y, tree.bounds.lo[2] = v->root_lo.z;
  tree.bounds.hi[0] = v->root_hi.x, tree.bounds.hi[1] = v->root_hi.y, tree.bounds.hi[2] = v->root_hi.z;
  lt_kd_ray q;
  lt_kd_ray_start(&q, v->batch.rays + 8 * (long)i, &tree.bounds);
  if (v->traversal == LT_KD_TRAVERSE_STACK) lt_kd_advance(&tree, &q, v->batch.flags, c);
  else lt_kd_advance_stackless(&tree, &q, v->batch.flags, v->traversal == LT_KD_TRAVERSE_BACKTRACK, c);
  lt_trace_batch_put(&v->batch, i, q.hit);
  return q.overflow ? -1 : 0;
}

#endif
