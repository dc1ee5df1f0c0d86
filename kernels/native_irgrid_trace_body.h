/* The native trace kernel of finished irregular grids, instantiated by include for 16-byte
 * cells once for baseline x86-64 (native_irgrid_trace.c) and once for AVX2 and BMI2
 * (native_irgrid_trace_avx2.c), and for cells of either layout once (native_irgrid_trace_wide.c):
 *
 *   #define LT_IRG_TRACE_NAME   the function's name (void fn(void *launch))
 *   #define LT_IRG_CELL16_ONLY  1 for 16-byte cells only, before any include (device/irgrid_cells.h)
 *
 * On x86 a cell's triangles are tested four at a time (traversal/watertight4.h, the same hits).
 * Native only; no include guard. */
#if defined(__SSE2__)
#include "traversal/watertight4.h"
#define LT_IRG_WATERTIGHT4 1
#endif
#include "kernels/irgrid_trace.h"

void LT_IRG_TRACE_NAME(void *arg);
#define LT_TRACE_NATIVE LT_IRG_TRACE_NAME
#define LT_TRACE_VIEW   lt_irg_trace_view
#define LT_TRACE_ONE    lt_irg_trace_one
#include "kernels/trace_kernel_body.h"
#undef LT_IRG_TRACE_NAME
