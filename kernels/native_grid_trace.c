/* The uniform grid's trace kernel compiled as C for the native backend. */
#include "kernels/native_kernels.h"

#include "kernels/grid_trace.h"

#define LT_TRACE_NATIVE lt__native_grid_trace_kernel
#define LT_TRACE_VIEW lt_grid_trace_view
#define LT_TRACE_ONE lt_grid_trace_one
#include "kernels/trace_kernel_body.h"
