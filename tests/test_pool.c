/* The task pool: its operations one by one on host arrays (device/pool.h compiled as C), and
 * the whole scheduler through its own workload, the lazy sort, on both backends. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "device/pool.h"
#include "runtime/context_internal.h"
#include "tests/support.h"

/* ---- A pool on host arrays, driven by hand from one thread ---- */

typedef struct host_pool {
  lt_i32 headers[64];
  lt_task tasks[64];
  lt_i32 empty_cache[4], priority_cache[4];
  lt_pool_control control;
  lt_u32 stats[LT_POOL_STAT_COUNT];
  lt_pool pool;
} host_pool;

static host_pool *host_pool_new(int capacity, int mode) {
  host_pool *h = calloc(1, sizeof *h);
  for (int i = 0; i < 64; i++) h->headers[i] = LT_POOL_EMPTY;
  for (int i = 0; i < 4; i++) h->empty_cache[i] = h->priority_cache[i] = -1;
  h->pool = (lt_pool){h->headers, h->tasks, h->empty_cache, h->priority_cache, &h->control, h->stats, NULL,
                      capacity, 4, 4, 0, mode};
  return h;
}

static lt_i32 insert_published(host_pool *h, lt_i32 node, lt_i32 chunks) {
  lt_i32 slot = lt_pool_insert(&h->pool, 0, node, 0, 100, 0, chunks);
  assert_true(slot >= 0);
  assert_int_equal(h->headers[slot], 0); /* locked while it is being linked */
  lt_pool_publish(&h->pool, slot);
  return slot;
}

/* Empty -> locked -> waiting -> unlocked (chunks counting down) -> locked -> next phase ->
 * retired (empty, in the empty-task cache). */
static void pool_header_states_and_transitions(void **state) {
  (void)state;
  host_pool *h = host_pool_new(8, LT_POOL_REQUESTED);
  lt_i32 chunk;
  lt_i32 slot = insert_published(h, 5, 3);
  assert_int_equal(h->headers[slot], LT_POOL_WAITING(5));
  assert_true(LT_POOL_IS_WAITING(h->headers[slot]));
  assert_int_equal(h->control.outstanding, 1);
  assert_int_equal(lt_pool_take(&h->pool, &chunk), -1); /* a waiting task gives no work */

  /* A request unlocks it with its first phase's chunks and prioritises it. */
  assert_int_equal(lt_pool_request(&h->pool, slot, 5), 1);
  assert_int_equal(h->headers[slot], 3);
  assert_int_equal(h->stats[LT_POOL_STAT_REQUESTED], 1);
  for (int expect = 2; expect >= 0; expect--) {
    assert_int_equal(lt_pool_take(&h->pool, &chunk), slot);
    assert_int_equal(chunk, expect);
  }
  assert_int_equal(h->headers[slot], 0); /* all chunks handed out: locked */
  assert_int_equal(lt_pool_take(&h->pool, &chunk), -1);

  /* Only the last finisher switches the phase. */
  assert_false(lt_pool_finish_chunk(&h->pool, slot));
  assert_false(lt_pool_finish_chunk(&h->pool, slot));
  assert_true(lt_pool_finish_chunk(&h->pool, slot));
  lt_pool_next_phase(&h->pool, slot, 1, 2);
  assert_int_equal(h->headers[slot], 2);
  assert_int_equal(h->tasks[slot].phase, 1);
  assert_int_equal(lt_pool_take(&h->pool, &chunk), slot);
  assert_int_equal(lt_pool_take(&h->pool, &chunk), slot);
  assert_false(lt_pool_finish_chunk(&h->pool, slot));
  assert_true(lt_pool_finish_chunk(&h->pool, slot));

  /* Retired: empty again, in the empty-task cache, no longer outstanding. */
  lt_pool_retire(&h->pool, slot);
  assert_int_equal(h->headers[slot], LT_POOL_EMPTY);
  assert_int_equal(h->empty_cache[0], slot);
  assert_int_equal(h->control.outstanding, 0);
  assert_int_equal(h->stats[LT_POOL_STAT_TASKS], 1);
  assert_int_equal(h->stats[LT_POOL_STAT_SPECULATIVE], 0);
  free(h);
}

