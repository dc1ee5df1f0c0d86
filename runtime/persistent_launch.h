/* Launches of a persistent kernel (kernels/persistent_loop_body.h) on either backend: exactly
 * as many work-groups as run at once, because its work-groups wait on each other. */
#ifndef LT_PERSISTENT_LAUNCH_H
#define LT_PERSISTENT_LAUNCH_H

#include "runtime/trace_launch.h"

/* A workload's kernel: its OpenCL entry, its native twin (an lt__native_launch), and the
 * generated argument functions of its argument list (runtime/kernel_args_host.h). */
typedef struct lt__persistent_kernel {
  const char *entry;
  void (*native)(void *launch);
  lt__set_args_fn set_args;
  void (*view)(const void *args, void *view);
} lt__persistent_kernel;

/* One launch over the workload's host arguments `args` (view_storage: room for its native
 * view). The set-up launch (setup = 1) makes the root: on OpenCL it has the shape of the
 * others, because PoCL compiles a kernel for the shape of its first launch (counted as compile
 * time), and only work-group 0 works in it; on native it runs one work-group. On the native
 * backend a launch is watched: after stall_seconds without progress in the pool whose control
 * block is `control`, it ends with the pool's stall error. */
lt_status lt__persistent_launch(lt_context *ctx, const lt__persistent_kernel *kernel, const void *args,
                                        void *view_storage, int setup, lt__buffer *control, int stall_seconds);

#endif
