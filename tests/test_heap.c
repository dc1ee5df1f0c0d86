/* The device heap (device/heap.h) on host threads, and a pool holding tasks of two kinds at
 * once, run by the persistent loop (kernels/persistent_loop_body.h) instantiated here for a
 * test workload: splitting tasks that take their room from the heap and spawn tasks of both
 * kinds, and tallying tasks of several chunks each. The device code is compiled as C and run
 * on native work-groups (one thread each), as the native backend runs it. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "device/heap.h"
#include "device/pool.h"
#include "runtime/context_internal.h"
#include "tests/support.h"

/* ---- Allocation from many threads ---- */

#define ALLOCS_PER_GROUP 20000
#define MAX_GROUPS 8

typedef struct alloc_job {
  lt_heap heap;
  lt_i32 *owner;  /* per unit: the group and request that took it, or -1 */
  lt_i32 failed[MAX_GROUPS];
  lt_i32 twice; /* units found already marked: handed out twice (checked on the main thread) */
  uint64_t seed;
} alloc_job;

/* Each group asks for blocks of 1 to 16 units and marks every unit of each block it gets. */
static void alloc_group(void *arg) {
  alloc_job *job = arg;
  int g = lt__native_group_id;
  uint64_t state = job->seed + (uint64_t)g * 7919;
  for (int k = 0; k < ALLOCS_PER_GROUP; k++) {
    lt_i32 n = 1 + (lt_i32)(lt__splitmix_next(&state) % 16);
    lt_i32 at = lt_heap_alloc(&job->heap, n);
    if (at < 0) {
      job->failed[g]++;
      continue;
    }
    for (lt_i32 i = at; i < at + n; i++) {
      /* A unit handed out twice would already carry another mark. */
      lt_i32 mark = g * ALLOCS_PER_GROUP + k;
      if (__atomic_exchange_n(&job->owner[i], mark, __ATOMIC_RELAXED) != -1) __atomic_fetch_add(&job->twice, 1, __ATOMIC_RELAXED);
    }
  }
}

static void run_allocs(int groups, lt_i32 capacity, uint64_t seed, lt_i32 *used, int *failures) {
  lt_i32 top = 0;
  alloc_job job;
  memset(&job, 0, sizeof job);
  job.heap.top = &top, job.heap.capacity = capacity, job.seed = seed;
  /* A guard zone past the end: nothing may be written there. */
  job.owner = malloc((size_t)(capacity + 64) * sizeof *job.owner);
  for (lt_i32 i = 0; i < capacity + 64; i++) job.owner[i] = -1;
  assert_int_equal(lt__native_run(groups, alloc_group, &job), LT_OK);
  assert_int_equal(job.twice, 0);
  for (lt_i32 i = capacity; i < capacity + 64; i++) assert_int_equal(job.owner[i], -1);

  /* The marked units are the ones handed out: a prefix without gaps, which the heap's own
   * count covers (it may also count the tail a failed request could not have). */
  lt_i32 marked = 0;
  while (marked < capacity && job.owner[marked] >= 0) marked++;
  for (lt_i32 i = marked; i < capacity; i++) assert_int_equal(job.owner[i], -1);
  *used = lt_heap_used(&job.heap);
  assert_true(marked <= *used && *used <= capacity);
  if (top <= capacity) assert_int_equal(marked, *used);
  *used = marked;
  *failures = 0;
  for (int g = 0; g < groups; g++) *failures += job.failed[g];
  free(job.owner);
}

static void heap_concurrent_blocks_are_disjoint(void **state) {
  (void)state;
  for (int groups = 1; groups <= MAX_GROUPS; groups *= 2) {
    lt_i32 used;
    int failures;
    run_allocs(groups, groups * ALLOCS_PER_GROUP * 16, 100 + groups, &used, &failures);
    assert_int_equal(failures, 0);
    assert_true(used >= groups * ALLOCS_PER_GROUP);
  }
}

static void heap_exhaustion_fails_cleanly_and_stays_in_bounds(void **state) {
  (void)state;
  lt_i32 used;
  int failures;
  run_allocs(4, 50000, 7, &used, &failures);
  assert_true(failures > 0);
  assert_true(used <= 50000 && used > 50000 - 16); /* full up to less than one block */

  /* A top past the end reads as a full heap, never as an offset. */
  lt_i32 top = 70000;
  lt_heap heap = {&top, 50000};
  assert_int_equal(lt_heap_used(&heap), 50000);
  assert_int_equal(lt_heap_alloc(&heap, 1), -1);
}

/* ---- Two task kinds in one pool ---- */

/* A split task over [begin, end) takes end - begin units from the heap, writes its element
 * numbers there, and spawns two split children and one tally task, until a range is small. */
enum { KIND_SPLIT = 0, KIND_TALLY = 1 };
#define SMALL 8
#define TALLY_CHUNK 4

