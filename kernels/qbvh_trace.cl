/* Entry point of the QBVH's trace kernel (kernels/qbvh_trace.h); the native backend's twin is
 * made from the same body in kernels/native_qbvh_trace.c. */
#include "kernels/qbvh_trace.h"

#define LT_TRACE_ENTRY lt_qbvh_trace
#define LT_TRACE_VIEW lt_qbvh_trace_view
#define LT_TRACE_ARGS LT_QBVH_TRACE_ARGS
#define LT_TRACE_ONE lt_qbvh_trace_one
#include "kernels/trace_kernel_body.h"
