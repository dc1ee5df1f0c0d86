/* The host half of the task pool (see pool_internal.h and device/pool.h). */
#include "runtime/pool_host.h"

#include <stdlib.h>
#include <string.h>

#include "runtime/error.h"
#include "runtime/stats_internal.h"

lt_pool_config lt__pool_config_defaults(const lt_pool_config *config) {
  lt_pool_config c = {65536, 1024, 1024, 200000000, 0};
  if (config) {
    if (config->capacity > 0) c.capacity = config->capacity;
    if (config->empty_cache_size > 0) c.empty_cache_size = config->empty_cache_size;
    if (config->priority_cache_size > 0) c.priority_cache_size = config->priority_cache_size;
    if (config->max_idle_polls > 0) c.max_idle_polls = config->max_idle_polls;
    if (config->order_log_size > 0) c.order_log_size = config->order_log_size;
  }
  return c;
}

lt_status lt__pool_create(lt_context *ctx, const lt_pool_config *config, int mode, lt__pool *pool) {
  memset(pool, 0, sizeof *pool);
  pool->ctx = ctx;
  pool->config = lt__pool_config_defaults(config);
  pool->mode = mode;
  const lt_pool_config *c = &pool->config;
  if (c->capacity > LT_POOL_MAX_NODE)
    return lt__fail(LT_ERROR_INVALID_ARGUMENT, "pool capacity %d exceeds %d", c->capacity, LT_POOL_MAX_NODE);

  /* Headers start EMPTY; the caches hold no slot (-1); counters start at 0. */
  lt_status status = lt__buffer_create(ctx, &pool->headers, (size_t)c->capacity * 4, NULL, LT_POOL_EMPTY);
  if (!status) status = lt__buffer_create(ctx, &pool->tasks, (size_t)c->capacity * sizeof(lt_task), NULL, 0);
  if (!status) status = lt__buffer_create(ctx, &pool->empty_cache, (size_t)c->empty_cache_size * 4, NULL, -1);
  if (!status) status = lt__buffer_create(ctx, &pool->priority_cache, (size_t)c->priority_cache_size * 4, NULL, -1);
  if (!status) status = lt__buffer_create(ctx, &pool->control, sizeof(lt_pool_control), NULL, 0);
  if (!status)
    status = lt__buffer_create(ctx, &pool->stats, (size_t)ctx->work_groups * LT_POOL_STAT_COUNT * 4, NULL, 0);
  if (!status) status = lt__buffer_create(ctx, &pool->order, (size_t)c->order_log_size * 4, NULL, -1);
  if (status) lt__pool_release(pool);
  return status;
}

void lt__pool_release(lt__pool *pool) {
  lt__buffer_release(&pool->headers);
  lt__buffer_release(&pool->tasks);
  lt__buffer_release(&pool->empty_cache);
  lt__buffer_release(&pool->priority_cache);
  lt__buffer_release(&pool->control);
  lt__buffer_release(&pool->stats);
  lt__buffer_release(&pool->order);
}

lt_status lt__pool_insert_root(lt__pool *pool, int slot, int node, int begin, int end, int chunks) {
  lt_task task = {begin, end, node, 0, chunks, 0, 0, 0, {0}};
  lt_pool_control control;
  lt_status status = lt__buffer_read(pool->ctx, &pool->control, 0, sizeof control, &control);
  if (status) return status;
  control.outstanding++;
  if (control.high_water < slot + 1) control.high_water = slot + 1;
  int header = pool->mode == LT_POOL_REQUESTED ? LT_POOL_WAITING(node) : chunks;
  status = lt__buffer_write(pool->ctx, &pool->tasks, (size_t)slot * sizeof task, sizeof task, &task);
  if (!status) status = lt__buffer_write(pool->ctx, &pool->control, 0, sizeof control, &control);
  if (!status) status = lt__buffer_write(pool->ctx, &pool->headers, (size_t)slot * 4, 4, &header);
  return status;
}

