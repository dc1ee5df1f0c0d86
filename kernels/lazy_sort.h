/* The scheduler's own workload: a quicksort built on demand through the task pool. Its
 * "rays" are queries for the key at a sorted position, which walk the sort tree from the root
 * (traversal/sort_walk.h) and request the unbuilt nodes they reach; its tasks partition nodes
 * (builders/sort_task.h). Only what the queries need gets sorted in requested mode; everything
 * in a full build. The answers are checkable. */
#ifndef LT_KERNEL_LAZY_SORT_H
#define LT_KERNEL_LAZY_SORT_H

#include "builders/sort_task.h"
#include "device/kernel_args.h"
#include "traversal/sort_walk.h"

/* The task kinds this workload runs, numbered for its pool. */
enum { LT_SORT_KIND_PARTITION = 0 };

typedef struct lt_sort_args {
  lt_sort_build build;
  LT_GLOBAL const lt_i32 *queries; /* sorted positions asked for */
  LT_GLOBAL lt_u32 *answers;
  lt_i32 key_count, query_count, max_idle_polls;
} lt_sort_args;

/* The kernel's arguments, in order (device/kernel_args.h). */
#define LT_SORT_ARGS(X)                                \
  LT_SORT_BUILD_ARGS(X, build)                         \
  X(BUF, lt_i32, queries, queries)                     \
  X(BUF, lt_u32, answers, answers)                     \
  X(VAL, lt_i32, key_count, key_count)                 \
  X(VAL, lt_i32, query_count, query_count)             \
  X(VAL, lt_i32, max_idle_polls, max_idle_polls)

/* One query in flight. */
typedef struct lt_sort_query {
  lt_i32 pos, node; /* the sorted position asked for; where the walk stands */
  int suspended;    /* waiting at `node`, which it has requested */
  lt_u32 answer;
} lt_sort_query;

LT_DEVICE void lt_sort_query_start(const lt_sort_args *a, lt_sort_query *q, lt_i32 i) {
  q->pos = a->queries[i], q->node = 0, q->suspended = 0;
}

LT_DEVICE int lt_sort_query_advance(const lt_sort_args *a, lt_sort_query *q) {
  lt_sort_tree tree;
  tree.state = a->build.state, tree.nodes = a->build.nodes, tree.keys = a->build.keys;
  q->suspended = !lt_sort_walk(&tree, &a->build.pool, q->pos, &q->node, q->suspended, &q->answer);
  return !q->suspended;
}

#define LT_LOOP_NAME lt_sort_run
#define LT_LOOP_ARGS lt_sort_args
#define LT_LOOP_POOL(a) (&(a)->build.pool)
#define LT_LOOP_ITEM lt_sort_query
#define LT_LOOP_ITEMS_PER_WORK_ITEM 1
#define LT_LOOP_ITEM_COUNT(a) ((a)->query_count)
#define LT_LOOP_START(a, q, i, c) lt_sort_query_start(a, q, i)
#define LT_LOOP_ADVANCE(a, q, c) lt_sort_query_advance(a, q)
#define LT_LOOP_FINISH(a, i, q) ((a)->answers[i] = (q)->answer)
#define LT_LOOP_BUILD(a) 1
#define LT_LOOP_MAX_IDLE(a) ((a)->max_idle_polls)
#define LT_LOOP_FLUSH(a, c) ((void)(c))
#define LT_LOOP_TASK_KINDS(X) X(LT_SORT_KIND_PARTITION, lt_sort_chunk, lt_sort_end_phase, &a->build)
#include "kernels/persistent_loop_body.h"

/* Both backends' entry: the set-up launch (work-item 0 of work-group 0) makes the root; a normal launch
 * runs the persistent loop. */
LT_DEVICE void lt_sort_kernel(lt_sort_args *a, int setup, LT_LOCAL lt_loop_shared *sh) {
  a->build.task_kind = LT_SORT_KIND_PARTITION;
  if (!setup) {
    lt_sort_run(a, sh);
  } else if (lt_group_id() == 0 && lt_local_id() == 0) {
    lt_sort_setup(&a->build, a->key_count);
  }
}

#endif