/* The waiting value is unique per node: a request naming another node fails, as does a
 * request for a slot that has since been emptied and reused. */
static void pool_cas_with_another_waiting_value_does_not_unlock(void **state) {
  (void)state;
  host_pool *h = host_pool_new(8, LT_POOL_REQUESTED);
  lt_i32 a = insert_published(h, 7, 1);
  assert_int_equal(lt_pool_request(&h->pool, a, 8), 0);
  assert_int_equal(h->headers[a], LT_POOL_WAITING(7));
  assert_int_equal(h->priority_cache[0], -1);

  /* Node 7's task finishes and its slot goes to node 9: a late request for 7 does nothing. */
  assert_int_equal(lt_pool_request(&h->pool, a, 7), 1);
  lt_i32 chunk;
  assert_int_equal(lt_pool_take(&h->pool, &chunk), a);
  assert_true(lt_pool_finish_chunk(&h->pool, a));
  lt_pool_retire(&h->pool, a);
  lt_i32 b = insert_published(h, 9, 1);
  assert_int_equal(b, a);
  assert_int_equal(lt_pool_request(&h->pool, b, 7), 0);
  assert_int_equal(h->headers[b], LT_POOL_WAITING(9));
  free(h);
}

/* An emptied slot is found through the empty-task cache, without a scan. */
static void pool_emptied_slot_is_reused_through_the_cache(void **state) {
  (void)state;
  host_pool *h = host_pool_new(64, LT_POOL_SPECULATIVE);
  lt_i32 slots[5];
  for (int i = 0; i < 5; i++) slots[i] = insert_published(h, 10 + i, 1);
  assert_int_equal(h->stats[LT_POOL_STAT_EMPTY_HITS], 0);

  /* Retire the task in slot 2: the next insert takes slot 2 from the cache. */
  h->headers[slots[2]] = 0;
  h->tasks[slots[2]].done = 0;
  assert_true(lt_pool_finish_chunk(&h->pool, slots[2]));
  lt_pool_retire(&h->pool, slots[2]);
  lt_i32 again = insert_published(h, 20, 1);
  assert_int_equal(again, slots[2]);
  assert_int_equal(h->stats[LT_POOL_STAT_EMPTY_HITS], 1);
  free(h);
}

/* Requested tasks come out of the prioritisation cache before any speculative task; the
 * order of takes is recorded and checked. */
static void pool_requested_before_speculative(void **state) {
  (void)state;
  host_pool *h = host_pool_new(16, LT_POOL_SPECULATIVE);
  lt_i32 slot_of[8];
  for (int node = 1; node <= 6; node++) slot_of[node] = insert_published(h, node, 1);
  lt_pool_request(&h->pool, slot_of[4], 4);
  lt_pool_request(&h->pool, slot_of[2], 2);
  assert_int_equal(h->stats[LT_POOL_STAT_REQUESTED], 2);

  lt_i32 order[6], chunk;
  for (int i = 0; i < 6; i++) {
    lt_i32 slot = lt_pool_take(&h->pool, &chunk);
    assert_true(slot >= 0);
    order[i] = h->tasks[slot].node;
  }
  assert_int_equal(lt_pool_take(&h->pool, &chunk), -1);
  assert_int_equal(order[0], 2); /* newest request first */
  assert_int_equal(order[1], 4);
  for (int i = 2; i < 6; i++) assert_true(order[i] != 2 && order[i] != 4);
  assert_int_equal(h->stats[LT_POOL_STAT_CACHE_HITS], 2);
  free(h);
}

/* A prioritised slot that is retired and reused by a task nobody asked for is not taken as
 * requested: the stale cache entry is skipped (this once let speculation pose as requests). */
