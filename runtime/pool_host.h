/* The host half of the task pool: its buffers, initial state, launches and counters. */
#ifndef LT_POOL_HOST_H
#define LT_POOL_HOST_H

#include "device/pool.h"
#include "runtime/buffer.h"

typedef struct lt__pool {
  lt_context *ctx;
  lt_pool_config config;
  int mode;
  lt__buffer headers, tasks, empty_cache, priority_cache, control, stats, order;
} lt__pool;

lt_pool_config lt__pool_config_defaults(const lt_pool_config *config);
/* Allocates an empty pool: every header EMPTY, caches without entries, counters zero. */
lt_status lt__pool_create(lt_context *ctx, const lt_pool_config *config, int mode, lt__pool *pool);
void lt__pool_release(lt__pool *pool);
/* Resets what one launch consumes: termination counter, own-work cursor, counters. */
lt_status lt__pool_begin_launch(lt__pool *pool);
/* Reads the control block and per-group counters after a launch, adds the counters to stats
 * and turns a kernel-side error into an lt_status that describes the pool's state. */
lt_status lt__pool_end_launch(lt__pool *pool, lt_stats *stats);
/* Level baseline: unlocks every waiting task from the host; returns how many via *count. */
lt_status lt__pool_unlock_waiting(lt__pool *pool, int *count);
/* Fills the pool's entries of a kernel's host arguments (LT_POOL_ARGS, runtime/kernel_args_host.h). */
#define LT__POOL_HOST_ARGS(args, p)                                                                   \
  ((args)->pool_headers = &(p)->headers, (args)->pool_tasks = &(p)->tasks,                            \
   (args)->pool_empty_cache = &(p)->empty_cache, (args)->pool_priority_cache = &(p)->priority_cache, \
   (args)->pool_control = &(p)->control, (args)->pool_stats = &(p)->stats, (args)->pool_order = &(p)->order, \
   (args)->pool_capacity = (p)->config.capacity, (args)->pool_empty_size = (p)->config.empty_cache_size, \
   (args)->pool_priority_size = (p)->config.priority_cache_size,                                      \
   (args)->pool_order_size = (p)->config.order_log_size, (args)->pool_mode = (p)->mode)
/* Counts the headers by state, for messages and tests. */
lt_status lt__pool_census(lt__pool *pool, int *empty, int *waiting, int *locked, int *unlocked);

#endif
