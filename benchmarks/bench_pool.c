/* The task pool measured on its own workload, the lazy sort, on both backends:
 *   - a full sort through the persistent kernel: tasks per second and work-group time per task;
 *   - the same tasks with one launch per tree level, the host unlocking each level (baseline);
 *   - requested mode: 1000 queries, building only what they need;
 *   - the C library's qsort of the same keys on one thread, for scale.
 * Prints a markdown table of medians.
 *
 *   bench_pool [--keys N] [--runs R]      (defaults: 2,000,000 keys, 5 runs)
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lazytrace.h"
#include "benchmarks/median.h"

#define MAX_RUNS 32

static int compare_u32(const void *a, const void *b) {
  uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
  return (x > y) - (x < y);
}
typedef struct result {
  double ms[MAX_RUNS], tasks, chunks, levels;
} result;

/* mode: 0 full through the pool, 1 level baseline, 2 requested with queries. */
static int measure(lt_context *ctx, const uint32_t *keys, const uint32_t *sorted, size_t n, int mode, int run,
                   result *r) {
  lt_lazy_sort *sort;
  lt_stats *stats;
  int32_t positions[1000];
  uint32_t answers[1000], *out = malloc(n * 4);
  uint64_t state = 99;
  for (int i = 0; i < 1000; i++) positions[i] = (int32_t)((state = state * 6364136223846793005ull + 1) >> 33) % (int32_t)n;
  lt_stats_create(&stats);
  lt_status status = lt_lazy_sort_create(ctx, keys, n, mode == 2 ? LT_BUILD_REQUESTED : LT_BUILD_FULL, NULL, &sort);
  int levels = 0;
  if (!status)
    status = mode == 1 ? lt_lazy_sort_by_levels(sort, stats, &levels)
                       : lt_lazy_sort_query(sort, positions, mode == 2 ? 1000 : 0, answers, stats);

  /* Every figure is of a checked result. */
  if (!status && mode != 2) status = lt_lazy_sort_keys(sort, out);
  if (!status && mode != 2 && memcmp(out, sorted, n * 4) != 0) return fprintf(stderr, "WRONG SORT\n"), 1;
  for (int i = 0; !status && mode == 2 && i < 1000; i++)
    if (answers[i] != sorted[positions[i]]) return fprintf(stderr, "WRONG ANSWER\n"), 1;
  if (status) return fprintf(stderr, "%s\n", lt_last_error()), 1;
  r->ms[run] = lt_stats_get(stats, "total_ms");
  r->tasks = lt_stats_get(stats, "pool.tasks");
  r->chunks = lt_stats_get(stats, "pool.chunks");
  r->levels = levels;
  lt_lazy_sort_destroy(sort);
  lt_stats_destroy(stats);
  free(out);
  return 0;
}

int main(int argc, char **argv) {
  size_t n = 2000000;
  int runs = 5;
  for (int i = 1; i < argc; i++) {
    if (strcmp(argv[i], "--keys") == 0 && i + 1 < argc) n = strtoul(argv[++i], NULL, 10);
    else if (strcmp(argv[i], "--runs") == 0 && i + 1 < argc) runs = atoi(argv[++i]);
    else return fprintf(stderr, "usage: bench_pool [--keys N] [--runs R]\n"), 2;
  }
  if (runs < 1 || runs > MAX_RUNS || n < 100) return fprintf(stderr, "bench_pool: bad --keys or --runs\n"), 2;

  uint32_t *keys = malloc(n * 4), *sorted = malloc(n * 4), *copy = malloc(n * 4);
  uint64_t state = 12345;
  for (size_t i = 0; i < n; i++) keys[i] = (uint32_t)((state = state * 6364136223846793005ull + 1442695040888963407ull) >> 32);
  memcpy(sorted, keys, n * 4);
  qsort(sorted, n, 4, compare_u32);
  double qsort_ms[MAX_RUNS];
  for (int r = 0; r < runs; r++) {
    memcpy(copy, keys, n * 4);
    double start = lt_now_ms();
    qsort(copy, n, 4, compare_u32);
    qsort_ms[r] = lt_now_ms() - start;
  }

  printf("%zu random 32-bit keys, %d runs, medians. Work-group time per task = wall time x work-groups / tasks.\n\n", n, runs);
  printf("| backend | method | ms | tasks | chunks | launches | tasks/s | work-group us/task | vs level baseline |\n");
  printf("|---|---|---:|---:|---:|---:|---:|---:|---:|\n");
  const char *names[] = {"persistent pool, full sort", "one launch per level (baseline)", "requested, 1000 queries"};
  for (int b = 0; b < 2; b++) {
    lt_context *ctx;
    lt_context_config config = {b == 0 ? LT_DEVICE_OPENCL : LT_DEVICE_NATIVE, 0, 0, 0, 1};
    if (lt_context_create(&config, &ctx) != LT_OK) continue;
    int groups = lt_context_work_groups(ctx);
    result r[3];
    /* Methods interleaved run by run, so that the machine's drift hits them alike. */
    for (int run = 0; run < runs; run++)
      for (int mode = 0; mode < 3; mode++) {
        if (measure(ctx, keys, sorted, n, mode, run, &r[mode])) return 1;
        fprintf(stderr, "  %s, %s, run %d: %.1f ms\n", lt_context_device_name(ctx), names[mode], run + 1, r[mode].ms[run]);
      }
    double level_ms = lt_bench_median(r[1].ms, runs);
    for (int mode = 0; mode < 3; mode++) {
      double ms = lt_bench_median(r[mode].ms, runs), tasks = r[mode].tasks > 0 ? r[mode].tasks : 1;
      printf("| %s, %d work-groups | %s | %.1f | %.0f | %.0f | %.0f | %.0f | %.2f | %.2fx |\n",
             b == 0 ? "OpenCL (PoCL)" : "native", groups, names[mode], ms, r[mode].tasks, r[mode].chunks,
             mode == 1 ? r[mode].levels : 1.0, tasks / ms * 1e3, ms * 1e3 * groups / tasks, ms / level_ms);
    }
    lt_context_destroy(ctx);
  }
  printf("| host | C library qsort, 1 thread | %.1f | - | - | - | - | - | %s |\n", lt_bench_median(qsort_ms, runs), "-");
  free(keys), free(sorted), free(copy);
  return 0;
}
