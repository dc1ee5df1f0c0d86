/* The irregular grid paper's experiments in shape (Perard-Gayot, Kalojanov and Slusallek 2017,
 * "GPU Ray Tracing using Irregular Grids"), on lazytrace's --structure irgrid, with the SAH BVH
 * and Embree 3 beside it on the same triangles and primary rays:
 *
 *   bench_irgrid table1    [--runs R] [--size N] SCENE...   Table 1: each construction phase
 *   bench_irgrid densities [--runs R] [--size N] SCENE...   Table 2: lambda1 x lambda2, two-level grid
 *   bench_irgrid uniform   [--runs R] [--size N] SCENE...   Table 5: merge and expansion on uniform grids
 *   bench_irgrid ondemand  [--runs R] [--size N] SCENE...   full grid against top cells built on demand
 *   bench_irgrid trace     [--runs R] [--size N] SCENE...   Table 1's full grid and SAH BVH rows alone
 *   bench_irgrid sweep     [--runs R] [--size N] [--max M] [--csv FILE]   house-row:1..M
 *
 * Rays: N x N primary rays from each scene's outer camera (SCENE@outer unless SCENE names a
 * camera). A finished structure's trace time (and Embree's) is the median of W traces (--warm,
 * default 3) after the first, whose time Table 1 shows beside it; W = 0 takes the first. Every
 * figure is the median of R runs, the variants interleaved run by run; every
 * lazytrace variant's closest hits must equal the full SAH BVH's bit for bit, or the program
 * says so and exits with status 1. Markdown goes to stdout, progress to stderr. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "benchmarks/median.h"
#include "benchmarks/methods.h"
#include "lazytrace.h"
#include "runtime/irgrid_host.h" /* lt__irgrid_top_dims: Table 5 prints the top grid's resolution */
#ifdef LT_HAVE_EMBREE
#include "benchmarks/embree_peer.h"
#endif

#define MAX_RUNS 16

/* The options every experiment shares: runs per variant, and N for N x N primary rays. */
static int runs = 3, size = 512;
/* Traces after the first whose median is a finished structure's trace time (0: the first's):
 * the first trace after a build runs on caches and pages the build left, up to 2x slower for
 * the irregular grid here, and throughput is what Table 1 compares. */
static int warm = 3;


/* ---- What one run of one variant yields ---- */

/* The figures kept per run; the first ones are lazytrace statistics by key. */
enum {
  F_BUILD,
  F_TRACE,
  F_TOTAL,
  F_STEPS,
  F_TESTS,
  F_MEMORY,
  F_NODES,
  F_TOP,
  F_TOP_BUILT,
  F_INITIAL,
  F_FINAL,
  F_STRUCTURE, /* cells (or nodes), references and voxel map in bytes: the structure without build scratch */
  F_FIRST,     /* the first trace after the build (F_TRACE is then the median of `warm` more) */
  F_COUNT
};
static const char *const stat_keys[F_STRUCTURE] = {"build_ms",        "trace_ms",      "total_ms",    "traversal_steps",
                                                   "intersections",   "memory_bytes",  "nodes_built", "cells.top",
                                                   "cells.top_built", "cells.initial", "cells.final"};

/* One thing measured: a lazytrace structure (config) or Embree, and its figures run by run
 * (-1 where a figure does not apply). */
typedef struct variant {
  char label[64];
  lt_structure_config config;
  int embree;
  int ok; /* measured (Embree: only where it is linked) */
  double v[F_COUNT][MAX_RUNS];
} variant;

/* The median of a figure over the runs. */
static double med(const variant *m, int figure) { return lt_bench_median(m->v[figure], runs); }

/* A scene with its primary rays and the full SAH BVH's closest hits (the reference). */
typedef struct workload {
  char spec[256];
  lt_scene *scene;
  lt_ray *rays;
  size_t count;
  lt_hit *reference, *hits;
} workload;

/* ---- Errors and the context ---- */

/* Prints a message and exits with status 1 (callers pass lt_last_error() where it applies). */
static void die(const char *format, ...) {
  va_list args;
  va_start(args, format);
  fprintf(stderr, "bench_irgrid: ");
  vfprintf(stderr, format, args);
  va_end(args);
  fprintf(stderr, "\n");
  exit(1);
}

