/* The trace kernel of finished irregular grids compiled as C for the native backend; on x86 a
 * cell's triangles are tested four at a time (traversal/watertight4.h, the same hits). */
#include "kernels/native_kernels.h"

#if defined(__SSE2__)
#include "traversal/watertight4.h"
#define LT_IRG_WATERTIGHT4 1
#endif
#include "kernels/irgrid_trace.h"

#define LT_TRACE_NATIVE lt__native_irgrid_trace_kernel
#define LT_TRACE_VIEW lt_irg_trace_view
#define LT_TRACE_ONE lt_irg_trace_one
#include "kernels/trace_kernel_body.h"
