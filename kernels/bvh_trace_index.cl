/* Entry point of the trace kernel of BVHs the pool has finished (kernels/bvh_trace.h); the
 * native backend's twin is made from the same body in kernels/native_bvh_trace_index.c. */
#include "kernels/bvh_trace.h"

#define LT_TRACE_ENTRY lt_bvh_trace_index
#define LT_TRACE_VIEW lt_bvh_index_view
#define LT_TRACE_ARGS LT_BVH_INDEX_ARGS
#define LT_TRACE_ONE lt_bvh_trace_index_one
#include "kernels/trace_kernel_body.h"