static void pool_stale_priority_entry_is_not_a_request(void **state) {
  (void)state;
  host_pool *h = host_pool_new(16, LT_POOL_SPECULATIVE);
  lt_i32 chunk, a = insert_published(h, 1, 1);
  lt_pool_request(&h->pool, a, 1);
  assert_int_equal(lt_pool_take_requested(&h->pool, &chunk), a);
  assert_true(lt_pool_finish_chunk(&h->pool, a));
  lt_pool_retire(&h->pool, a);
  lt_i32 b = insert_published(h, 2, 1); /* same slot, from the empty-task cache */
  assert_int_equal(b, a);
  assert_int_equal(lt_pool_take_requested(&h->pool, &chunk), -1);
  assert_int_equal(lt_pool_take(&h->pool, &chunk), b); /* still there as speculative work */
  free(h);
}

/* A full pool says so: the insert fails and the error is set for every work-group to see. */
static void pool_full_is_reported(void **state) {
  (void)state;
  host_pool *h = host_pool_new(2, LT_POOL_FULL);
  insert_published(h, 1, 1);
  insert_published(h, 2, 1);
  assert_int_equal(lt_pool_insert(&h->pool, 0, 3, 0, 1, 0, 1), -1);
  assert_int_equal(h->control.error, LT_POOL_ERROR_FULL);
  assert_true(lt_pool_may_quit(&h->pool));
  free(h);
}

/* Termination: nobody quits while a work-group has own work; then requested and speculative
 * builds quit at once, a full build only when no task is outstanding. */
static void pool_termination_counter(void **state) {
  (void)state;
  host_pool *h = host_pool_new(8, LT_POOL_FULL);
  h->control.termination = 2;
  assert_false(lt_pool_may_quit(&h->pool));
  lt_atomic_add_i32(&h->control.termination, -1);
  lt_atomic_add_i32(&h->control.termination, -1);
  assert_true(lt_pool_may_quit(&h->pool)); /* zero tasks */
  insert_published(h, 1, 1);
  assert_false(lt_pool_may_quit(&h->pool));
  h->pool.mode = LT_POOL_SPECULATIVE;
  assert_true(lt_pool_may_quit(&h->pool));
  free(h);
}

/* The stall cap counts only polls during which every work-group is idle and nothing moves: a
 * work-group may wait any number of polls for another that is busy (tracing a long batch, or
 * set aside by the operating system), but when all poll without progress the cap trips. */
static void pool_stall_cap_waits_for_a_busy_group(void **state) {
  (void)state;
  host_pool *h = host_pool_new(8, LT_POOL_REQUESTED);
  h->control.groups = 2;
  lt_pool_worker a = lt_pool_worker_new(), b = lt_pool_worker_new();
  lt_pool_busy(&h->pool, &b); /* b is tracing */
  for (int i = 0; i < 1000; i++) lt_pool_idle(&h->pool, &a, 10);
  assert_int_equal(h->control.error, LT_POOL_OK);
  assert_int_equal(h->control.idle_groups, 1);

  /* Both idle: the cap trips after 10 polls without progress... */
  lt_pool_idle(&h->pool, &b, 10);
  assert_int_equal(h->control.idle_groups, 2);
  for (int i = 0; i < 10; i++) lt_pool_idle(&h->pool, &a, 10);
  assert_int_equal(h->control.error, LT_POOL_OK);
  lt_pool_idle(&h->pool, &a, 10);
  assert_int_equal(h->control.error, LT_POOL_ERROR_STALL);

  /* ...but not while progress moves, and a group that leaves counts as idle for good. */
  h->control.error = LT_POOL_OK;
  lt_pool_busy(&h->pool, &a), lt_pool_busy(&h->pool, &b);
  assert_int_equal(h->control.idle_groups, 0);
  for (int i = 0; i < 100; i++) {
    lt_atomic_add_i32(&h->control.progress, 1);
    lt_pool_idle(&h->pool, &a, 10);
  }
  assert_int_equal(h->control.error, LT_POOL_OK);
  lt_pool_leave(&h->pool, &b);
  lt_pool_leave(&h->pool, &b);
  assert_int_equal(h->control.idle_groups, 2);
  for (int i = 0; i < 12; i++) lt_pool_idle(&h->pool, &a, 10);
  assert_int_equal(h->control.error, LT_POOL_ERROR_STALL);
  free(h);
}