/* The benchmarks' native context (benchmarks/methods.h), or the end of the run. */
static lt_context *native_context(void) {
  lt_context *ctx = lt_bench_native_context();
  if (!ctx) die("no native context: %s", lt_last_error());
  return ctx;
}

/* ---- Configurations ---- */

/* The irregular grid: merge is LT_IRGRID_MERGE_*, passes the number of expansion passes,
 * densities lambda1 and lambda2 (0: the defaults, 0.12 and 2.4). */
static lt_structure_config irgrid(lt_build_mode build, int merge, int passes, float lambda1, float lambda2) {
  lt_structure_config c = lt_structure_config_default(LT_STRUCTURE_IRGRID);
  c.build = build;
  c.irgrid_merge = merge;
  c.irgrid_expansion_passes = LT_IRGRID_PASSES(passes);
  if (lambda1 > 0) c.irgrid_top_density = lambda1;
  if (lambda2 > 0) c.irgrid_cell_density = lambda2;
  return c;
}

/* The SAH BVH built in full, the reference of every comparison. */
static lt_structure_config bvh_full(void) {
  lt_structure_config c = lt_structure_config_default(LT_STRUCTURE_BVH);
  c.build = LT_BUILD_FULL;
  return c;
}

/* Fills in a variant (label printf-style). */
static void variant_set(variant *m, lt_structure_config config, int embree, const char *format, ...) {
  memset(m, 0, sizeof *m);
  va_list args;
  va_start(args, format);
  vsnprintf(m->label, sizeof m->label, format, args);
  va_end(args);
  m->config = config, m->embree = embree;
}

/* ---- Scenes, rays and the reference hits ---- */

/* Loads SPEC (at its outer camera unless it names one), generates size x size primary rays and
 * traces them through the full SAH BVH for the reference hits. */
static void workload_load(workload *w, const char *spec) {
  memset(w, 0, sizeof *w);
  snprintf(w->spec, sizeof w->spec, strchr(spec, '@') ? "%s" : "%s@outer", spec);
  if (lt_scene_load(w->spec, &w->scene) != LT_OK) die("%s: %s", w->spec, lt_last_error());
  w->count = (size_t)size * size;
  w->rays = malloc(w->count * sizeof *w->rays);
  w->reference = malloc(w->count * sizeof *w->reference);
  w->hits = malloc(w->count * sizeof *w->hits);
  if (!w->rays || !w->reference || !w->hits) die("out of memory for %zu rays", w->count);
  lt_camera camera = lt_scene_camera(w->scene);
  lt_camera_primary_rays(&camera, size, size, w->rays);
  lt_structure_config config = bvh_full();
  lt_structure *bvh;
  if (lt_structure_create(native_context(), w->scene, &config, NULL, &bvh) != LT_OK ||
      lt_structure_trace(bvh, w->rays, w->count, LT_QUERY_CLOSEST, w->reference, NULL) != LT_OK)
    die("%s: the reference BVH: %s", w->spec, lt_last_error());
  lt_structure_destroy(bvh);
  fprintf(stderr, "%s: %zu triangles, %zu rays\n", w->spec, lt_scene_triangle_count(w->scene), w->count);
}

static void workload_free(workload *w) {
  free(w->rays), free(w->reference), free(w->hits);
  lt_scene_destroy(w->scene);
}

/* Exits loudly unless every hit equals the reference's bit for bit. */
static void check_hits(const workload *w, const variant *m) {
  for (size_t i = 0; i < w->count; i++) {
    if (memcmp(&w->hits[i], &w->reference[i], sizeof(lt_hit)) == 0) continue;
    const lt_hit *a = &w->hits[i], *b = &w->reference[i];
    fprintf(stderr,
            "\n*** HIT MISMATCH *** %s, %s: ray %zu hits triangle %d at t %.9g (u %.9g, v %.9g); the full SAH BVH "
            "hits triangle %d at t %.9g (u %.9g, v %.9g)\n\n",
            w->spec, m->label, i, (int)a->prim, (double)a->t, (double)a->u, (double)a->v, (int)b->prim, (double)b->t,
            (double)b->u, (double)b->v);
    exit(1);
  }
}

/* ---- Measuring ---- */

/* Embree's default static build (robust flag) and trace with as many threads as lazytrace's
 * work-groups; steps, tests, memory and cells do not apply. Returns 0 where Embree is not linked. */
