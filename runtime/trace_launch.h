/* Launches of a finished structure's trace kernel (kernels/trace_kernel_body.h) over one batch
 * of rays, on either backend. A structure sets its own arguments (from its LT__KERNEL_ARGS
 * list, with the batch's buffers in it) and hands over the kernel or the native function. */
#ifndef LT_TRACE_LAUNCH_H
#define LT_TRACE_LAUNCH_H

#include <stdint.h>

#include "runtime/buffer.h"

typedef struct lt__trace_batch {
  lt__buffer rays, hits; /* on native, the caller's arrays themselves */
  int count;
  uint64_t traversal_steps, intersections; /* what the launch counted */
} lt__trace_batch;

/* The batch's buffers over the caller's rays and hits. */
lt_status lt__trace_batch_begin(lt_context *ctx, lt__trace_batch *batch, const lt_ray *rays, int count, lt_hit *hits);
/* Reads the hits back (OpenCL) and releases the buffers. */
lt_status lt__trace_batch_end(lt_context *ctx, lt__trace_batch *batch, lt_hit *hits, lt_status status);
/* OpenCL: the kernel's own arguments are set up to index `next`; this adds the counters and
 * the error flag, launches one work-item per ray and sums the counters. A stack overflow is
 * LT_ERROR_CAPACITY. */
lt_status lt__trace_opencl(lt_context *ctx, lt__kernel *kernel, cl_uint next, lt__trace_batch *batch);
/* Native: runs fn (an lt__native_trace_launch over `view`) on every work-group. */
lt_status lt__trace_native(lt_context *ctx, void (*fn)(void *), const void *view, lt__trace_batch *batch);

#endif