/* ---- The scheduler end to end: lazy sorts on every backend ---- */

typedef struct backend {
  lt_device_kind kind;
  int work_groups, local_size;
} backend;

static int opencl_ok = -1;

static lt_context *open_backend(const backend *b) {
  lt_context *ctx = NULL;
  lt_context_config config = {b->kind, 0, b->work_groups, b->local_size, 1};
  if (b->kind == LT_DEVICE_OPENCL && (opencl_ok == 0 || getenv("LT_TEST_NATIVE_ONLY"))) return NULL;
  lt_status status = lt_context_create(&config, &ctx);
  if (b->kind == LT_DEVICE_OPENCL) opencl_ok = status == LT_OK;
  return status == LT_OK ? ctx : NULL;
}

static int compare_u32(const void *a, const void *b) {
  uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
  return (x > y) - (x < y);
}

/* Keys with many duplicates (a range of n / 3) so that the three-way split is exercised. */
static void make_keys(uint64_t seed, size_t n, uint32_t *keys, uint32_t *sorted) {
  for (size_t i = 0; i < n; i++) keys[i] = (uint32_t)(lt__splitmix_next(&seed) % (n / 3 + 1));
  memcpy(sorted, keys, n * sizeof *keys);
  qsort(sorted, n, sizeof *sorted, compare_u32);
}

/* One lazy sort: queries in the given mode, answers checked, the full array checked in full
 * mode. Returns the tasks the pool ran. */
static double run_sort(const backend *b, lt_build_mode mode, uint64_t seed, size_t n, size_t queries) {
  lt_context *ctx = open_backend(b);
  if (!ctx) return -1;
  uint32_t *keys = malloc((n + 1) * 4), *sorted = malloc((n + 1) * 4), *answers = malloc((queries + 1) * 4);
  int32_t *positions = malloc((queries + 1) * 4);
  make_keys(seed, n, keys, sorted);
  for (size_t i = 0; i < queries; i++) positions[i] = (int32_t)(lt__splitmix_next(&seed) % n);
  lt_lazy_sort *sort;
  lt_stats *stats;
  assert_int_equal(lt_stats_create(&stats), LT_OK);
  assert_int_equal(lt_lazy_sort_create(ctx, keys, n, mode, NULL, &sort), LT_OK);
  lt_status status = lt_lazy_sort_query(sort, positions, queries, answers, stats);
  if (status) fprintf(stderr, "lazy sort failed: %s\n", lt_last_error());
  assert_int_equal(status, LT_OK);
  for (size_t i = 0; i < queries; i++) assert_int_equal(answers[i], sorted[positions[i]]);
  if (mode == LT_BUILD_FULL) {
    assert_int_equal(lt_lazy_sort_keys(sort, keys), LT_OK);
    assert_memory_equal(keys, sorted, n * 4);
  }
  double tasks = lt_stats_get(stats, "pool.tasks");
  lt_lazy_sort_destroy(sort);
  lt_stats_destroy(stats);
  lt_context_destroy(ctx);
  free(keys), free(sorted), free(answers), free(positions);
  return tasks;
}


static const backend backends[] = {{LT_DEVICE_NATIVE, 2, 1}, {LT_DEVICE_OPENCL, 0, 8}};


/* Zero tasks (nothing to sort), one task (a root whose children are small), and all
 * work-groups running out of own work at once (no queries at all). */
static void pool_terminates_with_zero_one_and_no_queries(void **state) {
  (void)state;
  for (int i = 0; i < 2; i++) {
    if (run_sort(&backends[i], LT_BUILD_FULL, 1, 0, 0) < 0) continue; /* no such backend */
    assert_true(run_sort(&backends[i], LT_BUILD_FULL, 1, 0, 0) == 0);
    assert_true(run_sort(&backends[i], LT_BUILD_FULL, 2, 33, 5) == 1); /* both sides fit a leaf */
    assert_true(run_sort(&backends[i], LT_BUILD_REQUESTED, 3, 5000, 0) == 0);
    assert_true(run_sort(&backends[i], LT_BUILD_FULL, 4, 5000, 0) > 10);
  }
}

