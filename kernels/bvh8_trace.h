/* The trace kernel of the QBVH's native 8-wide path (device/bvh8_node.h,
 * traversal/bvh8_traverse.h): one ray at a time through the eight-box AVX2 traversal; leaves
 * are triangles in leaf order. Native backend only: runtime/structure_qbvh.c takes it where
 * the CPU has AVX2. */
#ifndef LT_KERNEL_BVH8_TRACE_H
#define LT_KERNEL_BVH8_TRACE_H

#include "kernels/trace_kernel.h"
#include "traversal/bvh8_traverse.h"

typedef struct lt_bvh8_trace_view {
  lt_trace_batch batch;
  const lt_bvh8_node *nodes;
  const lt_tri4 *blocks;
  const lt_tri *tris;
} lt_bvh8_trace_view;

#define LT_BVH8_TRACE_ARGS(X)           \
  LT_TRACE_BATCH_ARGS(X, batch)         \
  X(BUF, lt_bvh8_node, nodes, nodes)    \
  X(BUF, lt_tri4, blocks, blocks)       \
  X(BUF, lt_tri, tris, tris)

/* Kept out of line: the kernel's chunk loop is baseline x86-64, this function AVX2. */
LT_BVH8_TARGET __attribute__((noinline, unused)) static int lt_bvh8_trace_one(const lt_bvh8_trace_view *v, lt_i32 i,
                                                                     lt_trace_counters *c) {
  lt_ray_setup r;
  lt_bvh8_ray_prepare(v->batch.rays + 8 * (long)i, v->batch.flags, &r);
  lt_hit_record hit;
  int status = lt_bvh8_traverse_with(v->nodes, v->blocks, v->tris, &r, &hit, c, LT_BVH8_VECTOR);
  lt_trace_batch_put(&v->batch, i, hit);
  return status;
}

#endif
