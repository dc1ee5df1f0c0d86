/* The host half of the lazy sort, the task pool's own workload (kernels/lazy_sort.h). */
#include <stdlib.h>
#include <string.h>

#include "kernels/lazy_sort.h"
#include "kernels/native_kernels.h"
#include "runtime/error.h"
#include "runtime/heap_host.h"
#include "runtime/kernel_args_host.h"
#include "runtime/persistent_launch.h"
#include "runtime/pool_host.h"
#include "runtime/stats_internal.h"

struct lt_lazy_sort {
  lt_context *ctx;
  lt__pool pool;
  lt__heap node_heap;
  lt__buffer keys, scratch, state, nodes;
  int count;
};

/* The kernel's arguments from its one list (kernels/lazy_sort.h). */
LT__KERNEL_ARGS(sort_args, LT_SORT_ARGS, lt_sort_args)

/* One launch on either backend: the set-up launch (work-group 0 makes the root) or the persistent loop
 * over `count` queries (exactly as many work-groups as run at once: they wait on each other). */
static lt_status launch(lt_lazy_sort *s, lt__buffer *queries, lt__buffer *answers, int count, int setup) {
  lt_context *ctx = s->ctx;
  sort_args args;
  LT__POOL_HOST_ARGS(&args, &s->pool);
  LT__HEAP_HOST_ARGS(&args, node_heap, &s->node_heap);
  args.keys = &s->keys, args.scratch = &s->scratch, args.state = &s->state, args.nodes = &s->nodes;
  args.task_kind = 0; /* the kernel numbers its own task kinds */
  args.queries = queries, args.answers = answers;
  args.key_count = s->count, args.query_count = count, args.max_idle_polls = s->pool.config.max_idle_polls;
  static const lt__persistent_kernel kernel = {"lt_lazy_sort", lt__native_lazy_sort_kernel, sort_args_set_any,
                                               sort_args_view_any};
  lt_sort_args view;
  return lt__persistent_launch(ctx, &kernel, &args, &view, setup, &s->pool.control,
                                       s->pool.config.max_stall_seconds);
}

lt_status lt_lazy_sort_create(lt_context *ctx, const uint32_t *keys, size_t count, lt_build_mode mode,
                              const lt_pool_config *config, lt_lazy_sort **out) {
  if (!ctx || !out || (count && !keys)) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt_lazy_sort_create: NULL argument");
  if (count > (size_t)LT_POOL_MAX_NODE / 4) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "%zu keys are too many", count);
  lt_lazy_sort *s = calloc(1, sizeof *s);
  if (!s) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory for a lazy sort");
  s->ctx = ctx;
  s->count = (int)count;
  int node_capacity = 2 * (int)count + 2; /* every split makes two nodes, at most count - 1 splits */

  /* The kernels, the pool, and the arrays of the sort tree. */
  if ((unsigned)mode > LT_BUILD_SPECULATIVE) {
    free(s);
    return lt__fail(LT_ERROR_INVALID_ARGUMENT, "unknown build mode %d", (int)mode);
  }
  if (mode == LT_BUILD_DEFAULT) mode = LT_BUILD_SPECULATIVE;
  int pool_mode = (int)mode - LT_BUILD_FULL; /* LT_POOL_FULL, _REQUESTED, _SPECULATIVE */
  lt_status status = lt__pool_create(ctx, config, pool_mode, &s->pool);
  if (!status) status = lt__heap_create(ctx, &s->node_heap, node_capacity);
  if (!status) status = lt__buffer_create(ctx, &s->keys, count * 4, keys, 0);
  if (!status) status = lt__buffer_create(ctx, &s->scratch, count * 4, NULL, 0);
  if (!status) status = lt__buffer_create(ctx, &s->state, (size_t)node_capacity * 4, NULL, LT_SORT_LEAF_STATE);
  if (!status) status = lt__buffer_create(ctx, &s->nodes, (size_t)node_capacity * 16, NULL, 0);

  /* The root: node 0, a task in the pool unless there is nothing to sort, made on the device. */
  lt__buffer none;
  if (!status) status = lt__buffer_create(ctx, &none, 16, NULL, 0);
  if (!status) {
    status = launch(s, &none, &none, 0, 1);
    lt__buffer_release(&none);
  }
  if (!status) status = lt__pool_end_launch(&s->pool, NULL); /* a full pool, said as such */
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
  lt__heap_release(&s->node_heap);
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
  if (!status) status = launch(s, &query_buf, &answer_buf, (int)count, 0);
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
    if (!status) status = launch(s, &none, &none, 0, 0);
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
  int n = 0, exhausted;
  lt_status status = lt__buffer_read(s->ctx, &s->pool.control, 0, sizeof control, &control);
  if (!status) status = lt__heap_used(s->ctx, &s->node_heap, &n, &exhausted);
  int *state = malloc((size_t)(n > 0 ? n : 1) * sizeof *state);
  if (!status && !state) status = lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory");
  if (!status) status = lt__buffer_read(s->ctx, &s->state, 0, (size_t)n * 4, state);
  size_t built = 0;
  for (int i = 0; !status && i < n; i++) built += state[i] >= LT_SORT_LEAF_STATE;
  free(state);
  if (!status) *nodes_built = built, *tasks_left = (size_t)control.outstanding;
  return status;
}
