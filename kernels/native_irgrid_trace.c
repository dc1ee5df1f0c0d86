/* The trace kernel of finished irregular grids compiled as C for the native backend
 * (kernels/native_irgrid_trace_body.h), and the choice between its baseline and AVX2 builds. */
#include "kernels/native_kernels.h"

#define LT_IRG_TRACE_NAME lt__native_irgrid_trace_baseline
#include "kernels/native_irgrid_trace_body.h"

void lt__native_irgrid_trace_kernel(void *arg) {
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
