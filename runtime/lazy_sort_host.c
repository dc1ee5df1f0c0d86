/* The host half of the lazy sort, the task pool's own workload (kernels/lazy_sort.h). */
#include <stdlib.h>
#include <string.h>

#include "kernels/lazy_sort.h"
#include "kernels/native_kernels.h"
#include "runtime/error.h"
#include "runtime/pool_host.h"
#include "runtime/stats_internal.h"

struct lt_lazy_sort {
  lt_context *ctx;
  lt__pool pool;
  lt__buffer keys, scratch, state, nodes;
  int count;
  int node_capacity;
};

static lt_status launch_native(lt_lazy_sort *s, lt__buffer *queries, lt__buffer *answers, int count) {
  lt_sort args = {lt__pool_native_view(&s->pool), s->keys.host, s->scratch.host, s->state.host, s->nodes.host,
                  queries->host, answers->host, count, s->node_capacity, s->pool.config.max_idle_polls};
  return lt__native_run(s->ctx->work_groups, lt__native_lazy_sort_kernel, &args);
}

/* Arguments after the pool's nine, in the order of lt_lazy_sort in kernels/lazy_sort.cl. */
static lt_status launch_opencl(lt_lazy_sort *s, lt__buffer *queries, lt__buffer *answers, int count) {
  lt_context *ctx = s->ctx;
  cl_kernel k = ctx->sort_kernel;
  lt_status status = lt__pool_set_args(&s->pool, k);
  if (status) return status;
  cl_int err = clSetKernelArg(k, 9, sizeof(cl_mem), &s->keys.mem);
  err |= clSetKernelArg(k, 10, sizeof(cl_mem), &s->scratch.mem);
  err |= clSetKernelArg(k, 11, sizeof(cl_mem), &s->state.mem);
  err |= clSetKernelArg(k, 12, sizeof(cl_mem), &s->nodes.mem);
  err |= clSetKernelArg(k, 13, sizeof(cl_mem), &queries->mem);
  err |= clSetKernelArg(k, 14, sizeof(cl_mem), &answers->mem);
  err |= clSetKernelArg(k, 15, sizeof(int), &count);
  err |= clSetKernelArg(k, 16, sizeof(int), &s->node_capacity);
  err |= clSetKernelArg(k, 17, sizeof(int), &s->pool.config.max_idle_polls);
  if ((status = lt__opencl_check(err, "setting lazy sort kernel arguments"))) return status;

  /* Exactly as many work-groups as run at once: persistent groups wait on each other. */
  size_t local = (size_t)ctx->local_size, global = local * (size_t)ctx->work_groups;
  err = clEnqueueNDRangeKernel(ctx->queue, k, 1, NULL, &global, &local, 0, NULL, NULL);
  if (err == CL_SUCCESS) err = clFinish(ctx->queue);
  return lt__opencl_check(err, "running the lazy sort kernel");
}

static lt_status launch(lt_lazy_sort *s, lt__buffer *queries, lt__buffer *answers, int count) {
  return s->ctx->kind == LT_DEVICE_NATIVE ? launch_native(s, queries, answers, count)
                                          : launch_opencl(s, queries, answers, count);
}

/* The warm-up launch (lt__pool_warm_up): no queries. */
static lt_status warm_up_launch(void *user, lt__buffer *scratch) { return launch(user, scratch, scratch, 0); }

lt_status lt_lazy_sort_create(lt_context *ctx, const uint32_t *keys, size_t count, lt_build_mode mode,
                              const lt_pool_config *config, lt_lazy_sort **out) {
  if (!ctx || !out || (count && !keys)) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt_lazy_sort_create: NULL argument");
  if (count > (size_t)LT_POOL_MAX_NODE / 4) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "%zu keys are too many", count);
  if (ctx->local_size > LT_MAX_LOCAL_SIZE)
    return lt__fail(LT_ERROR_INVALID_ARGUMENT, "local size %d exceeds %d", ctx->local_size, LT_MAX_LOCAL_SIZE);
  lt_lazy_sort *s = calloc(1, sizeof *s);
  if (!s) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory for a lazy sort");
  s->ctx = ctx;
  s->count = (int)count;
  s->node_capacity = 2 * (int)count + 2; /* every split makes two nodes, at most count - 1 splits */

  /* The kernels, the pool, and the arrays of the sort tree. */
  lt_status status = ctx->kind == LT_DEVICE_OPENCL ? lt__opencl_program(ctx) : LT_OK;
  if (!status) status = lt__pool_create(ctx, config, (int)mode, &s->pool);
  if (!status) status = lt__buffer_create(ctx, &s->keys, count * 4, keys, 0);
  if (!status) status = lt__buffer_create(ctx, &s->scratch, count * 4, NULL, 0);
  if (!status) status = lt__buffer_create(ctx, &s->state, (size_t)s->node_capacity * 4, NULL, LT_SORT_LEAF_STATE);
  if (!status) status = lt__buffer_create(ctx, &s->nodes, (size_t)s->node_capacity * 16, NULL, 0);

  /* The root: node 0, a task in slot 0 unless there is nothing to sort. */
  lt_pool_control control = {0};
  control.nodes_next = 1;
  if (!status) status = lt__buffer_write(ctx, &s->pool.control, 0, sizeof control, &control);
  if (!status && count > 0) {
    int unbuilt = LT_SORT_UNBUILT(0);
    status = lt__pool_insert_root(&s->pool, 0, 0, 0, (int)count, 1);
    if (!status) status = lt__buffer_write(ctx, &s->state, 0, 4, &unbuilt);
  }
  if (!status && ctx->kind == LT_DEVICE_OPENCL) status = lt__pool_warm_up(&s->pool, warm_up_launch, s);
  if (status) {
    lt_lazy_sort_destroy(s);
    return status;
  }
  *out = s;
  return LT_OK;
}

