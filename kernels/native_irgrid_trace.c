/* The trace kernel of finished irregular grids compiled as C for the native backend
 * (kernels/native_irgrid_trace_body.h), and the choice between its builds: for 16-byte cells
 * (what compaction makes whenever the fine grid fits 16 bits a side), baseline here and AVX2 in
 * native_irgrid_trace_avx2.c; for either layout, read cell by cell, in
 * native_irgrid_trace_wide.c (the 32-byte cells of larger fine grids). */
#define LT_IRG_CELL16_ONLY 1
#include "kernels/native_kernels.h"

#define LT_IRG_TRACE_NAME lt__native_irgrid_trace_baseline
#include "kernels/native_irgrid_trace_body.h"

void lt__native_irgrid_trace_kernel(void *arg) {
  const lt_irg_trace_view *view = ((const lt__native_trace_launch *)arg)->view;
  if (!view->narrow) {
    lt__native_irgrid_trace_wide(arg);
    return;
  }
#if LT_NATIVE_AVX2_CLONES
  /* Asked at every launch: the answer never changes, and a launch traces a whole batch. */
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("bmi2")) {
    lt__native_irgrid_trace_avx2(arg);
    return;
  }
#endif
  lt__native_irgrid_trace_baseline(arg);
}
