/* The lazy sort's task kind: a quicksort node partitioned through the task pool, the
 * scheduler's own workload (kernels/lazy_sort.h). It mirrors node subdivision without
 * geometry: a task partitions the elements of one node around a pivot (phases: pick the
 * pivot, count, scatter, copy back) and spawns two children; ranges of LT_SORT_LEAF or fewer
 * are sorted at once by their parent. */
#ifndef LT_SORT_TASK_H
#define LT_SORT_TASK_H

#include "device/heap.h"
#include "device/sort_node.h"
#include "device/pool.h"

#define LT_SORT_CHUNK 256 /* elements per work chunk */
#define LT_SORT_LEAF 32   /* ranges this small are sorted at once by their parent */
#define LT_SORT_MAX_DEPTH 4096

/* Phases of a partition task. */
#define LT_SORT_PIVOT 0
#define LT_SORT_COUNT 1
#define LT_SORT_SCATTER 2
#define LT_SORT_COPY 3

/* Task scratch (lt_task.work). */
#define W_PIVOT 0
#define W_LESS 1 /* counts from the count phase */
#define W_EQUAL 2
#define W_GREATER 3
#define W_AT_LESS 4 /* scatter cursors */
#define W_AT_EQUAL 5
#define W_AT_GREATER 6

/* The sort tree and what its tasks work on. */
typedef struct lt_sort_build {
  lt_pool pool;
  LT_GLOBAL lt_u32 *keys;
  LT_GLOBAL lt_u32 *scratch;
  LT_GLOBAL lt_i32 *state;  /* per node: leaf, unbuilt or built */
  LT_GLOBAL lt_int4 *nodes; /* per built node: less_end, greater_begin, pivot, first child */
  lt_heap node_heap;        /* hands out nodes, two at a time */
  lt_i32 task_kind;         /* the number the running workload gave these tasks */
} lt_sort_build;

/* The build's kernel arguments (device/kernel_args.h); V is its path in the view. */
#define LT_SORT_BUILD_ARGS(X, V)             \
  LT_POOL_ARGS(X, V.pool)                    \
  X(BUF, lt_u32, V.keys, keys)               \
  X(BUF, lt_u32, V.scratch, scratch)         \
  X(BUF, lt_i32, V.state, state)             \
  X(BUF, lt_int4, V.nodes, nodes)            \
  LT_HEAP_ARGS(X, V.node_heap, node_heap)    \
  X(VAL, lt_i32, V.task_kind, task_kind)

LT_DEVICE lt_i32 lt_sort_chunks(lt_i32 n) { return (n + LT_SORT_CHUNK - 1) / LT_SORT_CHUNK; }

/* One chunk of the current phase, shared by the work-items of the group. */
LT_DEVICE void lt_sort_chunk(const lt_sort_build *s, lt_i32 slot, lt_i32 chunk, int lid, int lsize) {
  LT_GLOBAL lt_task *task = &s->pool.tasks[slot];
  lt_i32 begin = task->begin, end = task->end;
  lt_i32 lo = begin + chunk * LT_SORT_CHUNK, hi = lo + LT_SORT_CHUNK < end ? lo + LT_SORT_CHUNK : end;
  LT_GLOBAL lt_i32 *w = task->work;

  /* Pivot: the median of the first, middle and last keys. */
  if (task->phase == LT_SORT_PIVOT) {
    if (lid != 0) return;
    lt_u32 a = s->keys[begin], b = s->keys[begin + (end - begin) / 2], c = s->keys[end - 1];
    lt_u32 pivot = a < b ? (b < c ? b : (a < c ? c : a)) : (a < c ? a : (b < c ? c : b));
    lt_atomic_store_i32(&w[W_PIVOT], (lt_i32)pivot);
    return;
  }
  lt_u32 pivot = (lt_u32)lt_atomic_load_i32(&w[W_PIVOT]);

  /* Copy back: the partitioned range returns from scratch to keys. */
  if (task->phase == LT_SORT_COPY) {
    for (lt_i32 i = lo + lid; i < hi; i += lsize) s->keys[i] = s->scratch[i];
    return;
  }

  /* Count this work-item's share of the chunk. */
  lt_i32 less = 0, equal = 0, greater = 0;
  for (lt_i32 i = lo + lid; i < hi; i += lsize) {
    lt_u32 k = s->keys[i];
    less += k < pivot, equal += k == pivot, greater += k > pivot;
  }
  if (task->phase == LT_SORT_COUNT) {
    if (less) lt_atomic_add_i32(&w[W_LESS], less);
    if (equal) lt_atomic_add_i32(&w[W_EQUAL], equal);
    if (greater) lt_atomic_add_i32(&w[W_GREATER], greater);
    return;
  }

  /* Scatter: reserve room in each of the three regions, then write. */
  lt_i32 total_less = lt_atomic_load_i32(&w[W_LESS]), total_equal = lt_atomic_load_i32(&w[W_EQUAL]);
  lt_i32 at_less = begin + (less ? lt_atomic_add_i32(&w[W_AT_LESS], less) : 0);
  lt_i32 at_equal = begin + total_less + (equal ? lt_atomic_add_i32(&w[W_AT_EQUAL], equal) : 0);
  lt_i32 at_greater = begin + total_less + total_equal + (greater ? lt_atomic_add_i32(&w[W_AT_GREATER], greater) : 0);
  for (lt_i32 i = lo + lid; i < hi; i += lsize) {
    lt_u32 k = s->keys[i];
    if (k < pivot) s->scratch[at_less++] = k;
    else if (k == pivot) s->scratch[at_equal++] = k;
    else s->scratch[at_greater++] = k;
  }
}

