/* Entry point of the trace kernel of finished irregular grids (kernels/irgrid_trace.h); the
 * native backend's twin is made from the same body in kernels/native_irgrid_trace.c. */
#include "kernels/irgrid_trace.h"

#define LT_TRACE_ENTRY lt_irg_trace
#define LT_TRACE_VIEW lt_irg_trace_view
#define LT_TRACE_ARGS LT_IRG_TRACE_ARGS
#define LT_TRACE_ONE lt_irg_trace_one
#include "kernels/trace_kernel_body.h"