/* A requested lazy sort of 1000 keys on `groups` native work-groups, queried for 10 keys with
 * one fault injected: the thread of work-group fail_group cannot start, or work-group
 * stall_group stops at once (-1: none). Returns the query's status; *ms gets its time. */
static lt_status query_with_fault(int groups, int fail_group, int stall_group, int stall_seconds, double *ms) {
  lt_context *ctx;
  lt_context_config native = {LT_DEVICE_NATIVE, 0, groups, 0, 1};
  assert_int_equal(lt_context_create(&native, &ctx), LT_OK);
  uint32_t keys[1000], answers[10];
  int32_t positions[10];
  for (int i = 0; i < 1000; i++) keys[i] = (uint32_t)(i * 7919 % 1000);
  for (int i = 0; i < 10; i++) positions[i] = i * 97;
  lt_pool_config config = {0, 0, 0, 0, 0, stall_seconds};
  lt_lazy_sort *sort;
  assert_int_equal(lt_lazy_sort_create(ctx, keys, 1000, LT_BUILD_REQUESTED, &config, &sort), LT_OK);
  lt__native_fail_group = fail_group, lt__native_stall_group = stall_group;
  double start = lt_now_ms();
  lt_status status = lt_lazy_sort_query(sort, positions, 10, answers, NULL);
  *ms = lt_now_ms() - start;
  lt__native_fail_group = lt__native_stall_group = -1;
  lt_lazy_sort_destroy(sort);
  lt_context_destroy(ctx);
  return status;
}

/* A native work-group whose thread cannot start stops the launch with an error instead of
 * leaving the others waiting for it forever (they used to spin without end). */
static void pool_native_thread_that_cannot_start_is_reported(void **state) {
  (void)state;
  double ms;
  assert_int_equal(query_with_fault(3, 2, -1, 0, &ms), LT_ERROR_OUT_OF_MEMORY);
  assert_non_null(strstr(lt_last_error(), "work-group 2"));
  assert_true(ms < 5000.0);
}

/* A work-group that stops inside a launch without leaving the pool (the others wait for it to
 * give up its queries, and it never does) ends the launch with LT_ERROR_SCHEDULER once nothing
 * has moved for the configured time, instead of hanging. */
static void pool_stalled_work_group_is_a_scheduler_error(void **state) {
  (void)state;
  double ms;
  assert_int_equal(query_with_fault(2, -1, 1, 1, &ms), LT_ERROR_SCHEDULER);
  fprintf(stderr, "a stalled work-group: LT_ERROR_SCHEDULER after %.0f ms (%s)\n", ms, lt_last_error());
  assert_true(ms >= 900.0 && ms < 10000.0);
}

/* A pool too small for the frontier reports LT_ERROR_CAPACITY; a larger one then succeeds. */
static void pool_full_reports_and_succeeds_when_retried_larger(void **state) {
  (void)state;
  for (int i = 0; i < 2; i++) {
    lt_context *ctx = open_backend(&backends[i]);
    if (!ctx) continue;
    size_t n = 50000;
    uint32_t *keys = malloc(n * 4), *sorted = malloc(n * 4), answers[64];
    int32_t positions[64];
    make_keys(9, n, keys, sorted);
    for (int q = 0; q < 64; q++) positions[q] = (int32_t)(q * 781 % n);
    lt_pool_config small = {8, 0, 0, 0, 0, 0};
    lt_lazy_sort *sort;
    assert_int_equal(lt_lazy_sort_create(ctx, keys, n, LT_BUILD_REQUESTED, &small, &sort), LT_OK);
    assert_int_equal(lt_lazy_sort_query(sort, positions, 64, answers, NULL), LT_ERROR_CAPACITY);
    assert_non_null(strstr(lt_last_error(), "task pool is full"));
    lt_lazy_sort_destroy(sort);

    lt_pool_config larger = {4096, 0, 0, 0, 0, 0};
    assert_int_equal(lt_lazy_sort_create(ctx, keys, n, LT_BUILD_REQUESTED, &larger, &sort), LT_OK);
    assert_int_equal(lt_lazy_sort_query(sort, positions, 64, answers, NULL), LT_OK);
    for (int q = 0; q < 64; q++) assert_int_equal(answers[q], sorted[positions[q]]);
    lt_lazy_sort_destroy(sort);
    lt_context_destroy(ctx);
    free(keys), free(sorted);
  }
}