LT_DEVICE void lt_sort_small(const lt_sort_build *s, lt_i32 begin, lt_i32 end) {
  for (lt_i32 i = begin + 1; i < end; i++) {
    lt_u32 k = s->keys[i];
    lt_i32 j = i - 1;
    for (; j >= begin && s->keys[j] > k; j--) s->keys[j + 1] = s->keys[j];
    s->keys[j + 1] = k;
  }
}

/* Links one child of a finished node: small ranges are sorted now, others become tasks. */
LT_DEVICE void lt_sort_spawn(const lt_sort_build *s, lt_i32 child, lt_i32 begin, lt_i32 end, lt_i32 depth) {
  if (end - begin <= LT_SORT_LEAF) {
    lt_sort_small(s, begin, end);
    lt_fence();
    lt_atomic_store_i32(&s->state[child], LT_SORT_LEAF_STATE);
    return;
  }
  lt_i32 slot = lt_pool_insert(&s->pool, s->task_kind, child, begin, end, depth, 1);
  if (slot < 0) return;
  lt_atomic_store_i32(&s->state[child], LT_SORT_UNBUILT(slot));
  lt_pool_publish(&s->pool, slot);
}

/* Called by the work-group that finished the last chunk of a phase (work-item 0 only). */
LT_DEVICE void lt_sort_end_phase(const lt_sort_build *s, lt_i32 slot) {
  LT_GLOBAL lt_task *task = &s->pool.tasks[slot];
  lt_i32 chunks = lt_sort_chunks(task->end - task->begin);
  if (task->phase != LT_SORT_COPY) {
    lt_pool_next_phase(&s->pool, slot, task->phase + 1, chunks);
    return;
  }

  /* The node is partitioned: record it, link its children, then publish it. */
  LT_GLOBAL lt_i32 *w = task->work;
  lt_i32 less_end = task->begin + lt_atomic_load_i32(&w[W_LESS]);
  lt_i32 greater_begin = less_end + lt_atomic_load_i32(&w[W_EQUAL]);
  lt_i32 first = lt_heap_alloc(&s->node_heap, 2);
  if (first < 0) {
    lt_pool_fail(&s->pool, LT_POOL_ERROR_HEAP);
    return;
  }
  s->nodes[task->node] = lt_make_int4(less_end, greater_begin, lt_atomic_load_i32(&w[W_PIVOT]), first);
  lt_sort_spawn(s, first, task->begin, less_end, task->depth + 1);
  lt_sort_spawn(s, first + 1, greater_begin, task->end, task->depth + 1);
  lt_fence();
  lt_atomic_store_i32(&s->state[task->node], first);
  lt_pool_retire(&s->pool, slot);
}

/* The root, before the first launch (one work-item): node 0, whose task is in the pool
 * unless there is nothing to sort (its state then stays a leaf). */
LT_DEVICE void lt_sort_setup(const lt_sort_build *s, lt_i32 count) {
  lt_i32 root = lt_heap_alloc(&s->node_heap, 1);
  if (root < 0 || count <= 0) return;
  lt_i32 slot = lt_pool_insert(&s->pool, s->task_kind, root, 0, count, 0, 1);
  if (slot < 0) return;
  lt_atomic_store_i32(&s->state[root], LT_SORT_UNBUILT(slot));
  lt_pool_publish(&s->pool, slot);
}

#endif
