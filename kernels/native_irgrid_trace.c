/* The trace kernel of finished irregular grids compiled as C for the native backend. */
#include "kernels/native_kernels.h"

#include "kernels/irgrid_trace.h"

#define LT_TRACE_NATIVE lt__native_irgrid_trace_kernel
#define LT_TRACE_VIEW lt_irg_trace_view
#define LT_TRACE_ONE lt_irg_trace_one
#include "kernels/trace_kernel_body.h"
