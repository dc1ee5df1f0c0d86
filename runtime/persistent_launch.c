/* Launches of a persistent kernel (see persistent_launch.h). */
#include "runtime/persistent_launch.h"

#include "device/pool.h"
#include "kernels/native_kernels.h"
#include "runtime/context_internal.h"

lt_status lt__persistent_launch(lt_context *ctx, const lt__persistent_kernel *kernel, const void *args,
                                        void *view_storage, int setup, lt__buffer *control, int stall_seconds) {
  int groups = setup && ctx->kind == LT_DEVICE_NATIVE ? 1 : ctx->work_groups;
  if (ctx->kind == LT_DEVICE_NATIVE) {
    kernel->view(args, view_storage);
    lt__native_launch native = {view_storage, setup};
    lt_pool_control *c = control && !setup ? control->host : NULL;
    lt__native_watch watch = {c ? &c->progress : NULL, c ? &c->error : NULL, LT_POOL_ERROR_STALL, (double)stall_seconds};
    return lt__native_run_watched(groups, kernel->native, &native, c ? &watch : NULL);
  }
  lt__kernel *k;
  lt_status status = lt__opencl_kernel(ctx, kernel->entry, &k);
  if (status) return status;
  cl_uint next;
  cl_int err = kernel->set_args(k->kernel, args, &next);
  err |= clSetKernelArg(k->kernel, next, sizeof setup, &setup);
  if ((status = lt__opencl_check(err, kernel->entry))) return status;
  return lt__opencl_run(ctx, k, (size_t)groups, kernel->entry);
}
