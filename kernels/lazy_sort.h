/* The scheduler's own workload: a quicksort built on demand through the task pool. It
 * mirrors node subdivision without geometry. A task partitions the elements of one node around
 * a pivot (phases: pick the pivot, count, scatter, copy back) and spawns two children; the
 * "rays" are queries for the element at a sorted position, which walk the tree from the root
 * like a traversal and request the unbuilt nodes they reach. Only what the queries need gets
 * sorted in requested mode; everything in a full build. The answers are checkable. */
#ifndef LT_LAZY_SORT_H
#define LT_LAZY_SORT_H

#include "device/pool.h"

#define LT_SORT_CHUNK 256 /* elements per work chunk */
#define LT_SORT_LEAF 32   /* ranges this small are sorted at once by their parent */
#define LT_SORT_MAX_DEPTH 4096
#ifndef LT_MAX_LOCAL_SIZE
#define LT_MAX_LOCAL_SIZE 256
#endif

/* Node states: a leaf is sorted; an unbuilt node points at its task; a built node holds the
 * id of its first child (the second is first + 1). */
#define LT_SORT_LEAF_STATE (-1)
#define LT_SORT_UNBUILT(slot) (-2 - (slot))

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

typedef struct lt_sort {
  lt_pool pool;
  LT_GLOBAL lt_u32 *keys;
  LT_GLOBAL lt_u32 *scratch;
  LT_GLOBAL lt_i32 *state;      /* per node: leaf, unbuilt or built */
  LT_GLOBAL lt_int4 *nodes;     /* per built node: less_end, greater_begin, pivot, first child */
  LT_GLOBAL const lt_i32 *queries; /* sorted positions asked for */
  LT_GLOBAL lt_u32 *answers;
  lt_i32 query_count;
  lt_i32 node_capacity;
  lt_i32 max_idle_polls;
} lt_sort;

/* What a work-group shares in local memory. */
typedef struct lt_sort_shared {
  lt_pool_round round;
  lt_i32 pending[LT_MAX_LOCAL_SIZE];
} lt_sort_shared;

LT_DEVICE lt_i32 lt_sort_chunks(lt_i32 n) { return (n + LT_SORT_CHUNK - 1) / LT_SORT_CHUNK; }

/* Walks query `pos` from node *node; returns 1 with *answer set, or 0 when it stops at an
 * unbuilt node (left in *node, where the walk restarts). A walk that starts suspended on a
 * node still unbuilt has requested it already and just stays. */
LT_DEVICE int lt_sort_walk(const lt_sort *s, lt_i32 pos, lt_i32 *node, int suspended, lt_u32 *answer) {
  lt_i32 id = *node;
  for (int depth = 0; depth < LT_SORT_MAX_DEPTH; depth++) {
    lt_i32 state = lt_atomic_load_i32(&s->state[id]);
    if (state == LT_SORT_LEAF_STATE) {
      *answer = s->keys[pos];
      return 1;
    }
    if (state <= -2) {
      if (!suspended || id != *node) {
        lt_pool_request(&s->pool, -2 - state, id);
        lt_pool_count(&s->pool, LT_POOL_STAT_STALLS, 1);
      }
      *node = id;
      return 0;
    }
    lt_int4 n = s->nodes[id];
    if (pos >= n.x && pos < n.y) {
      *answer = (lt_u32)n.z;
      return 1;
    }
    id = pos < n.x ? state : state + 1;
  }
  lt_pool_fail(&s->pool, LT_POOL_ERROR_STACK);
  *answer = 0;
  return 1;
}

