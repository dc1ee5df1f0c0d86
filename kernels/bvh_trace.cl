/* Entry point of the trace kernel of host-built BVHs (kernels/bvh_trace.h); the native
 * backend's twin is made from the same body in kernels/native_bvh_trace.c. */
#include "kernels/bvh_trace.h"

#define LT_TRACE_ENTRY lt_bvh_trace
#define LT_TRACE_VIEW lt_bvh_trace_view
#define LT_TRACE_ARGS LT_BVH_TRACE_ARGS
#define LT_TRACE_ONE lt_bvh_trace_one
#include "kernels/trace_kernel_body.h"