lt_status lt__pool_begin_launch(lt__pool *pool) {
  lt_pool_control control;
  lt_status status = lt__buffer_read(pool->ctx, &pool->control, 0, sizeof control, &control);
  if (status) return status;
  if (control.error != LT_POOL_OK)
    return lt__fail(LT_ERROR_INVALID_ARGUMENT, "this pool stopped on an error earlier; create a new one");
  control.termination = pool->ctx->work_groups;
  control.groups = pool->ctx->work_groups;
  control.idle_groups = 0;
  control.work_next = 0;
  control.progress = 0;
  status = lt__buffer_write(pool->ctx, &pool->control, 0, sizeof control, &control);
  return status ? status : lt__buffer_fill(pool->ctx, &pool->stats, 0);
}

lt_status lt__pool_census(lt__pool *pool, int *empty, int *waiting, int *locked, int *unlocked) {
  int n = pool->config.capacity;
  int *headers = malloc((size_t)n * sizeof *headers);
  if (!headers) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory reading the pool");
  lt_status status = lt__buffer_read(pool->ctx, &pool->headers, 0, (size_t)n * 4, headers);
  *empty = *waiting = *locked = *unlocked = 0;
  for (int i = 0; !status && i < n; i++) {
    int h = headers[i];
    if (h == LT_POOL_EMPTY) ++*empty;
    else if (LT_POOL_IS_WAITING(h)) ++*waiting;
    else if (h == 0) ++*locked;
    else ++*unlocked;
  }
  free(headers);
  return status;
}

lt_status lt__pool_end_launch(lt__pool *pool, lt_stats *stats) {
  lt_pool_control control;
  int groups = pool->ctx->work_groups;
  lt_u32 *counters = calloc((size_t)groups * LT_POOL_STAT_COUNT, sizeof *counters);
  if (!counters) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory reading pool counters");
  lt_status status = lt__buffer_read(pool->ctx, &pool->control, 0, sizeof control, &control);
  if (!status) status = lt__buffer_read(pool->ctx, &pool->stats, 0, (size_t)groups * LT_POOL_STAT_COUNT * 4, counters);

  /* Per-group counters, summed into the statistics. */
  double sum[LT_POOL_STAT_COUNT] = {0};
  for (int g = 0; !status && g < groups; g++)
    for (int k = 0; k < LT_POOL_STAT_COUNT; k++) sum[k] += counters[g * LT_POOL_STAT_COUNT + k];
  free(counters);
  if (status) return status;
  static const lt_stat_id ids[LT_POOL_STAT_COUNT] = {
      LT_STAT_POOL_TASKS,        LT_STAT_POOL_REQUESTED, LT_STAT_POOL_SPECULATIVE, LT_STAT_POOL_STALLS,
      LT_STAT_POOL_CACHE_HITS,   LT_STAT_POOL_CACHE_MISSES, LT_STAT_POOL_SCANS,    LT_STAT_POOL_EMPTY_HITS,
      LT_STAT_POOL_CHUNKS,       LT_STAT_POOL_IDLE};
  for (int k = 0; k < LT_POOL_STAT_COUNT; k++) lt__stats_add(stats, ids[k], sum[k]);
  lt__stats_put(stats, LT_STAT_POOL_BYTES,
                (double)(pool->headers.bytes + pool->tasks.bytes + pool->empty_cache.bytes +
                         pool->priority_cache.bytes + pool->control.bytes));
  if (control.error == LT_POOL_OK) return LT_OK;

  /* An error: say which, with the pool's state. */
  int empty, waiting, locked, unlocked;
  lt__pool_census(pool, &empty, &waiting, &locked, &unlocked);
  const char *what = control.error == LT_POOL_ERROR_FULL    ? "the task pool is full"
                     : control.error == LT_POOL_ERROR_NODES ? "the node array is full"
                     : control.error == LT_POOL_ERROR_STACK ? "a traversal went deeper than its stack"
                                                            : "a work-group polled past its cap with no progress";
  return lt__fail(control.error == LT_POOL_ERROR_STALL ? LT_ERROR_SCHEDULER : LT_ERROR_CAPACITY,
                  "%s (capacity %d: %d empty, %d waiting, %d locked, %d unlocked; %d tasks outstanding, "
                  "%d of %d work-groups with own work left)",
                  what, pool->config.capacity, empty, waiting, locked, unlocked, control.outstanding,
                  control.termination, groups);
}