/* One chunk of the current phase, shared by the work-items of the group. */
LT_DEVICE void lt_sort_chunk(const lt_sort *s, lt_i32 slot, lt_i32 chunk, int lid, int lsize) {
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

LT_DEVICE void lt_sort_small(const lt_sort *s, lt_i32 begin, lt_i32 end) {
  for (lt_i32 i = begin + 1; i < end; i++) {
    lt_u32 k = s->keys[i];
    lt_i32 j = i - 1;
    for (; j >= begin && s->keys[j] > k; j--) s->keys[j + 1] = s->keys[j];
    s->keys[j + 1] = k;
  }
}

/* Links one child of a finished node: small ranges are sorted now, others become tasks. */
LT_DEVICE void lt_sort_spawn(const lt_sort *s, lt_i32 child, lt_i32 begin, lt_i32 end, lt_i32 depth) {
  if (end - begin <= LT_SORT_LEAF) {
    lt_sort_small(s, begin, end);
    lt_fence();
    lt_atomic_store_i32(&s->state[child], LT_SORT_LEAF_STATE);
    return;
  }
  lt_i32 slot = lt_pool_insert(&s->pool, child, begin, end, depth, 1);
  if (slot < 0) return;
  lt_atomic_store_i32(&s->state[child], LT_SORT_UNBUILT(slot));
  lt_pool_publish(&s->pool, slot);
}

/* Called by the work-group that finished the last chunk of a phase (work-item 0 only). */
LT_DEVICE void lt_sort_end_phase(const lt_sort *s, lt_i32 slot) {
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
  lt_i32 first = lt_atomic_add_i32(&s->pool.control->nodes_next, 2);
  if (first + 2 > s->node_capacity) {
    lt_pool_fail(&s->pool, LT_POOL_ERROR_NODES);
    return;
  }
  s->nodes[task->node] = lt_make_int4(less_end, greater_begin, lt_atomic_load_i32(&w[W_PIVOT]), first);
  lt_sort_spawn(s, first, task->begin, less_end, task->depth + 1);
  lt_sort_spawn(s, first + 1, greater_begin, task->end, task->depth + 1);
  lt_fence();
  lt_atomic_store_i32(&s->state[task->node], first);
  lt_pool_retire(&s->pool, slot);
}

/* The persistent loop of every work-group: answer queries, and build what they wait for;
 * out of queries, keep building until every work-group is out (termination counter). Every
 * barrier sits in the loop's straight-line body, never under a condition, because OpenCL
 * implementations that run a work-group as loops over its work-items (PoCL) need it so. */
LT_DEVICE void lt_sort_run(const lt_sort *s, LT_LOCAL lt_sort_shared *sh) {
  int lid = lt_local_id(), lsize = lt_local_size();
  const lt_pool *pool = &s->pool;
  lt_i32 item = -1, node = 0;
  int suspended = 0, running = 1;
  lt_pool_worker worker = lt_pool_worker_new();
  while (running) {
    /* Restart or continue this work-item's query. */
    if (item >= 0) {
      lt_u32 answer;
      suspended = !lt_sort_walk(s, s->queries[item], &node, suspended, &answer);
      if (!suspended) {
        s->answers[item] = answer;
        item = -1;
      }
    }
    sh->pending[lid] = item >= 0;
    lt_barrier();

    /* Work-item 0 decides for the group: a new batch of queries, building, or quitting. */
    if (lid == 0) {
      int waiting = 0;
      for (int l = 0; l < lsize; l++) waiting |= sh->pending[l];
      lt_pool_round r = lt_pool_decide(pool, &worker, waiting, 1, lsize, s->query_count, s->max_idle_polls);
      if (r.slot >= 0) lt_pool_log_start(pool, r.slot, r.chunk);
      sh->round = r;
    }
    lt_barrier();
    running = !sh->round.quit;
    lt_i32 batch = sh->round.batch, slot = sh->round.slot, chunk = sh->round.chunk;

    /* A new batch: every work-item takes one query and walks it at the top of the loop. */
    if (running && batch >= 0) {
      item = batch + lid < s->query_count ? batch + lid : -1;
      node = 0;
      suspended = 0;
    }

    /* Building: the group works the chunk together; work-item 0 finishes it. */
    int building = running && batch < 0 && slot >= 0;
    if (building) lt_sort_chunk(s, slot, chunk, lid, lsize);
    lt_barrier();
    if (building && lid == 0 && lt_pool_finish_chunk(pool, slot)) lt_sort_end_phase(s, slot);
    lt_barrier();
  }
}

#endif
