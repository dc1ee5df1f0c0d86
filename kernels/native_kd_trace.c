/* The trace kernel of finished kd-trees compiled as C for the native backend. */
#include "kernels/native_kernels.h"

#include "kernels/kd_trace.h"

#define LT_TRACE_NATIVE lt__native_kd_trace_kernel
#define LT_TRACE_VIEW lt_kd_trace_view
#define LT_TRACE_ONE lt_kd_trace_one
#include "kernels/trace_kernel_body.h"
