/* Entry point of the uniform grid's trace kernel (kernels/grid_trace.h); the native backend's
 * twin is made from the same body in kernels/native_grid_trace.c. */
#include "kernels/grid_trace.h"

#define LT_TRACE_ENTRY lt_grid_trace
#define LT_TRACE_VIEW lt_grid_trace_view
#define LT_TRACE_ARGS LT_GRID_TRACE_ARGS
#define LT_TRACE_ONE lt_grid_trace_one
#include "kernels/trace_kernel_body.h"