void lt_lazy_sort_destroy(lt_lazy_sort *s) {
  if (!s) return;
  lt__pool_release(&s->pool);
  lt__buffer_release(&s->keys);
  lt__buffer_release(&s->scratch);
  lt__buffer_release(&s->state);
  lt__buffer_release(&s->nodes);
  free(s);
}

lt_status lt_lazy_sort_query(lt_lazy_sort *s, const int32_t *positions, size_t count, uint32_t *answers,
                             lt_stats *stats) {
  if (!s || (count && (!positions || !answers)))
    return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt_lazy_sort_query: NULL argument");
  for (size_t i = 0; i < count; i++)
    if (positions[i] < 0 || positions[i] >= s->count)
      return lt__fail(LT_ERROR_INVALID_ARGUMENT, "query %zu asks for position %d of %d keys", i, positions[i], s->count);
  if (count > (size_t)INT32_MAX / 2) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "%zu queries are too many", count);

  lt__buffer query_buf, answer_buf;
  lt_status status = lt__buffer_create(s->ctx, &query_buf, count * 4, positions, 0);
  if (status) return status;
  status = lt__buffer_create(s->ctx, &answer_buf, count * 4, NULL, 0);
  if (!status) status = lt__pool_begin_launch(&s->pool);
  double start = lt_now_ms();
  if (!status) status = launch(s, &query_buf, &answer_buf, (int)count);
  double ms = lt_now_ms() - start;
  lt_status pool_status = status ? status : lt__pool_end_launch(&s->pool, stats);
  if (!pool_status && count) pool_status = lt__buffer_read(s->ctx, &answer_buf, 0, count * 4, answers);
  lt__buffer_release(&query_buf);
  lt__buffer_release(&answer_buf);
  if (stats && !pool_status) {
    lt__stats_add(stats, LT_STAT_RAYS, (double)count);
    lt__stats_add(stats, LT_STAT_TOTAL_MS, ms);
    lt__stats_put(stats, LT_STAT_COMPILE_MS, s->ctx->compile_ms);
    size_t built, left;
    if (lt_lazy_sort_progress(s, &built, &left) == LT_OK) lt__stats_put(stats, LT_STAT_NODES_BUILT, (double)built);
  }
  return pool_status;
}

lt_status lt_lazy_sort_by_levels(lt_lazy_sort *s, lt_stats *stats, int *levels) {
  if (!s || !levels) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt_lazy_sort_by_levels: NULL argument");
  if (s->pool.mode != LT_POOL_FULL) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "the level baseline needs a full-mode sort");

  /* Children wait now; each launch runs one level, then the host unlocks the next. */
  s->pool.mode = LT_POOL_LEVELS;
  lt__buffer none;
  lt_status status = lt__buffer_create(s->ctx, &none, 16, NULL, 0);
  double start = lt_now_ms();
  *levels = 0;
  for (int unlocked = 1; !status && unlocked > 0;) {
    status = lt__pool_begin_launch(&s->pool);
    if (!status) status = launch(s, &none, &none, 0);
    if (!status) status = lt__pool_end_launch(&s->pool, stats);
    if (!status) status = lt__pool_unlock_waiting(&s->pool, &unlocked);
    ++*levels;
  }
  if (stats && !status) lt__stats_add(stats, LT_STAT_TOTAL_MS, lt_now_ms() - start);
  lt__buffer_release(&none);
  s->pool.mode = LT_POOL_FULL;
  return status;
}

lt_status lt_lazy_sort_keys(lt_lazy_sort *s, uint32_t *out) {
  if (!s || (s->count && !out)) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt_lazy_sort_keys: NULL argument");
  return lt__buffer_read(s->ctx, &s->keys, 0, (size_t)s->count * 4, out);
}

lt_status lt_lazy_sort_order(lt_lazy_sort *s, int32_t *out, size_t capacity, size_t *count) {
  if (!s || !count) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt_lazy_sort_order: NULL argument");
  lt_pool_control control;
  lt_status status = lt__buffer_read(s->ctx, &s->pool.control, 0, sizeof control, &control);
  if (status) return status;
  size_t n = (size_t)control.order_next;
  if (n > (size_t)s->pool.config.order_log_size) n = (size_t)s->pool.config.order_log_size;
  if (n > capacity) n = capacity;
  *count = n;
  return n ? lt__buffer_read(s->ctx, &s->pool.order, 0, n * 4, out) : LT_OK;
}

lt_status lt_lazy_sort_progress(lt_lazy_sort *s, size_t *nodes_built, size_t *tasks_left) {
  lt_pool_control control;
  lt_status status = lt__buffer_read(s->ctx, &s->pool.control, 0, sizeof control, &control);
  int n = control.nodes_next < s->node_capacity ? control.nodes_next : s->node_capacity;
  int *state = malloc((size_t)(n > 0 ? n : 1) * sizeof *state);
  if (!status && !state) status = lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory");
  if (!status) status = lt__buffer_read(s->ctx, &s->state, 0, (size_t)n * 4, state);
  size_t built = 0;
  for (int i = 0; !status && i < n; i++) built += state[i] >= LT_SORT_LEAF_STATE;
  free(state);
  if (!status) *nodes_built = built, *tasks_left = (size_t)control.outstanding;
  return status;
}
