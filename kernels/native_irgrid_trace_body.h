/* The native trace kernel of finished irregular grids, instantiated by include for 16-byte
 * cells once for baseline x86-64 (native_irgrid_trace.c) and once for AVX2 and BMI2
 * (native_irgrid_trace_avx2.c), and for cells of either layout once (native_irgrid_trace_wide.c):
 *
 *   #define LT_IRG_TRACE_NAME   the function's name (void fn(void *launch))
 *   #define LT_IRG_CELL16_ONLY  1 for 16-byte cells only, before any include (device/irgrid_cells.h)
 *   #define LT_IRG_GLIDE_SSE41  1 for the fast walk in SSE4.1 lanes, with rays in flight together
 *
 * On x86 a cell's triangles are tested four at a time (traversal/watertight4.h, the same hits).
 * Native only; no include guard. */
#if defined(__SSE2__)
#include "traversal/watertight4.h"
#define LT_IRG_WATERTIGHT4 1
#endif
#include "kernels/irgrid_trace.h"

#if LT_IRG_GLIDE_SSE41
/* Rays in flight on one thread: each step of one ray is a chain of dependent loads and
 * arithmetic (the cell, its faces, the next voxel, its lookup), so the steps of a few rays taken
 * in turn overlap. Two measured faster than four or eight (docs/notes/irgrid.md, "The fast
 * walk"). */
#define LT_IRG_IN_FLIGHT 2

/* Rays [begin, end): each slot holds a ray on the fast walk, refilled as rays are answered. */
static int lt_irg_trace_range(const lt_irg_trace_view *t, lt_i32 begin, lt_i32 end, lt_trace_counters *c) {
  lt_irg_view v = lt_irg_trace_walk_view(t);
  lt_irg_glide_grid g = lt_irg_glide_grid_of(v.header);
  int flags = t->batch.flags, error = 0;
  lt_irg_glider s[LT_IRG_IN_FLIGHT];
  lt_i32 ray[LT_IRG_IN_FLIGHT], next = begin;
  for (int k = 0; k < LT_IRG_IN_FLIGHT; k++) ray[k] = -1;
  for (;;) {
    int flying = 0;
    for (int k = 0; k < LT_IRG_IN_FLIGHT; k++) {
      int r = 0;
      if (ray[k] < 0) {
        while (ray[k] < 0 && next < end) {
          lt_irg_ray_start(&s[k].q, t->batch.rays + 8 * (long)next, flags);
          if (lt_irg_glide_begin(&v, &g, &s[k], flags)) lt_trace_batch_put(&t->batch, next, s[k].q.hit);
          else ray[k] = next;
          next++;
        }
        if (ray[k] < 0) continue;
      } else {
        r = lt_irg_glide_step(&v, &g, &s[k], flags, c);
        if (r < 0) r = lt_irg_advance(&v, &s[k].q, flags, c) ? 1 : (error = 1);
      }
      if (r > 0) {
        lt_trace_batch_put(&t->batch, ray[k], s[k].q.hit);
        ray[k] = -1;
      }
      flying = 1;
    }
    if (!flying) break;
  }
  return error;
}
#define LT_TRACE_RANGE lt_irg_trace_range
#endif

void LT_IRG_TRACE_NAME(void *arg);
#define LT_TRACE_NATIVE LT_IRG_TRACE_NAME
#define LT_TRACE_VIEW   lt_irg_trace_view
#if !LT_IRG_GLIDE_SSE41
#define LT_TRACE_ONE    lt_irg_trace_one
#endif
#include "kernels/trace_kernel_body.h"
#undef LT_IRG_TRACE_NAME
