/* The host half of the task pool (see pool_host.h and device/pool.h). */
#include "runtime/pool_host.h"

#include <stdlib.h>
#include <string.h>

#include "runtime/error.h"
#include "runtime/stats_internal.h"

lt_pool_config lt__pool_config_defaults(const lt_pool_config *config) {
  lt_pool_config c = {65536, 1024, 1024, 200000000, 0, 60};
  if (config) {
    if (config->capacity > 0) c.capacity = config->capacity;
    if (config->empty_cache_size > 0) c.empty_cache_size = config->empty_cache_size;
    if (config->priority_cache_size > 0) c.priority_cache_size = config->priority_cache_size;
    if (config->max_idle_polls > 0) c.max_idle_polls = config->max_idle_polls;
    if (config->order_log_size > 0) c.order_log_size = config->order_log_size;
    if (config->max_stall_seconds > 0) c.max_stall_seconds = config->max_stall_seconds;
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
                     : control.error == LT_POOL_ERROR_HEAP  ? "a device heap (nodes, references) is full"
                     : control.error == LT_POOL_ERROR_KIND  ? "a task of a kind the workload does not run"
                     : control.error == LT_POOL_ERROR_STACK ? "a traversal went deeper than its stack"
                                                            : "nothing moved (a work-group polled past its cap, or the launch stood still for its stall time)";
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