/* The pool and the partial sort persist: a second launch continues, and repeating the first
 * launch's queries builds nothing new. */
static void pool_persists_across_launches(void **state) {
  (void)state;
  for (int i = 0; i < 2; i++) {
    lt_context *ctx = open_backend(&backends[i]);
    if (!ctx) continue;
    size_t n = 100000;
    uint32_t *keys = malloc(n * 4), *sorted = malloc(n * 4), answers[200];
    int32_t first[200], second[200];
    make_keys(13, n, keys, sorted);
    for (int q = 0; q < 200; q++) first[q] = (int32_t)(q * 97 % 20000), second[q] = (int32_t)(50000 + q * 211 % 50000);
    lt_lazy_sort *sort;
    lt_stats *stats;
    size_t built_first, built_second, left;
    assert_int_equal(lt_stats_create(&stats), LT_OK);
    assert_int_equal(lt_lazy_sort_create(ctx, keys, n, LT_BUILD_REQUESTED, NULL, &sort), LT_OK);
    assert_int_equal(lt_lazy_sort_query(sort, first, 200, answers, NULL), LT_OK);
    for (int q = 0; q < 200; q++) assert_int_equal(answers[q], sorted[first[q]]);
    assert_int_equal(lt_lazy_sort_progress(sort, &built_first, &left), LT_OK);
    assert_true(left > 0); /* requested: parts of the tree no query reached are not built */

    assert_int_equal(lt_lazy_sort_query(sort, second, 200, answers, NULL), LT_OK);
    for (int q = 0; q < 200; q++) assert_int_equal(answers[q], sorted[second[q]]);
    assert_int_equal(lt_lazy_sort_progress(sort, &built_second, &left), LT_OK);
    assert_true(built_second > built_first);

    assert_int_equal(lt_lazy_sort_query(sort, first, 200, answers, stats), LT_OK);
    for (int q = 0; q < 200; q++) assert_int_equal(answers[q], sorted[first[q]]);
    assert_true(lt_stats_get(stats, "pool.tasks") == 0);
    lt_stats_destroy(stats);
    lt_lazy_sort_destroy(sort);
    lt_context_destroy(ctx);
    free(keys), free(sorted);
  }
}

/* Requested mode builds only what the queries need; a full build builds everything. */
static void pool_requested_builds_less_than_full(void **state) {
  (void)state;
  double full = run_sort(&backends[0], LT_BUILD_FULL, 21, 200000, 50);
  double requested = run_sort(&backends[0], LT_BUILD_REQUESTED, 21, 200000, 50);
  double speculative = run_sort(&backends[0], LT_BUILD_SPECULATIVE, 21, 200000, 50);
  fprintf(stderr, "tasks for 50 queries over 200000 keys: full %.0f, requested %.0f, speculative %.0f\n", full,
          requested, speculative);
  assert_true(requested < full / 4);
  assert_true(speculative > 0 && speculative <= full); /* sort trees differ run to run: no finer order */
}

/* The level baseline, run many times: each level's launch must end with exactly the next
 * level waiting. This caught a stale last-finisher check (a chunk count read after the
 * increment could belong to the next phase or to the slot's next task), which failed within
 * about 20 sorts of 300,000 keys on 2 work-groups. */
