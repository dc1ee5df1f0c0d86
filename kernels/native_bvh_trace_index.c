/* The trace kernel of pool-finished BVHs compiled as C for the native backend. */
#include "kernels/native_kernels.h"

#include "kernels/bvh_trace.h"

#define LT_TRACE_NATIVE lt__native_bvh_trace_index_kernel
#define LT_TRACE_VIEW lt_bvh_index_view
#define LT_TRACE_ONE lt_bvh_trace_index_one
#include "kernels/trace_kernel_body.h"