lt_status lt__pool_unlock_waiting(lt__pool *pool, int *count) {
  /* Only slots below the high-water mark were ever used. */
  lt_pool_control control;
  lt_status status = lt__buffer_read(pool->ctx, &pool->control, 0, sizeof control, &control);
  int n = control.high_water;
  *count = 0;
  if (status || n <= 0) return status;
  int *headers = malloc((size_t)n * sizeof *headers);
  lt_task *tasks = malloc((size_t)n * sizeof *tasks);
  if (!headers || !tasks) status = lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory reading the pool");
  if (!status) status = lt__buffer_read(pool->ctx, &pool->headers, 0, (size_t)n * 4, headers);
  if (!status) status = lt__buffer_read(pool->ctx, &pool->tasks, 0, (size_t)n * sizeof *tasks, tasks);

  /* Every waiting task becomes unlocked with its first phase's chunks. */
  for (int i = 0; !status && i < n; i++)
    if (LT_POOL_IS_WAITING(headers[i])) headers[i] = tasks[i].chunks, ++*count;
  control.waiting = 0;
  if (!status) status = lt__buffer_write(pool->ctx, &pool->headers, 0, (size_t)n * 4, headers);
  if (!status) status = lt__buffer_write(pool->ctx, &pool->control, 0, sizeof control, &control);
  free(headers), free(tasks);
  return status;
}

lt_status lt__pool_warm_up(lt__pool *pool, lt__pool_launch_fn launch, void *user) {
  lt_pool_control saved, stop;
  lt__buffer scratch;
  lt_status status = lt__buffer_read(pool->ctx, &pool->control, 0, sizeof saved, &saved);
  if (status) return status;
  stop = saved;
  stop.error = LT_POOL_ERROR_STALL;
  double start = lt_now_ms();
  status = lt__buffer_create(pool->ctx, &scratch, 16, NULL, 0);
  if (status) return status;
  status = lt__buffer_write(pool->ctx, &pool->control, 0, sizeof stop, &stop);
  if (!status) status = launch(user, &scratch);
  lt__buffer_release(&scratch);
  if (!status) status = lt__buffer_write(pool->ctx, &pool->control, 0, sizeof saved, &saved);
  pool->ctx->compile_ms += lt_now_ms() - start;
  return status;
}

lt_pool lt__pool_native_view(lt__pool *pool) {
  lt_pool view = {pool->headers.host, pool->tasks.host, pool->empty_cache.host, pool->priority_cache.host,
                  pool->control.host, pool->stats.host, pool->order.host, pool->config.capacity,
                  pool->config.empty_cache_size, pool->config.priority_cache_size, pool->config.order_log_size,
                  pool->mode};
  return view;
}

lt_status lt__pool_set_args(lt__pool *pool, cl_kernel kernel) {
  cl_int4 sizes = {{pool->config.capacity, pool->config.empty_cache_size, pool->config.priority_cache_size,
                    pool->config.order_log_size}};
  cl_int err = clSetKernelArg(kernel, 0, sizeof(cl_mem), &pool->headers.mem);
  err |= clSetKernelArg(kernel, 1, sizeof(cl_mem), &pool->tasks.mem);
  err |= clSetKernelArg(kernel, 2, sizeof(cl_mem), &pool->empty_cache.mem);
  err |= clSetKernelArg(kernel, 3, sizeof(cl_mem), &pool->priority_cache.mem);
  err |= clSetKernelArg(kernel, 4, sizeof(cl_mem), &pool->control.mem);
  err |= clSetKernelArg(kernel, 5, sizeof(cl_mem), &pool->stats.mem);
  err |= clSetKernelArg(kernel, 6, sizeof(cl_mem), &pool->order.mem);
  err |= clSetKernelArg(kernel, 7, sizeof sizes, &sizes);
  err |= clSetKernelArg(kernel, 8, sizeof(int), &pool->mode);
  return lt__opencl_check(err, "setting task pool kernel arguments");
}
