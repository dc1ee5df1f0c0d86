/* The native irregular grid trace kernel (kernels/native_irgrid_trace_body.h) compiled a second
 * time for CPUs with AVX2 and BMI2, which lt__native_irgrid_trace_kernel picks at run time; the
 * library itself stays baseline x86-64. The walk gains from the three-operand forms and BMI2's
 * shifts by a variable count (the voxel map's lookups): about 5% fewer instructions. The floats
 * are the same: no fused multiply-adds (the build turns contraction off), and scalar and
 * 128-bit AVX arithmetic rounds as SSE's does, so the hits are bit for bit the baseline's. */
#define LT_IRG_CELL16_ONLY 1 /* for 16-byte cells, as the baseline build (native_irgrid_trace.c) */
#include "kernels/native_kernels.h"

#if LT_NATIVE_AVX2_CLONES
#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx2,bmi,bmi2"))), apply_to = function)
#else
#pragma GCC target("avx2,bmi,bmi2")
#endif
#define LT_IRG_TRACE_NAME lt__native_irgrid_trace_avx2
#define LT_IRG_GLIDE_SSE41 1 /* the fast walk's certificates on three lanes (traversal/irgrid_glide_sse41.h) */
#include "kernels/native_irgrid_trace_body.h"
#if defined(__clang__)
#pragma clang attribute pop
#endif
#endif
