/* The QBVH's native 8-wide trace kernel (kernels/bvh8_trace.h), made from the shared body. */
#include "kernels/native_kernels.h"

#if defined(__x86_64__)
#include "kernels/bvh8_trace.h"

#define LT_TRACE_NATIVE lt__native_bvh8_trace_kernel
#define LT_TRACE_VIEW   lt_bvh8_trace_view
#define LT_TRACE_RANGE  lt_bvh8_trace_range
#define LT_TRACE_STATE  lt_bvh8_occluders
#include "kernels/trace_kernel_body.h"
#endif
