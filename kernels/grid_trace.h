/* The trace kernel of the uniform grid (device/grid_cells.h, traversal/grid_traverse.h): one
 * ray at a time, triangles read from the scene's vertices through the cells' references. */
#ifndef LT_KERNEL_GRID_TRACE_H
#define LT_KERNEL_GRID_TRACE_H

#include "kernels/trace_kernel.h"
#include "traversal/grid_traverse.h"

typedef struct lt_grid_trace_view {
  lt_trace_batch batch;
  LT_GLOBAL const lt_grid_header *header;
  LT_GLOBAL const lt_i32 *cells; /* cell_begin: dims.w + 1 offsets into refs */
  LT_GLOBAL const lt_i32 *refs;
  LT_GLOBAL const float *verts;  /* the scene's, 9 floats a triangle */
} lt_grid_trace_view;

#define LT_GRID_TRACE_ARGS(X)              \
  LT_TRACE_BATCH_ARGS(X, batch)            \
  X(BUF, lt_grid_header, header, header)   \
  X(BUF, lt_i32, cells, cells)             \
  X(BUF, lt_i32, refs, refs)               \
  X(BUF, float, verts, verts)

LT_DEVICE int lt_grid_trace_one(const lt_grid_trace_view *v, lt_i32 i, lt_trace_counters *c) {
  LT_GLOBAL const float *ray = v->batch.rays + 8 * (long)i;
  lt_ray_setup r = lt_ray_prepare(ray[0], ray[1], ray[2], ray[3], ray[4], ray[5], ray[6], ray[7]);
  r.flags = v->batch.flags;
  lt_hit_record hit;
  int status = lt_grid_traverse(&r, v->header, v->cells, v->refs, v->verts, v->batch.flags & LT_QUERY_FLAG_ANY, &hit, c);
  lt_trace_batch_put(&v->batch, i, hit);
  return status;
}

#endif
