/* The native irregular grid trace kernel (kernels/native_irgrid_trace_body.h) for a compacted
 * grid of either cell layout, which it tells at every cell read (lt_irg_cell_get): the one
 * lt__native_irgrid_trace_kernel runs on the 32-byte cells that compaction keeps when the fine
 * grid is wider than 16 bits. Baseline x86-64 only: such grids are rare. */
#include "kernels/native_kernels.h"

#define LT_IRG_TRACE_NAME lt__native_irgrid_trace_wide
#include "kernels/native_irgrid_trace_body.h"
