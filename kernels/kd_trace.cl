/* Entry point of the trace kernel of finished kd-trees (kernels/kd_trace.h); the native
 * backend's twin is made from the same body in kernels/native_kd_trace.c. */
#include "kernels/kd_trace.h"

#define LT_TRACE_ENTRY lt_kd_trace
#define LT_TRACE_VIEW lt_kd_trace_view
#define LT_TRACE_ARGS LT_KD_TRACE_ARGS
#define LT_TRACE_ONE lt_kd_trace_one
#include "kernels/trace_kernel_body.h"