static int run_embree(const workload *w, variant *m, int run) {
#ifdef LT_HAVE_EMBREE
  double build;
  lt_embree *e = lt_embree_build(w->scene, lt_context_work_groups(native_context()), &build);
  if (!e) die("%s: Embree failed to build", w->spec);
  double first = lt_embree_trace(e, w->rays, w->count, 0, w->hits), more[MAX_RUNS];
  for (int k = 0; k < warm; k++) more[k] = lt_embree_trace(e, w->rays, w->count, 0, w->hits);
  lt_embree_release(e);
  for (int f = 0; f < F_COUNT; f++) m->v[f][run] = -1;
  double trace = warm > 0 ? lt_bench_median(more, warm) : first;
  m->v[F_BUILD][run] = build, m->v[F_TRACE][run] = trace, m->v[F_TOTAL][run] = build + first;
  m->v[F_FIRST][run] = first;
  return 1;
#else
  (void)w, (void)m, (void)run;
  return 0;
#endif
}

/* One run of one lazytrace variant: create (built in full, or prepared for on-demand builds),
 * trace the primary rays once (with stats: on demand, a second trace gives trace_ms), check
 * the hits, keep the figures. */
static void run_lazytrace(const workload *w, variant *m, int run) {
  lt_stats *stats;
  lt_structure *s = NULL;
  if (lt_stats_create(&stats) != LT_OK) die("stats: %s", lt_last_error());
  if (lt_structure_create(native_context(), w->scene, &m->config, stats, &s) != LT_OK)
    die("%s, %s: create: %s", w->spec, m->label, lt_last_error());
  if (lt_structure_trace(s, w->rays, w->count, LT_QUERY_CLOSEST, w->hits, stats) != LT_OK)
    die("%s, %s: trace: %s", w->spec, m->label, lt_last_error());
  check_hits(w, m);
  for (int f = 0; f < F_STRUCTURE; f++) m->v[f][run] = lt_stats_get(stats, stat_keys[f]);
  m->v[F_FIRST][run] = m->v[F_TRACE][run];
  if (m->config.build == LT_BUILD_FULL && warm > 0) {
    double more[MAX_RUNS];
    for (int k = 0; k < warm; k++) {
      lt_stats *again;
      if (lt_stats_create(&again) != LT_OK ||
          lt_structure_trace(s, w->rays, w->count, LT_QUERY_CLOSEST, w->hits, again) != LT_OK)
        die("%s, %s: trace again: %s", w->spec, m->label, lt_last_error());
      check_hits(w, m);
      more[k] = lt_stats_get(again, "trace_ms");
      lt_stats_destroy(again);
    }
    m->v[F_TRACE][run] = lt_bench_median(more, warm);
  }
  double map = lt_stats_get(stats, "map_bytes");
  m->v[F_STRUCTURE][run] =
      lt_stats_get(stats, "node_bytes") + lt_stats_get(stats, "reference_bytes") + (map > 0 ? map : 0);
  lt_structure_destroy(s);
  lt_stats_destroy(stats);
}

/* All variants over one workload, `runs` times, interleaved run by run; a line per measurement
 * on stderr. */
static void run_all(const workload *w, variant *variants, int count) {
  for (int run = 0; run < runs; run++)
    for (int i = 0; i < count; i++) {
      variant *m = &variants[i];
      if (m->embree)
        m->ok = run_embree(w, m, run);
      else
        run_lazytrace(w, m, run), m->ok = 1;
      if (m->ok)
        fprintf(stderr, "  %-34s run %d: build %9.1f ms, trace %9.1f ms, total %9.1f ms\n", m->label, run + 1,
                m->v[F_BUILD][run], m->v[F_TRACE][run], m->v[F_TOTAL][run]);
    }
}

/* ---- Formatting ---- */

/* x with `decimals` decimals, or "n/a" where it does not apply (negative); the text lives in
 * one of a ring of buffers, so a printf may take several. */
static const char *num(double x, int decimals) {
  static char ring[32][32];
  static int next;
  char *s = ring[next++ % 32];
  if (x < 0 || isnan(x)) return "n/a";
  snprintf(s, 32, "%.*f", decimals, x);
  return s;
}

/* a / b, or n/a where either does not apply. */
static const char *ratio(double a, double b, int decimals) { return a < 0 || b <= 0 ? "n/a" : num(a / b, decimals); }