static void pool_level_baseline_repeats(void **state) {
  (void)state;
  size_t n = 300000;
  uint32_t *keys = malloc(n * 4), *sorted = malloc(n * 4), *out = malloc(n * 4);
  make_keys(31, n, keys, sorted);
  for (int b = 0; b < 2; b++) {
    lt_context *ctx = open_backend(&backends[b]);
    if (!ctx) continue;
    int repeats = getenv("LT_TEST_QUICK") ? 5 : b == 0 ? 60 : 15;
    for (int r = 0; r < repeats; r++) {
      lt_lazy_sort *sort;
      int levels = 0;
      assert_int_equal(lt_lazy_sort_create(ctx, keys, n, LT_BUILD_FULL, NULL, &sort), LT_OK);
      lt_status status = lt_lazy_sort_by_levels(sort, NULL, &levels);
      if (status) fprintf(stderr, "repeat %d: %s\n", r, lt_last_error());
      assert_int_equal(status, LT_OK);
      assert_int_equal(lt_lazy_sort_keys(sort, out), LT_OK);
      assert_memory_equal(out, sorted, n * 4);
      lt_lazy_sort_destroy(sort);
    }
    lt_context_destroy(ctx);
  }
  free(keys), free(sorted), free(out);
}

/* Many seeds, every work-group count up to the concurrent one (and one more natively, where
 * threads can oversubscribe), local sizes 1 to 32, every mode; and one run of at least
 * 100,000 tasks per backend. LT_STRESS_ROUNDS scales the seeds. */
static void pool_stress(void **state) {
  (void)state;
  int rounds = getenv("LT_STRESS_ROUNDS") ? atoi(getenv("LT_STRESS_ROUNDS")) : 2;
  int local_sizes[] = {1, 2, 7, 32};
  uint64_t seed = 1000;
  for (int r = 0; r < rounds; r++)
    for (int mode = LT_BUILD_FULL; mode <= LT_BUILD_SPECULATIVE; mode++) {
      for (int groups = 1; groups <= 3; groups++) {
        backend native = {LT_DEVICE_NATIVE, groups, 1};
        run_sort(&native, (lt_build_mode)mode, seed++, 20000 + 7919 * r, 300);
      }
      for (int l = 0; l < 4; l++)
        for (int groups = 1; groups <= 2; groups++) {
          backend opencl = {LT_DEVICE_OPENCL, groups, local_sizes[l]};
          run_sort(&opencl, (lt_build_mode)mode, seed++, 20000 + 7919 * r, 300);
        }
    }

  /* The big one: a full sort of 2.5M keys runs well over 100,000 tasks. */
  for (int i = 0; i < 2; i++) {
    double tasks = run_sort(&backends[i], LT_BUILD_FULL, 77, 2500000, 1000);
    if (tasks < 0) continue;
    fprintf(stderr, "backend %d: %.0f tasks\n", i, tasks);
    assert_true(tasks >= 100000);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(pool_header_states_and_transitions),
      cmocka_unit_test(pool_cas_with_another_waiting_value_does_not_unlock),
      cmocka_unit_test(pool_emptied_slot_is_reused_through_the_cache),
      cmocka_unit_test(pool_requested_before_speculative),
      cmocka_unit_test(pool_stale_priority_entry_is_not_a_request),
      cmocka_unit_test(pool_full_is_reported),
      cmocka_unit_test(pool_termination_counter),
      cmocka_unit_test(pool_stall_cap_waits_for_a_busy_group),
      cmocka_unit_test(pool_terminates_with_zero_one_and_no_queries),
      cmocka_unit_test(pool_native_thread_that_cannot_start_is_reported),
      cmocka_unit_test(pool_stalled_work_group_is_a_scheduler_error),
      cmocka_unit_test(pool_full_reports_and_succeeds_when_retried_larger),
      cmocka_unit_test(pool_persists_across_launches),
      cmocka_unit_test(pool_requested_builds_less_than_full),
      cmocka_unit_test(pool_level_baseline_repeats),
      cmocka_unit_test(pool_stress),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