typedef struct mixed_args {
  lt_pool pool;
  lt_heap heap;
  LT_GLOBAL lt_i32 *units;    /* the heap's room */
  LT_GLOBAL lt_i32 *counts;   /* [0]: elements tallied, [1]: elements placed, [2]: split tasks */
  lt_i32 max_idle_polls;
} mixed_args;

typedef struct mixed_item {
  int unused;
} mixed_item;

static lt_i32 tally_chunks(lt_i32 n) { return (n + TALLY_CHUNK - 1) / TALLY_CHUNK; }

static void mixed_spawn(const mixed_args *a, lt_i32 kind, lt_i32 begin, lt_i32 end, lt_i32 depth) {
  lt_i32 chunks = kind == KIND_TALLY ? tally_chunks(end - begin) : 1;
  lt_i32 slot = lt_pool_insert(&a->pool, kind, begin, begin, end, depth, chunks);
  if (slot >= 0) lt_pool_publish(&a->pool, slot);
}

static void split_chunk(const mixed_args *a, lt_i32 slot, lt_i32 chunk, int lid, int lsize) {
  (void)a, (void)slot, (void)chunk, (void)lid, (void)lsize; /* all the work is at the phase's end */
}

static void split_end(const mixed_args *a, lt_i32 slot) {
  LT_GLOBAL lt_task *task = &a->pool.tasks[slot];
  lt_i32 begin = task->begin, end = task->end;
  lt_i32 at = lt_heap_alloc(&a->heap, end - begin);
  if (at < 0) {
    lt_pool_fail(&a->pool, LT_POOL_ERROR_HEAP);
    return;
  }
  for (lt_i32 i = begin; i < end; i++) a->units[at + i - begin] = i;
  lt_atomic_add_i32(&a->counts[1], end - begin);
  lt_atomic_add_i32(&a->counts[2], 1);
  if (end - begin > SMALL) {
    lt_i32 mid = begin + (end - begin) / 2;
    mixed_spawn(a, KIND_SPLIT, begin, mid, task->depth + 1);
    mixed_spawn(a, KIND_SPLIT, mid, end, task->depth + 1);
    mixed_spawn(a, KIND_TALLY, begin, end, task->depth + 1);
  }
  lt_pool_retire(&a->pool, slot);
}

static void tally_chunk(const mixed_args *a, lt_i32 slot, lt_i32 chunk, int lid, int lsize) {
  LT_GLOBAL lt_task *task = &a->pool.tasks[slot];
  lt_i32 lo = task->begin + chunk * TALLY_CHUNK, hi = lo + TALLY_CHUNK < task->end ? lo + TALLY_CHUNK : task->end;
  (void)lsize;
  if (lid == 0) lt_atomic_add_i32(&a->counts[0], hi - lo);
}

static void tally_end(const mixed_args *a, lt_i32 slot) { lt_pool_retire(&a->pool, slot); }

#define LT_LOOP_NAME mixed_run
#define LT_LOOP_ARGS mixed_args
#define LT_LOOP_POOL(a) (&(a)->pool)
#define LT_LOOP_ITEM mixed_item
#define LT_LOOP_ITEMS_PER_WORK_ITEM 1
#define LT_LOOP_ITEM_COUNT(a) 0
#define LT_LOOP_START(a, q, i, c) ((void)(q))
#define LT_LOOP_ADVANCE(a, q, c) ((void)(q), 1)
#define LT_LOOP_FINISH(a, i, q) ((void)0)
#define LT_LOOP_BUILD(a) 1
#define LT_LOOP_MAX_IDLE(a) ((a)->max_idle_polls)
#define LT_LOOP_FLUSH(a, c) ((void)(c))
#define LT_LOOP_TASK_KINDS(X) X(KIND_SPLIT, split_chunk, split_end, a) X(KIND_TALLY, tally_chunk, tally_end, a)
#include "kernels/persistent_loop_body.h"

static void mixed_group(void *arg) {
  lt_loop_shared shared;
  mixed_run(arg, &shared);
}

/* The host side of the test workload: a pool and a heap of `capacity` units over n elements. */
typedef struct mixed_host {
  lt_i32 *headers, *empty_cache, *priority_cache, *units, counts[3], top;
  lt_task *tasks;
  lt_pool_control control;
  lt_u32 *stats;
  mixed_args args;
} mixed_host;

