/* Launches of a finished structure's trace kernel (see trace_launch.h). */
#include "runtime/trace_launch.h"

#include <stdlib.h>
#include <string.h>

#include "kernels/trace_kernel.h"
#include "runtime/error.h"
#include "runtime/stats_internal.h"

typedef struct trace_batch {
  lt__buffer rays, hits; /* on native, the caller's arrays themselves */
  int count;
  uint64_t traversal_steps, intersections; /* what the launch counted */
} trace_batch;

static lt_status trace_batch_begin(lt_context *ctx, trace_batch *batch, const lt_ray *rays, int count, lt_hit *hits) {
  memset(batch, 0, sizeof *batch);
  batch->count = count;
  return lt__batch_buffers_begin(ctx, &batch->rays, &batch->hits, rays, count, hits);
}

static lt_status trace_batch_end(lt_context *ctx, trace_batch *batch, lt_hit *hits, lt_status status) {
  return lt__batch_buffers_end(ctx, &batch->rays, &batch->hits, hits, batch->count, status);
}

static lt_status overflow(void) {
  return lt__fail(LT_ERROR_CAPACITY, "a traversal stack would overflow (the structure is deeper than its stack)");
}

/* PoCL compiles a kernel's work-group function at its first launch, and again for a launch of
 * a different scale (docs/notes/task_pool.md): the first launch has no rays and as many
 * work-groups as a large batch, so that the compile lands in compile time, not trace time. */
#define WARM_UP_GROUPS 1024

static lt_status trace_opencl(lt_context *ctx, const char *entry, lt__set_args_fn set_args, void *args, lt_i32 *ray_count,
                           trace_batch *batch) {
  lt__kernel *kernel;
  lt_status status = lt__opencl_kernel(ctx, entry, &kernel);
  if (status) return status;
  size_t groups = ((size_t)batch->count + (size_t)ctx->local_size - 1) / (size_t)ctx->local_size;
  lt__buffer counters, error;
  status = lt__buffer_create(ctx, &counters, 2 * (groups > WARM_UP_GROUPS ? groups : WARM_UP_GROUPS) * sizeof(lt_u32),
                             NULL, 0);
  if (status) return status;
  status = lt__buffer_create(ctx, &error, sizeof(int), NULL, 0);
  cl_uint next = 0;
  cl_int err = CL_SUCCESS;

  /* The first launch: no rays, counted as compile time (lt__opencl_run). */
  if (!status && !kernel->warm) {
    lt_i32 count = *ray_count;
    *ray_count = 0;
    err = set_args(kernel->kernel, args, &next);
    err |= clSetKernelArg(kernel->kernel, next, sizeof(cl_mem), &counters.mem);
    err |= clSetKernelArg(kernel->kernel, next + 1, sizeof(cl_mem), &error.mem);
    *ray_count = count;
    status = lt__opencl_check(err, "setting trace kernel arguments");
    if (!status) status = lt__opencl_run(ctx, kernel, WARM_UP_GROUPS, "warming up the trace kernel");
  }

  /* Every ray, with the counters of each work-group in a slot of its own. */
  if (!status) {
    err = set_args(kernel->kernel, args, &next);
    err |= clSetKernelArg(kernel->kernel, next, sizeof(cl_mem), &counters.mem);
    err |= clSetKernelArg(kernel->kernel, next + 1, sizeof(cl_mem), &error.mem);
    status = lt__opencl_check(err, "setting trace kernel arguments");
  }
  if (!status) status = lt__opencl_run(ctx, kernel, groups, "running the trace kernel");
  lt_u32 *sums = status ? NULL : malloc(2 * groups * sizeof *sums);
  int failed = 0;
  if (!status && !sums) status = lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory reading trace counters");
  if (!status) status = lt__buffer_read(ctx, &counters, 0, 2 * groups * sizeof *sums, sums);
  if (!status) status = lt__buffer_read(ctx, &error, 0, sizeof failed, &failed);
  for (size_t g = 0; !status && g < groups; g++)
    batch->traversal_steps += sums[2 * g], batch->intersections += sums[2 * g + 1];
  free(sums);
  lt__buffer_release(&counters);
  lt__buffer_release(&error);
  return !status && failed ? overflow() : status;
}

static lt_status trace_native(lt_context *ctx, void (*fn)(void *), const void *view, trace_batch *batch) {
  /* Each work-group's share of the rays: a contiguous stretch, as equal as the count allows. */
  int groups = ctx->work_groups;
  lt__native_trace_share *shares = aligned_alloc(_Alignof(lt__native_trace_share), groups * sizeof *shares);
  if (!shares) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory for %d work-groups' shares of rays", groups);
  for (int g = 0; g < groups; g++) {
    shares[g].next = (lt_u32)((uint64_t)batch->count * (uint64_t)g / (uint64_t)groups);
    shares[g].end = (lt_u32)((uint64_t)batch->count * (uint64_t)(g + 1) / (uint64_t)groups);
  }
  lt__native_trace_launch launch = {view, shares, 0, 0, 0};
  lt_status status = lt__native_run(groups, fn, &launch);
  free(shares);
  batch->traversal_steps += launch.traversal_steps, batch->intersections += launch.intersections;
  return !status && launch.error ? overflow() : status;
}

lt_status lt__trace_finished(lt_context *ctx, const lt__trace_call *call, const lt_ray *rays, int count, int flags,
                             lt_hit *hits, lt_stats *stats) {
  /* The kernel's first launch is compile time (lt__opencl_run), taken out of the trace time. */
  double start = lt_now_ms(), compile = ctx->compile_ms;
  trace_batch batch;
  lt_status status = trace_batch_begin(ctx, &batch, rays, count, hits);
  *call->rays = &batch.rays, *call->hits = &batch.hits, *call->ray_count = count, *call->flags = flags;
  if (!status && ctx->kind == LT_DEVICE_NATIVE) {
    call->view(call->args, call->view_storage);
    status = trace_native(ctx, call->native, call->view_storage, &batch);
  } else if (!status) {
    status = trace_opencl(ctx, call->entry, call->set_args, call->args, call->ray_count, &batch);
  }
  status = trace_batch_end(ctx, &batch, hits, status);
  if (!status) {
    lt__stats_add(stats, LT_STAT_TRACE_MS, lt_now_ms() - start - (ctx->compile_ms - compile));
    lt__stats_add(stats, LT_STAT_TRAVERSAL_STEPS, (double)batch.traversal_steps);
    lt__stats_add(stats, LT_STAT_INTERSECTIONS, (double)batch.intersections);
  }
  return status;
}
