/* Native entries of the kernels: each runs on every native work-group (see lt__native_run). */
#ifndef LT_NATIVE_KERNELS_H
#define LT_NATIVE_KERNELS_H

#include "kernels/trace_kernel.h"

/* A launch of a persistent kernel: the workload's view struct, which every work-group copies,
 * and whether this is the set-up launch (one work-group) that makes the root. */
typedef struct lt__native_launch {
  const void *view;
  int setup;
} lt__native_launch;

/* kernels/native_lazy_sort.c: arg is an lt__native_launch over an lt_sort_args. */
void lt__native_lazy_sort_kernel(void *arg);
/* kernels/native_bvh_ondemand.c: arg is an lt__native_launch over an lt_od_args. */
void lt__native_bvh_ondemand_kernel(void *arg);
/* kernels/native_kd_ondemand.c: arg is an lt__native_launch over an lt_kd_args. */
void lt__native_kd_ondemand_kernel(void *arg);
/* kernels/native_bvh_trace.c: arg is an lt__native_trace_launch over an lt_bvh_trace_view. */
void lt__native_bvh_trace_kernel(void *arg);
/* kernels/native_bvh_trace_index.c: arg is an lt__native_trace_launch over an lt_bvh_index_view. */
void lt__native_bvh_trace_index_kernel(void *arg);
/* kernels/native_kd_trace.c: arg is an lt__native_trace_launch over an lt_kd_trace_view. */
void lt__native_kd_trace_kernel(void *arg);
/* kernels/native_grid_trace.c: arg is an lt__native_trace_launch over an lt_grid_trace_view. */
void lt__native_grid_trace_kernel(void *arg);
/* kernels/native_irgrid_ondemand.c: arg is an lt__native_launch over an lt_irg_args. */
void lt__native_irgrid_ondemand_kernel(void *arg);
void lt__native_irgrid_merge_kernel(void *arg);
/* kernels/native_irgrid_trace.c: arg is an lt__native_trace_launch over an lt_irg_trace_view. */
void lt__native_irgrid_trace_kernel(void *arg);
/* kernels/native_irgrid_trace_wide.c: the same for cells of either layout (the 32-byte ones). */
void lt__native_irgrid_trace_wide(void *arg);
/* Kernels also compiled for AVX2 and BMI2 and chosen at run time (x86-64 with GCC or clang):
 * kernels/native_irgrid_trace_avx2.c. */
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define LT_NATIVE_AVX2_CLONES 1
void lt__native_irgrid_trace_avx2(void *arg);
#else
#define LT_NATIVE_AVX2_CLONES 0
#endif
/* kernels/native_qbvh_trace.c: arg is an lt__native_trace_launch over an lt_qbvh_trace_view. */
void lt__native_qbvh_trace_kernel(void *arg);
/* kernels/native_bvh8_trace.c (x86 with AVX2 only): arg is an lt__native_trace_launch over an
 * lt_bvh8_trace_view. */
void lt__native_bvh8_trace_kernel(void *arg);
/* kernels/native_escape_bvh_trace.c: arg is an lt__native_trace_launch over an lt_escape_bvh_trace_view. */
void lt__native_escape_bvh_trace_kernel(void *arg);

#endif
