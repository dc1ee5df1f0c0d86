/* On-demand traversal on the wide layout against binary on-demand traversal (issue 16, point 2),
 * with Embree 3 beside them, on Table 1's workloads (primary rays, then primary + AO rays, each
 * from the outer and the close camera):
 *
 *   bench_ondemand_wide [--runs R] [--size N] [--ao S] SCENE...
 *
 * Methods, interleaved run by run: the BVH requested and speculative, each with its built part
 * collapsed 8 wide before every launch (the default natively) and with LT_BVH_WIDE=0 (binary
 * traversal only), and Embree. Time to image is build plus trace over the batches (the
 * primary batch, then the AO batch on the same structure), as in Table 1; the collapses are
 * part of it. Every lazytrace method's last hits are checked against the first method's. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "benchmarks/median.h"
#include "benchmarks/methods.h"
#include "lazytrace.h"
#ifdef LT_HAVE_EMBREE
#include "benchmarks/embree_peer.h"
#endif

#define MAX_RUNS 16
enum { REQ_WIDE, REQ_BINARY, SPEC_WIDE, SPEC_BINARY, EMBREE, METHODS };
static const char *const names[METHODS] = {"requested wide", "requested binary", "speculative wide",
                                           "speculative binary", "Embree"};

typedef struct figures {
  double total[MAX_RUNS], trace[MAX_RUNS], wide_ms[MAX_RUNS];
  double wide_bytes, wide_nodes, memory;
  int ok;
} figures;

static int run_method(const lt_scene *scene, int m, const lt_bench_batch *batches, int nbatches, int run, figures *f,
                      lt_hit *hits) {
  if (m == EMBREE) {
#ifdef LT_HAVE_EMBREE
    double build;
    lt_embree *e = lt_embree_build_quality(scene, lt_context_work_groups(lt_bench_native_context()), LT_EMBREE_MEDIUM,
                                           &build);
    if (!e) return 1;
    double trace = 0;
    for (int b = 0; b < nbatches; b++) trace += lt_embree_trace(e, batches[b].rays, batches[b].count, batches[b].any, hits);
    lt_embree_release(e);
    f->total[run] = build + trace, f->trace[run] = trace, f->wide_ms[run] = 0, f->ok = 1;
    return 0;
#else
    return 1;
#endif
  }
  int binary = m == REQ_BINARY || m == SPEC_BINARY;
  if (binary) setenv("LT_BVH_WIDE", "0", 1);
  lt_stats *stats;
  lt_stats_create(&stats);
  int method = m == REQ_WIDE || m == REQ_BINARY ? LT_BENCH_REQUESTED : LT_BENCH_SPECULATIVE;
  lt_status status = lt_bench_build_and_trace(scene, method, batches, nbatches, hits, stats);
  unsetenv("LT_BVH_WIDE");
  if (!status) {
    f->total[run] = lt_stats_get(stats, "total_ms");
    f->trace[run] = lt_stats_get(stats, "trace_ms");
    double ms = lt_stats_get(stats, "wide.ms"), bytes = lt_stats_get(stats, "wide.bytes");
    f->wide_ms[run] = ms > 0 ? ms : 0;
    f->wide_bytes = bytes > 0 ? bytes : 0;
    double wide_nodes = lt_stats_get(stats, "wide.nodes");
    f->wide_nodes = wide_nodes > 0 ? wide_nodes : 0;
    f->memory = lt_stats_get(stats, "memory_bytes");
    f->ok = 1;
  }
  lt_stats_destroy(stats);
  return status != LT_OK;
}

/* Every method, interleaved run by run; lazytrace's closest hits checked against the first's. */
static int run_all(const lt_scene *scene, const lt_bench_batch *batches, int nbatches, int runs, figures *f) {
  size_t last = batches[nbatches - 1].count;
  lt_hit *ref = malloc((last + 1) * sizeof *ref), *hits = malloc((last + 1) * sizeof *hits);
  memset(f, 0, METHODS * sizeof *f);
  for (int run = 0; run < runs; run++)
    for (int m = 0; m < METHODS; m++) {
      if (run_method(scene, m, batches, nbatches, run, &f[m], m == REQ_WIDE ? ref : hits)) continue;
      if (m != REQ_WIDE && m != EMBREE && !batches[nbatches - 1].any)
        for (size_t i = 0; i < last; i++)
          if (hits[i].prim != ref[i].prim || (hits[i].prim >= 0 && hits[i].t != ref[i].t))
            return fprintf(stderr, "%s: hit %zu differs from %s's\n", names[m], i, names[REQ_WIDE]), 1;
      fprintf(stderr, "    %-18s run %d: %8.1f ms\n", names[m], run + 1, f[m].total[run]);
    }
  free(ref), free(hits);
  return 0;
}