/* Per-ray figures, megabytes and Mrays/s of a variant's medians. */
static double per_ray(const variant *m, int figure, const workload *w) {
  double x = med(m, figure);
  return x < 0 ? -1 : x / (double)w->count;
}
static double megabytes(const variant *m, int figure) {
  double x = med(m, figure);
  return x < 0 ? -1 : x / 1048576.0;
}
static double mrays(const variant *m, const workload *w) { return (double)w->count / 1e3 / med(m, F_TRACE); }

/* ---- Table 1: the construction phases against the SAH BVH and Embree ---- */

static void table1(int argc, char **argv) {
  printf(
      "| scene (triangles) | structure | steps/ray | tests/ray | build ms | first trace ms | trace ms | Mrays/s |"
      " memory MB | structure MB | trace / BVH | memory / BVH | structure / BVH |\n"
      "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (int i = 0; i < argc; i++) {
    workload w;
    workload_load(&w, argv[i]);
    enum { TWO_LEVEL, MERGE, MERGE_EXPAND, MERGE_TOP, BVH, EMBREE, COUNT };
    variant v[COUNT];
    variant_set(&v[TWO_LEVEL], irgrid(LT_BUILD_FULL, LT_IRGRID_MERGE_OFF, 0, 0, 0), 0, "two-level grid");
    variant_set(&v[MERGE], irgrid(LT_BUILD_FULL, LT_IRGRID_MERGE_ON, 0, 0, 0), 0, "+ merge");
    variant_set(&v[MERGE_EXPAND], irgrid(LT_BUILD_FULL, LT_IRGRID_MERGE_ON, 3, 0, 0), 0, "+ merge + expansion");
    variant_set(&v[MERGE_TOP], irgrid(LT_BUILD_FULL, LT_IRGRID_MERGE_TOP, 3, 0, 0), 0,
                "merge within top cells + expansion");
    variant_set(&v[BVH], bvh_full(), 0, "SAH BVH (full)");
    variant_set(&v[EMBREE], bvh_full(), 1, "Embree");
    run_all(&w, v, COUNT);
    double bvh_trace = med(&v[BVH], F_TRACE), bvh_memory = med(&v[BVH], F_MEMORY);
    double bvh_structure = med(&v[BVH], F_STRUCTURE);
    for (int k = 0; k < COUNT; k++) {
      const variant *m = &v[k];
      if (!m->ok) {
        printf("| %s (%zu) | %s | not linked | | | | | | | | | | |\n", argv[i], lt_scene_triangle_count(w.scene),
               m->label);
        continue;
      }
      printf("| %s (%zu) | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", argv[i],
             lt_scene_triangle_count(w.scene), m->label, num(per_ray(m, F_STEPS, &w), 1),
             num(per_ray(m, F_TESTS, &w), 1), num(med(m, F_BUILD), 1), num(med(m, F_FIRST), 1),
             num(med(m, F_TRACE), 1), num(mrays(m, &w), 2),
             num(megabytes(m, F_MEMORY), 2), num(megabytes(m, F_STRUCTURE), 2), ratio(med(m, F_TRACE), bvh_trace, 2),
             ratio(med(m, F_MEMORY), bvh_memory, 2), ratio(med(m, F_STRUCTURE), bvh_structure, 2));
    }
    workload_free(&w);
  }
}

/* ---- The trace target: the full irregular grid against the SAH BVH, nothing else ---- */

/* Table 1's "+ merge + expansion" and SAH BVH rows alone (and Embree), so that their trace times
 * can be measured with more runs in the time Table 1's slow two-level builds take. */
