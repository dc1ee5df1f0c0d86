/* The host half of the task pool: its buffers, initial state, launches and counters. */
#ifndef LT_POOL_INTERNAL_H
#define LT_POOL_INTERNAL_H

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
/* Puts a task in `slot` from the host (the root), published as the mode says. */
lt_status lt__pool_insert_root(lt__pool *pool, int slot, int node, int begin, int end, int chunks);
/* Resets what one launch consumes: termination counter, own-work cursor, counters. */
lt_status lt__pool_begin_launch(lt__pool *pool);
/* Reads the control block and per-group counters after a launch, adds the counters to stats
 * and turns a kernel-side error into an lt_status that describes the pool's state. */
lt_status lt__pool_end_launch(lt__pool *pool, lt_stats *stats);
/* Level baseline: unlocks every waiting task from the host; returns how many via *count. */
lt_status lt__pool_unlock_waiting(lt__pool *pool, int *count);
/* PoCL compiles a kernel's work-group function at its first launch: warm-up runs `launch`
 * once with the control block saying "error" (every work-group quits at once) and a small
 * scratch buffer for its ray or query arguments, then restores the control block. The time
 * counts as compile time. */
typedef lt_status (*lt__pool_launch_fn)(void *user, lt__buffer *scratch);
lt_status lt__pool_warm_up(lt__pool *pool, lt__pool_launch_fn launch, void *user);
/* The device view for the native backend (host pointers). */
lt_pool lt__pool_native_view(lt__pool *pool);
/* Sets the pool's kernel arguments 0..8 (the layout of lt_lazy_sort in kernels/lazy_sort.cl). */
lt_status lt__pool_set_args(lt__pool *pool, cl_kernel kernel);
/* Counts the headers by state, for messages and tests. */
lt_status lt__pool_census(lt__pool *pool, int *empty, int *waiting, int *locked, int *unlocked);

#endif
