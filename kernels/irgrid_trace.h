/* The trace kernel of a finished irregular grid (a full build, or one whose top cells are all
 * built): one ray at a time through traversal/irgrid_traverse.h, without the persistent
 * kernel's rounds. */
#ifndef LT_KERNEL_IRGRID_TRACE_H
#define LT_KERNEL_IRGRID_TRACE_H

#include "kernels/trace_kernel.h"
#include "traversal/irgrid_glide.h"

typedef struct lt_irg_trace_view {
  lt_trace_batch batch;
  LT_GLOBAL const lt_grid_header *header;
  LT_GLOBAL const lt_i32 *top_map;
  LT_GLOBAL const lt_i32 *sub_maps;
  LT_GLOBAL const lt_irg_cell *cells; /* lt_irg_cell16 when narrow */
  LT_GLOBAL const lt_i32 *refs;
  LT_GLOBAL const float *verts;
  lt_int4 fine_dims;
  lt_i32 shift;
  lt_i32 narrow; /* 1: the cells are a compacted grid's lt_irg_cell16, their lists packed */
} lt_irg_trace_view;

#define LT_IRG_TRACE_ARGS(X)                 \
  LT_TRACE_BATCH_ARGS(X, batch)              \
  X(BUF, lt_grid_header, header, header)     \
  X(BUF, lt_i32, top_map, top_map)           \
  X(BUF, lt_i32, sub_maps, sub_maps)         \
  X(BUF, lt_irg_cell, cells, cells)          \
  X(BUF, lt_i32, refs, refs)                 \
  X(BUF, float, verts, verts)                \
  X(VAL, lt_int4, fine_dims, fine_dims)      \
  X(VAL, lt_i32, shift, shift)               \
  X(VAL, lt_i32, narrow, narrow)

/* What the walk reads, from the kernel's view. */
LT_DEVICE lt_irg_view lt_irg_trace_walk_view(const lt_irg_trace_view *t) {
  lt_irg_view v;
  v.header = t->header, v.top_map = t->top_map, v.sub_maps = t->sub_maps, v.cells = t->cells;
  v.cells16 = t->narrow ? (LT_GLOBAL const lt_irg_cell16 *)t->cells : 0;
  v.refs = t->refs, v.verts = t->verts, v.pool = 0, v.fine_dims = t->fine_dims, v.shift = t->shift;
  return v;
}

/* One ray at a time (the native AVX2 kernel steps two at a time instead:
 * kernels/native_irgrid_trace_body.h). */
#if !LT_IRG_GLIDE_SSE41
LT_DEVICE int lt_irg_trace_one(const lt_irg_trace_view *t, lt_i32 i, lt_trace_counters *c) {
  lt_irg_view v = lt_irg_trace_walk_view(t);
  lt_irg_ray q;
  lt_irg_ray_start(&q, t->batch.rays + 8 * (long)i, t->batch.flags);
  int done = lt_irg_glide(&v, &q, t->batch.flags, c) || lt_irg_advance(&v, &q, t->batch.flags, c);
  lt_trace_batch_put(&t->batch, i, q.hit);
  return done ? 0 : -1;
}
#endif

#endif