static void trace_target(int argc, char **argv) {
  printf(
      "| scene (triangles) | irregular grid trace ms | SAH BVH trace ms | Embree trace ms | grid / BVH (median) |"
      " grid / BVH, run by run | grid memory / BVH |\n"
      "|---|---:|---:|---:|---:|---|---:|\n");
  for (int i = 0; i < argc; i++) {
    workload w;
    workload_load(&w, argv[i]);
    enum { GRID, BVH, EMBREE, COUNT };
    variant v[COUNT];
    variant_set(&v[GRID], irgrid(LT_BUILD_FULL, LT_IRGRID_MERGE_ON, 3, 0, 0), 0, "irregular grid");
    variant_set(&v[BVH], bvh_full(), 0, "SAH BVH (full)");
    variant_set(&v[EMBREE], bvh_full(), 1, "Embree");
    run_all(&w, v, COUNT);
    /* The ratio of each run's two times (measured side by side), and their median: on a noisy
     * machine the medians of the two columns can come from runs of different speeds. */
    char each[256] = "";
    double ratios[MAX_RUNS];
    for (int run = 0; run < runs; run++) {
      size_t used = strlen(each);
      ratios[run] = v[GRID].v[F_TRACE][run] / v[BVH].v[F_TRACE][run];
      snprintf(each + used, sizeof each - used, "%s%.2f", run ? ", " : "", ratios[run]);
    }
    printf("| %s (%zu) | %s | %s | %s | %s | %s | %s |\n", argv[i], lt_scene_triangle_count(w.scene),
           num(med(&v[GRID], F_TRACE), 1), num(med(&v[BVH], F_TRACE), 1), v[EMBREE].ok ? num(med(&v[EMBREE], F_TRACE), 1) : "n/a",
           num(lt_bench_median(ratios, runs), 2), each,
           ratio(med(&v[GRID], F_MEMORY), med(&v[BVH], F_MEMORY), 2));
    workload_free(&w);
  }
}

/* ---- Table 2: the densities ---- */

static const float lambda1s[3] = {0.012f, 0.04f, 0.12f}, lambda2s[3] = {0.24f, 0.8f, 2.4f};

/* The [min, max] of a figure's medians over variants first, first + step, ... (count of them). */
static void range_of(const variant *v, int first, int count, int step, int figure, double scale, double *lo,
                     double *hi) {
  *lo = INFINITY, *hi = -INFINITY;
  for (int k = 0; k < count; k++) {
    double x = med(&v[first + k * step], figure) * scale;
    *lo = fmin(*lo, x), *hi = fmax(*hi, x);
  }
}