static void print_row(const char *label, size_t rays, const figures *f, int runs) {
  double t[METHODS];
  for (int m = 0; m < METHODS; m++) t[m] = f[m].ok ? lt_bench_median(f[m].total, runs) : NAN;
  printf("| %s | %.2fM |", label, rays / 1e6);
  for (int m = 0; m < METHODS; m++) printf(" %.0f |", t[m]);
  printf(" %.2f | %.2f |", t[REQ_WIDE] / t[REQ_BINARY], t[SPEC_WIDE] / t[SPEC_BINARY]);
  double best_wide = t[REQ_WIDE] < t[SPEC_WIDE] ? t[REQ_WIDE] : t[SPEC_WIDE];
  double best_binary = t[REQ_BINARY] < t[SPEC_BINARY] ? t[REQ_BINARY] : t[SPEC_BINARY];
  printf(" %.2f | %.2f |", best_wide / t[EMBREE], best_binary / t[EMBREE]);
  printf(" %.0f / %.1f / %.2f | %.0f / %.1f / %.2f |\n", f[REQ_WIDE].wide_nodes, lt_bench_median(f[REQ_WIDE].wide_ms, runs),
         f[REQ_WIDE].wide_bytes / 1e6, f[SPEC_WIDE].wide_nodes, lt_bench_median(f[SPEC_WIDE].wide_ms, runs),
         f[SPEC_WIDE].wide_bytes / 1e6);
}

int main(int argc, char **argv) {
  int runs = 3, size = 1024, ao = 8;
  const char *scenes[64];
  int nscenes = 0;
  for (int i = 1; i < argc; i++) {
    if (strcmp(argv[i], "--runs") == 0 && i + 1 < argc) runs = atoi(argv[++i]);
    else if (strcmp(argv[i], "--size") == 0 && i + 1 < argc) size = atoi(argv[++i]);
    else if (strcmp(argv[i], "--ao") == 0 && i + 1 < argc) ao = atoi(argv[++i]);
    else if (argv[i][0] != '-' && nscenes < 64) scenes[nscenes++] = argv[i];
    else return fprintf(stderr, "bench_ondemand_wide: unknown option %s\n", argv[i]), 2;
  }
  if (runs < 1 || runs > MAX_RUNS || nscenes == 0)
    return fprintf(stderr, "usage: bench_ondemand_wide [--runs 1..%d] [--size N] [--ao S] SCENE...\n", MAX_RUNS), 2;
  printf("| scene@camera, workload | rays | requested wide | requested binary | speculative wide | speculative binary |"
         " Embree | req wide / binary | spec wide / binary | best wide / Embree | best binary / Embree |"
         " req: wide nodes / collapse ms / wide MB | spec: wide nodes / collapse ms / wide MB |\n");
  printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (int i = 0; i < nscenes; i++)
    for (int c = 0; c < 2; c++) {
      char spec[256];
      snprintf(spec, sizeof spec, "%s@%s", scenes[i], c ? "close" : "outer");
      lt_scene *scene;
      if (lt_scene_load(spec, &scene) != LT_OK) return fprintf(stderr, "%s\n", lt_last_error()), 1;
      fprintf(stderr, "%s (%zu triangles)\n", spec, lt_scene_triangle_count(scene));

      /* Primary rays, then AO rays from their hits (the same for every method), as Table 1. */
      size_t n = (size_t)size * size;
      lt_ray *primary = malloc(n * sizeof *primary), *ao_rays = malloc(n * ao * sizeof *ao_rays);
      lt_camera cam = lt_scene_camera(scene);
      lt_camera_primary_rays(&cam, size, size, primary);
      lt_bench_batch batches[2] = {{primary, n, 0}, {ao_rays, 0, 1}};
      figures f[METHODS];
      if (run_all(scene, batches, 1, runs, f)) return 1;
      char label[300];
      snprintf(label, sizeof label, "%s, primary", spec);
      print_row(label, n, f, runs);

      batches[1].count = lt_bench_table1_ao_rays(scene, primary, n, ao, ao_rays);
      if (run_all(scene, batches, 2, runs, f)) return 1;
      snprintf(label, sizeof label, "%s, primary + %d AO", spec, ao);
      print_row(label, n + batches[1].count, f, runs);
      fflush(stdout);
      free(primary), free(ao_rays);
      lt_scene_destroy(scene);
    }
  return 0;
}