/* Runs the whole build on `groups` work-groups; returns the pool's error code. */
static lt_i32 run_mixed(int groups, lt_i32 n, lt_i32 capacity, mixed_host *h) {
  const lt_i32 slots = 4096, ring = 64;
  memset(h, 0, sizeof *h);
  h->headers = malloc(slots * sizeof *h->headers), h->tasks = calloc(slots, sizeof *h->tasks);
  h->empty_cache = malloc(ring * sizeof(lt_i32)), h->priority_cache = malloc(ring * sizeof(lt_i32));
  h->units = malloc((size_t)(capacity + 64) * sizeof *h->units);
  h->stats = calloc((size_t)groups * LT_POOL_STAT_COUNT, sizeof *h->stats);
  for (lt_i32 i = 0; i < slots; i++) h->headers[i] = LT_POOL_EMPTY;
  for (lt_i32 i = 0; i < ring; i++) h->empty_cache[i] = h->priority_cache[i] = -1;
  for (lt_i32 i = 0; i < capacity + 64; i++) h->units[i] = -1;
  h->control.termination = groups, h->control.groups = groups;
  mixed_args *a = &h->args;
  a->pool = (lt_pool){h->headers, h->tasks, h->empty_cache, h->priority_cache, &h->control, h->stats, NULL,
                      slots, ring, ring, 0, LT_POOL_FULL};
  a->heap = (lt_heap){&h->top, capacity};
  a->units = h->units, a->counts = h->counts, a->max_idle_polls = 50000000;

  /* The root, then every group runs the loop until the pool is done. */
  mixed_spawn(a, KIND_SPLIT, 0, n, 0);
  assert_int_equal(lt__native_run(groups, mixed_group, a), LT_OK);
  for (lt_i32 i = capacity; i < capacity + 64; i++) assert_int_equal(h->units[i], -1);
  return h->control.error;
}

static void mixed_free(mixed_host *h) {
  free(h->headers), free(h->tasks), free(h->empty_cache), free(h->priority_cache), free(h->units), free(h->stats);
}

/* Room the build needs: every split task takes its range, level by level down to SMALL. */
static lt_i32 units_needed(lt_i32 begin, lt_i32 end) {
  lt_i32 n = end - begin, mid = begin + n / 2;
  return n + (n > SMALL ? units_needed(begin, mid) + units_needed(mid, end) : 0);
}

static lt_i32 tallied(lt_i32 begin, lt_i32 end) {
  lt_i32 n = end - begin, mid = begin + n / 2;
  return n > SMALL ? n + tallied(begin, mid) + tallied(mid, end) : 0;
}

static void heap_two_task_kinds_in_one_pool(void **state) {
  (void)state;
  const lt_i32 n = 5000;
  lt_i32 need = units_needed(0, n);
  for (int groups = 1; groups <= 4; groups++) {
    mixed_host h;
    assert_int_equal(run_mixed(groups, n, need, &h), LT_POOL_OK);
    assert_int_equal(h.control.outstanding, 0);
    assert_int_equal(h.top, need);
    assert_int_equal(h.counts[1], need);       /* every split placed its range */
    assert_int_equal(h.counts[0], tallied(0, n)); /* every tally task ran all its chunks */

    /* Each element appears in the heap once per level above its leaf and in its leaf. */
    lt_i32 *seen = calloc((size_t)n, sizeof *seen);
    for (lt_i32 i = 0; i < need; i++) {
      assert_true(h.units[i] >= 0 && h.units[i] < n);
      seen[h.units[i]]++;
    }
    for (lt_i32 e = 0; e < n; e++) assert_true(seen[e] >= 2);
    free(seen);

    /* Both kinds were retired: the pool's counters saw every task. */
    lt_u32 tasks = 0;
    for (int g = 0; g < groups; g++) tasks += h.stats[g * LT_POOL_STAT_COUNT + LT_POOL_STAT_TASKS];
    assert_int_equal(tasks, (lt_u32)(h.counts[2] + (h.counts[2] - 1) / 2)); /* splits, and a tally per inner one */
    mixed_free(&h);
  }
}

/* Too small a heap stops the launch with the heap error; the host retries with twice the room
 * until it fits, as a structure's host half does, and then gets the same answer. */
static void heap_full_reports_and_succeeds_when_retried_larger(void **state) {
  (void)state;
  const lt_i32 n = 3000;
  lt_i32 need = units_needed(0, n), capacity = need / 5, tries = 0;
  for (;;) {
    mixed_host h;
    lt_i32 error = run_mixed(2, n, capacity, &h);
    tries++;
    if (error == LT_POOL_OK) {
      assert_true(capacity >= need);
      assert_int_equal(h.top, need);
      mixed_free(&h);
      break;
    }
    assert_int_equal(error, LT_POOL_ERROR_HEAP);
    assert_true(capacity < need);
    mixed_free(&h);
    capacity *= 2;
  }
  assert_true(tries >= 2);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(heap_concurrent_blocks_are_disjoint),
      cmocka_unit_test(heap_exhaustion_fails_cleanly_and_stays_in_bounds),
      cmocka_unit_test(heap_two_task_kinds_in_one_pool),
      cmocka_unit_test(heap_full_reports_and_succeeds_when_retried_larger),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
