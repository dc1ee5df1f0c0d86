/* Launches of a finished structure's trace kernel (kernels/trace_kernel_body.h) over one batch
 * of rays, on either backend. A structure sets its own arguments (from its LT__KERNEL_ARGS
 * list, with the batch's buffers in it) and hands over the kernel or the native function. */
#ifndef LT_TRACE_LAUNCH_H
#define LT_TRACE_LAUNCH_H

#include <stdint.h>

#include "device/compat.h"
#include "runtime/buffer.h"

/* Sets a kernel's own arguments (runtime/kernel_args_host.h, name##_set_any). */
typedef cl_int (*lt__set_args_fn)(cl_kernel kernel, const void *args, cl_uint *next);
/* Everything a finished structure's trace needs from it: its trace kernel (the OpenCL entry,
 * the native twin, and the generated argument functions of runtime/kernel_args_host.h), its
 * host arguments with the structure's own entries filled in, where the batch's entries are in
 * them, and room for the native view. */
typedef struct lt__trace_call {
  const char *entry;
  void (*native)(void *launch);
  lt__set_args_fn set_args;
  void (*view)(const void *args, void *view);
  void *args;
  lt__buffer **rays, **hits; /* the batch's entries in args (LT_TRACE_BATCH_ARGS) */
  lt_i32 *ray_count, *flags;
  void *view_storage;
} lt__trace_call;

/* Traces a batch through a finished structure on ctx's backend; adds trace_ms (compile time
 * taken out), traversal steps and intersections to stats (may be NULL). */
lt_status lt__trace_finished(lt_context *ctx, const lt__trace_call *call, const lt_ray *rays, int count, int flags,
                             lt_hit *hits, lt_stats *stats);

#endif
