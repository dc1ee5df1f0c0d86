/* The escape-index BVH's trace kernel compiled as C for the native backend. */
#include "kernels/native_kernels.h"

#include "kernels/escape_bvh_trace.h"

#define LT_TRACE_NATIVE lt__native_escape_bvh_trace_kernel
#define LT_TRACE_VIEW lt_escape_bvh_trace_view
#define LT_TRACE_ONE lt_escape_bvh_trace_one
#include "kernels/trace_kernel_body.h"