static void densities(int argc, char **argv) {
  printf(
      "| scene | lambda1 | lambda2 | irregular: build ms | memory MB | cells | steps/ray | tests/ray | trace ms |"
      " two-level: build ms | memory MB | cells | steps/ray | tests/ray | trace ms |\n"
      "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  char summary[64][512]; /* the summary table's rows, printed after the last scene */
  int rows = 0;
  for (int i = 0; i < argc; i++) {
    workload w;
    workload_load(&w, argv[i]);
    /* Variants 2p (irregular) and 2p + 1 (two-level) for pair p = 3 * a + b; the BVH last. */
    variant v[19];
    for (int a = 0; a < 3; a++)
      for (int b = 0; b < 3; b++) {
        int p = 3 * a + b;
        variant_set(&v[2 * p], irgrid(LT_BUILD_FULL, LT_IRGRID_MERGE_ON, 3, lambda1s[a], lambda2s[b]), 0,
                    "irregular %g : %g", (double)lambda1s[a], (double)lambda2s[b]);
        variant_set(&v[2 * p + 1], irgrid(LT_BUILD_FULL, LT_IRGRID_MERGE_OFF, 0, lambda1s[a], lambda2s[b]), 0,
                    "two-level %g : %g", (double)lambda1s[a], (double)lambda2s[b]);
      }
    variant_set(&v[18], bvh_full(), 0, "SAH BVH (full)");
    run_all(&w, v, 19);
    int best = 1; /* the two-level grid with the fastest trace, as the paper picks it */
    for (int p = 0; p < 9; p++) {
      const variant *g = &v[2 * p], *t = &v[2 * p + 1];
      printf("| %s | %g | %g | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", argv[i],
             (double)lambda1s[p / 3], (double)lambda2s[p % 3], num(med(g, F_BUILD), 1), num(megabytes(g, F_MEMORY), 2),
             num(med(g, F_FINAL), 0), num(per_ray(g, F_STEPS, &w), 1), num(per_ray(g, F_TESTS, &w), 1),
             num(med(g, F_TRACE), 1), num(med(t, F_BUILD), 1), num(megabytes(t, F_MEMORY), 2), num(med(t, F_FINAL), 0),
             num(per_ray(t, F_STEPS, &w), 1), num(per_ray(t, F_TESTS, &w), 1), num(med(t, F_TRACE), 1));
      if (med(t, F_TRACE) < med(&v[best], F_TRACE)) best = 2 * p + 1;
    }
    double build_lo, build_hi, trace_lo, trace_hi, mem_lo, mem_hi;
    range_of(v, 0, 9, 2, F_BUILD, 1, &build_lo, &build_hi);
    range_of(v, 0, 9, 2, F_TRACE, 1, &trace_lo, &trace_hi);
    range_of(v, 0, 9, 2, F_MEMORY, 1.0 / 1048576, &mem_lo, &mem_hi);
    double rate = (double)w.count / 1e3;
    int pair = best / 2;
    if (rows < 64)
      snprintf(summary[rows++], sizeof summary[0],
               "| %s | %zu | [%.1f, %.1f] | %.1f | %.1f | [%.2f, %.2f] | %.2f | %.2f | [%.2f, %.2f] | %.2f | %.2f |"
               " %g : %g |",
               argv[i], lt_scene_triangle_count(w.scene), build_lo, build_hi, med(&v[best], F_BUILD),
               med(&v[18], F_BUILD), rate / trace_hi, rate / trace_lo, mrays(&v[best], &w), mrays(&v[18], &w), mem_lo,
               mem_hi, megabytes(&v[best], F_MEMORY), megabytes(&v[18], F_MEMORY), (double)lambda1s[pair / 3],
               (double)lambda2s[pair % 3]);
    workload_free(&w);
  }
  printf(
      "\nOver the nine density pairs (the paper's Table 2): the irregular grid's range, the two-level grid at its"
      " fastest pair, the full SAH BVH.\n\n"
      "| scene | triangles | irregular build ms | two-level build ms | BVH build ms | irregular Mrays/s |"
      " two-level Mrays/s | BVH Mrays/s | irregular memory MB | two-level memory MB | BVH memory MB |"
      " two-level pair |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (int r = 0; r < rows; r++) printf("%s\n", summary[r]);
}

/* ---- Table 5: merge and expansion on uniform grids ---- */

/* The uniform grid at top density lambda1: the irregular grid whose top cells are never cut.
 * A top cell of m references is cut once lambda2 * m > 1 (lt_irg_level, builders/irgrid_task.h),
 * so 0.001, the command line's least, still cuts top cells of over 1000 references (house has
 * some at lambda1 0.12); 1e-6 cuts none below a million. */
#define UNIFORM_CELL_DENSITY 1e-6f

/* "AxBxC" for the top grid the library makes for this scene at lambda1, or "N top cells" where
 * that resolution does not account for the top cells the build reported. */
static void top_resolution(const lt_scene *scene, float lambda1, double top_cells, char *out, size_t capacity) {
  float lo[3], hi[3];
  lt_scene_bounds(scene, lo, hi);
  double extent[3] = {(double)hi[0] - lo[0], (double)hi[1] - lo[1], (double)hi[2] - lo[2]};
  int dims[3];
  lt__irgrid_top_dims(extent, lt_scene_triangle_count(scene), lambda1, dims);
  if ((double)dims[0] * dims[1] * dims[2] == top_cells)
    snprintf(out, capacity, "%dx%dx%d", dims[0], dims[1], dims[2]);
  else
    snprintf(out, capacity, "%.0f top cells", top_cells);
}

static void uniform(int argc, char **argv) {
  static const float lambdas[2] = {0.12f, 1.0f};
  static const struct {
    const char *label;
    int merge, passes;
  } kinds[4] = {{"uniform", LT_IRGRID_MERGE_OFF, 0},
                {"+ expansion", LT_IRGRID_MERGE_OFF, 3},
                {"+ merge", LT_IRGRID_MERGE_ON, 0},
                {"+ merge + expansion", LT_IRGRID_MERGE_ON, 3}};
  printf(
      "| scene | lambda1 (top grid) | variant | steps/ray | tests/ray | trace ms | Mrays/s | trace / uniform |"
      " memory MB | structure MB | cells |\n|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (int i = 0; i < argc; i++) {
    workload w;
    workload_load(&w, argv[i]);
    variant v[8];
    for (int l = 0; l < 2; l++)
      for (int k = 0; k < 4; k++)
        variant_set(&v[4 * l + k],
                    irgrid(LT_BUILD_FULL, kinds[k].merge, kinds[k].passes, lambdas[l], UNIFORM_CELL_DENSITY), 0,
                    "%g: %s", (double)lambdas[l], kinds[k].label);
    run_all(&w, v, 8);
    for (int l = 0; l < 2; l++) {
      const variant *u = &v[4 * l];
      char dims[64];
      top_resolution(w.scene, lambdas[l], med(u, F_TOP), dims, sizeof dims);
      if (med(u, F_INITIAL) > med(u, F_TOP))
        fprintf(stderr, "note: %s at lambda1 %g: %.0f initial cells for %.0f top cells, so some top cell was cut\n",
                w.spec, (double)lambdas[l], med(u, F_INITIAL), med(u, F_TOP));
      for (int k = 0; k < 4; k++) {
        const variant *m = &v[4 * l + k];
        printf("| %s | %g (%s) | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", argv[i], (double)lambdas[l], dims,
               kinds[k].label, num(per_ray(m, F_STEPS, &w), 1), num(per_ray(m, F_TESTS, &w), 1),
               num(med(m, F_TRACE), 1), num(mrays(m, &w), 2), ratio(med(m, F_TRACE), med(u, F_TRACE), 2),
               num(megabytes(m, F_MEMORY), 2), num(megabytes(m, F_STRUCTURE), 2), num(med(m, F_FINAL), 0));
      }
    }
    workload_free(&w);
  }
}

/* ---- Top cells on demand ---- */

/* The default irregular grid built in full, on request and speculatively. */
enum { OD_FULL, OD_REQUESTED, OD_SPECULATIVE, OD_COUNT };
static void ondemand_variants(variant *v) {
  variant_set(&v[OD_FULL], irgrid(LT_BUILD_FULL, LT_IRGRID_MERGE_ON, 3, 0, 0), 0, "full");
  variant_set(&v[OD_REQUESTED], irgrid(LT_BUILD_REQUESTED, LT_IRGRID_MERGE_ON, 3, 0, 0), 0, "requested");
  variant_set(&v[OD_SPECULATIVE], irgrid(LT_BUILD_SPECULATIVE, LT_IRGRID_MERGE_ON, 3, 0, 0), 0, "speculative");
}

static void ondemand(int argc, char **argv) {
  printf(
      "| scene (triangles) | build | time to image ms | build ms | trace ms | top cells built | cells |"
      " steps/ray | image / full |\n|---|---|---:|---:|---:|---:|---:|---:|---:|\n");
  for (int i = 0; i < argc; i++) {
    workload w;
    workload_load(&w, argv[i]);
    variant v[OD_COUNT];
    ondemand_variants(v);
    run_all(&w, v, OD_COUNT);
    double full = med(&v[OD_FULL], F_TOTAL);
    for (int k = 0; k < OD_COUNT; k++) {
      const variant *m = &v[k];
      printf("| %s (%zu) | %s | %s | %s | %s | %s of %s | %s | %s | %s |\n", argv[i], lt_scene_triangle_count(w.scene),
             m->label, num(med(m, F_TOTAL), 1), num(med(m, F_BUILD), 1), num(med(m, F_TRACE), 1),
             num(med(m, F_TOP_BUILT), 0), num(med(m, F_TOP), 0), num(med(m, F_NODES), 0),
             num(per_ray(m, F_STEPS, &w), 1), ratio(med(m, F_TOTAL), full, 2));
    }
    workload_free(&w);
  }
}

static void sweep(int max, FILE *csv) {
  printf(
      "| houses | triangles | full: cells | image ms | requested: top cells | cells | image ms |"
      " speculative: top cells | cells | image ms | requested / full | speculative / full |\n"
      "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  if (csv)
    fprintf(csv,
            "houses,triangles,full_cells,full_ms,requested_top_built,requested_cells,requested_ms,"
            "speculative_top_built,speculative_cells,speculative_ms,top_cells\n");
  for (int houses = 1; houses <= max; houses++) {
    char spec[64];
    snprintf(spec, sizeof spec, "house-row:%d", houses);
    workload w;
    workload_load(&w, spec);
    variant v[OD_COUNT];
    ondemand_variants(v);
    run_all(&w, v, OD_COUNT);
    double ms[OD_COUNT], cells[OD_COUNT], top[OD_COUNT];
    for (int k = 0; k < OD_COUNT; k++)
      ms[k] = med(&v[k], F_TOTAL), cells[k] = med(&v[k], F_NODES), top[k] = med(&v[k], F_TOP_BUILT);
    double top_cells = med(&v[OD_FULL], F_TOP);
    printf("| %d | %zu | %.0f | %.1f | %.0f of %.0f | %.0f | %.1f | %.0f of %.0f | %.0f | %.1f | %.2f | %.2f |\n",
           houses, lt_scene_triangle_count(w.scene), cells[OD_FULL], ms[OD_FULL], top[OD_REQUESTED], top_cells,
           cells[OD_REQUESTED], ms[OD_REQUESTED], top[OD_SPECULATIVE], top_cells, cells[OD_SPECULATIVE],
           ms[OD_SPECULATIVE], ms[OD_REQUESTED] / ms[OD_FULL], ms[OD_SPECULATIVE] / ms[OD_FULL]);
    if (csv)
      fprintf(csv, "%d,%zu,%.0f,%.2f,%.0f,%.0f,%.2f,%.0f,%.0f,%.2f,%.0f\n", houses, lt_scene_triangle_count(w.scene),
              cells[OD_FULL], ms[OD_FULL], top[OD_REQUESTED], cells[OD_REQUESTED], ms[OD_REQUESTED],
              top[OD_SPECULATIVE], cells[OD_SPECULATIVE], ms[OD_SPECULATIVE], top_cells);
    workload_free(&w);
  }
}

/* ---- Command line ---- */

static int usage(void) {
  fprintf(stderr,
          "usage: bench_irgrid table1|densities|uniform|ondemand|trace [--runs R] [--size N] [--warm W] SCENE...\n"
          "       bench_irgrid sweep [--runs R] [--size N] [--max M] [--csv FILE]\n"
          "(R in 1..%d, default 3; N default 512; W in 0..%d, default 3: a finished structure's trace\n"
          " time is the median of W traces after the first; M default 16)\n",
          MAX_RUNS, MAX_RUNS);
  return 2;
}

int main(int argc, char **argv) {
  setvbuf(stdout, NULL, _IOLBF, 0); /* rows as they are measured: a long run stopped keeps them */
  if (argc < 2) return usage();
  int max = 16, nscenes = 0;
  const char *csv_path = NULL;
  char *scenes[64];
  for (int i = 2; i < argc; i++) {
    if (strcmp(argv[i], "--runs") == 0 && i + 1 < argc)
      runs = atoi(argv[++i]);
    else if (strcmp(argv[i], "--size") == 0 && i + 1 < argc)
      size = atoi(argv[++i]);
    else if (strcmp(argv[i], "--warm") == 0 && i + 1 < argc)
      warm = atoi(argv[++i]);
    else if (strcmp(argv[i], "--max") == 0 && i + 1 < argc)
      max = atoi(argv[++i]);
    else if (strcmp(argv[i], "--csv") == 0 && i + 1 < argc)
      csv_path = argv[++i];
    else if (argv[i][0] != '-' && nscenes < 64)
      scenes[nscenes++] = argv[i];
    else
      return fprintf(stderr, "bench_irgrid: unknown option %s\n", argv[i]), usage();
  }
  if (runs < 1 || runs > MAX_RUNS || size < 1 || size > 8192 || max < 1 || warm < 0 || warm > MAX_RUNS)
    return usage();
  /* The experiments taking scenes, then the sweep (which makes its own). */
  static const char *const names[] = {"table1", "densities", "uniform", "ondemand", "trace", "sweep"};
  static void (*const experiments[])(int, char **) = {table1, densities, uniform, ondemand, trace_target};
  int e = 0;
  while (e < 6 && strcmp(argv[1], names[e]) != 0) e++;
  if (e == 6) return fprintf(stderr, "bench_irgrid: unknown experiment %s\n", argv[1]), usage();
  if (e < 5 && nscenes == 0) return fprintf(stderr, "bench_irgrid: %s needs at least one scene\n", argv[1]), usage();
  FILE *csv = NULL;
  if (csv_path && !(csv = fopen(csv_path, "w"))) return fprintf(stderr, "bench_irgrid: cannot write %s\n", csv_path), 1;
  fprintf(stderr, "bench_irgrid %s: %d run(s), %dx%d primary rays, %s\n", names[e], runs, size, size,
          lt_context_device_name(native_context()));
  if (e < 5)
    experiments[e](nscenes, scenes);
  else
    sweep(max, csv);
  if (csv && fclose(csv) != 0) return fprintf(stderr, "bench_irgrid: cannot write %s\n", csv_path), 1;
  return 0;
}
