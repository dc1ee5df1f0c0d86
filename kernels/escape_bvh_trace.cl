/* Entry point of the escape-index BVH's trace kernel (kernels/escape_bvh_trace.h); the native
 * backend's twin is made from the same body in kernels/native_escape_bvh_trace.c. */
#include "kernels/escape_bvh_trace.h"

#define LT_TRACE_ENTRY lt_escape_bvh_trace
#define LT_TRACE_VIEW lt_escape_bvh_trace_view
#define LT_TRACE_ARGS LT_ESCAPE_BVH_TRACE_ARGS
#define LT_TRACE_ONE lt_escape_bvh_trace_one
#include "kernels/trace_kernel_body.h"
