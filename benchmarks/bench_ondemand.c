/* The on-demand paper's experiments in shape (Vinkler et al. 2016, section 5), with Embree 3
 * side by side on the same triangles and rays:
 *
 *   bench_ondemand table  [--runs R] [--size N] [--ao S] SCENE...   Table 1: time to image
 *   bench_ondemand sweep  [--runs R] [--size N] [--max M]           Figure 5: house-row:1..M
 *   bench_ondemand collide [--runs R] [--peers] SCENE...            Table 4: collision rays
 *   bench_ondemand steps  [--size N] SCENE...                       Table 3: steps per ray
 *
 * Methods: the SAH BVH built in full, requested and speculative modes, the LBVH, Embree; with
 * --kd, table and sweep measure the kd-tree in the three modes instead (the paper's Table 2
 * and Figure 5 for kd-trees), beside the full and speculative BVH and Embree; collide always
 * measures both, the BVH with its Morton top (--top morton) too, and Embree's low-quality build
 * beside its default; collide --peers only the on-demand BVH (both tops), the LBVH and Embree low
 * (no full builds, whose hits the others are otherwise checked against; the tests check them).
 * Every figure is the median of R runs (methods interleaved run by run); the lazytrace hits
 * are checked against the full build's. Markdown goes to stdout, CSV to --csv FILE. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lazytrace.h"
#ifdef LT_HAVE_EMBREE
#include "benchmarks/embree_peer.h"
#include "benchmarks/median.h"
#include "benchmarks/methods.h"
#endif

#define MAX_RUNS 16
#define METHODS LT_BENCH_METHODS
enum { FULL = LT_BENCH_FULL, REQUESTED = LT_BENCH_REQUESTED, SPECULATIVE = LT_BENCH_SPECULATIVE, LBVH = LT_BENCH_LBVH,
       KD_FULL = LT_BENCH_KD_FULL, KD_REQUESTED = LT_BENCH_KD_REQUESTED, KD_SPECULATIVE = LT_BENCH_KD_SPECULATIVE,
       EMBREE = LT_BENCH_EMBREE, EMBREE_LOW = LT_BENCH_EMBREE_LOW, QBVH = LT_BENCH_QBVH,
       REQUESTED_MORTON = LT_BENCH_REQUESTED_MORTON, SPECULATIVE_MORTON = LT_BENCH_SPECULATIVE_MORTON };

/* Which methods an experiment runs (bits 1 << method). */
#define BVH_METHODS (1u << FULL | 1u << REQUESTED | 1u << SPECULATIVE | 1u << LBVH | 1u << EMBREE)
/* Table 1 also has the QBVH: the fastest layout for a full build. */
#define TABLE1_METHODS (BVH_METHODS | 1u << QBVH)
#define KD_METHODS (1u << KD_FULL | 1u << KD_REQUESTED | 1u << KD_SPECULATIVE | 1u << FULL | 1u << SPECULATIVE | 1u << EMBREE)
/* Collision frames rebuild every time: Embree's low-quality (Morton) build is the peer there. */
#define COLLIDE_METHODS (BVH_METHODS | KD_METHODS | 1u << EMBREE_LOW | MORTON_METHODS)
#define MORTON_METHODS (1u << REQUESTED_MORTON | 1u << SPECULATIVE_MORTON)
/* collide --peers: only what a frame that rebuilds is compared with (no full builds, no kd-tree). */
#define PEER_METHODS (1u << REQUESTED | 1u << SPECULATIVE | MORTON_METHODS | 1u << LBVH | 1u << EMBREE_LOW)
static unsigned methods_run = BVH_METHODS;

typedef struct figures {
  double total[MAX_RUNS], build[MAX_RUNS], trace[MAX_RUNS];
  double nodes, nodes_full, sort_ops;
  int ok;
} figures;

/* One run of one method over the batches; hits of the last batch land in `hits`. */
static int run_method(const lt_scene *scene, int method, const lt_bench_batch *batches, int nbatches, int run,
                      figures *f, lt_hit *hits) {
  if (method == EMBREE || method == EMBREE_LOW) {
#ifdef LT_HAVE_EMBREE
    double build;
    lt_embree *e = lt_embree_build_quality(scene, lt_context_work_groups(lt_bench_native_context()),
                                           method == EMBREE_LOW ? LT_EMBREE_LOW : LT_EMBREE_MEDIUM, &build);
    if (!e) return 1;
    double trace = 0;
    for (int b = 0; b < nbatches; b++) trace += lt_embree_trace(e, batches[b].rays, batches[b].count, batches[b].any, hits);
    lt_embree_release(e);
    f->build[run] = build, f->trace[run] = trace, f->total[run] = build + trace, f->ok = 1;
    return 0;
#else
    return 1;
#endif
  }
  lt_stats *stats;
  if (lt_stats_create(&stats)) return 1;
  if (lt_bench_build_and_trace(scene, method, batches, nbatches, hits, stats)) {
    lt_stats_destroy(stats);
    return 1;
  }
  f->total[run] = lt_stats_get(stats, "total_ms");
  f->build[run] = lt_stats_get(stats, "build_ms");
  f->trace[run] = lt_stats_get(stats, "trace_ms");
  f->nodes = lt_stats_get(stats, "nodes_built");
  f->nodes_full = lt_stats_get(stats, "nodes_full");
  f->sort_ops = lt_stats_get(stats, "sort_ops");
  f->ok = 1;
  lt_stats_destroy(stats);
  return 0;
}

/* All methods, interleaved run by run; checks lazytrace's closest hits against the full build. */
static int run_all(const lt_scene *scene, const lt_bench_batch *batches, int nbatches, int runs, figures *f) {
  size_t last = batches[nbatches - 1].count, most = 0;
  for (int b = 0; b < nbatches; b++) most = batches[b].count > most ? batches[b].count : most;
  lt_hit *ref = malloc((most + 1) * sizeof *ref), *hits = malloc((most + 1) * sizeof *hits);
  memset(f, 0, METHODS * sizeof *f);
  for (int run = 0; run < runs; run++)
    for (int m = 0; m < METHODS; m++) {
      if (!(methods_run & 1u << m)) continue;
      if (run_method(scene, m, batches, nbatches, run, &f[m], m == FULL ? ref : hits) != 0) continue;
      int closest = !batches[nbatches - 1].any;
      if (m != FULL && m != EMBREE && closest)
        for (size_t i = 0; i < last; i++)
          if (hits[i].prim != ref[i].prim || (hits[i].prim >= 0 && hits[i].t != ref[i].t))
            return fprintf(stderr, "%s: hit %zu differs from the full build's\n", lt_bench_method_names[m], i), 1;
      fprintf(stderr, "    %-11s run %d: %8.1f ms\n", lt_bench_method_names[m], run + 1, f[m].total[run]);
    }
  free(ref), free(hits);
  return 0;
}

static void csv_row(FILE *csv, const char *scene, const char *camera, const char *workload, const figures *f, int runs) {
  if (!csv) return;
  for (int m = 0; m < METHODS; m++)
    if (f[m].ok)
      fprintf(csv, "%s,%s,%s,%s,%.2f,%.2f,%.2f,%.0f,%.0f\n", scene, camera, workload, lt_bench_method_names[m],
              lt_bench_median(f[m].total, runs), lt_bench_median(f[m].build, runs), lt_bench_median(f[m].trace, runs),
              m == EMBREE ? -1.0 : f[m].nodes, m == EMBREE ? -1.0 : f[m].sort_ops);
}

static void print_row(const char *label, size_t rays, const figures *f, int runs) {
  printf("| %s | %.2fM |", label, rays / 1e6);
  for (int m = 0; m < METHODS; m++) { /* one column for each method the experiment runs */
    if (f[m].ok) printf(" %.0f |", lt_bench_median(f[m].total, runs));
    else if (methods_run & 1u << m) printf(" - |");
  }
  double full = lt_bench_median(f[FULL].total, runs), req = lt_bench_median(f[REQUESTED].total, runs), spec = lt_bench_median(f[SPECULATIVE].total, runs);
  double best = req < spec ? req : spec;
  printf(" %.2f | %.2f |", req / full, spec / full);
  if (f[EMBREE].ok) printf(" %.2f |", best / lt_bench_median(f[EMBREE].total, runs));
  else printf(" - |");
  if (methods_run & 1u << QBVH) printf(" %.2f |", best / lt_bench_median(f[QBVH].total, runs));
  printf(" %.1f%% |\n", 100.0 * f[REQUESTED].nodes / f[FULL].nodes);
}

/* The paper's Table 2 row: the full kd-tree's time to image, build, trace and sort operations,
 * the on-demand ones relative to it, and the BVH and Embree beside them. */
static void print_kd_row(const char *label, size_t rays, const figures *f, int runs) {
  double full = lt_bench_median(f[KD_FULL].total, runs);
  printf("| %s | %.2fM | %.0f | %.0f | %.0f | %.1f |", label, rays / 1e6, full, lt_bench_median(f[KD_FULL].build, runs),
         lt_bench_median(f[KD_FULL].trace, runs), f[KD_FULL].sort_ops / 1e6);
  for (int m = KD_REQUESTED; m <= KD_SPECULATIVE; m++)
    printf(" %+.0f%% / %+.0f%% / %+.0f%% |", 100.0 * (lt_bench_median(f[m].total, runs) / full - 1),
           100.0 * (lt_bench_median(f[m].trace, runs) / lt_bench_median(f[KD_FULL].trace, runs) - 1),
           100.0 * (f[m].sort_ops / f[KD_FULL].sort_ops - 1));
  double kd_a = lt_bench_median(f[KD_SPECULATIVE].total, runs), bvh_a = lt_bench_median(f[SPECULATIVE].total, runs);
  printf(" %.0f | %.0f | %.0f | %.2f | %.2f | %.2f |\n", lt_bench_median(f[FULL].total, runs), bvh_a,
         f[EMBREE].ok ? lt_bench_median(f[EMBREE].total, runs) : -1.0, kd_a / full, kd_a / bvh_a,
         f[EMBREE].ok ? kd_a / lt_bench_median(f[EMBREE].total, runs) : -1.0);
}

static int table(int argc, char **argv, int runs, int size, int ao, FILE *csv) {
  if (methods_run == KD_METHODS) {
    printf("| scene@camera, workload | rays | Kd image ms | Kd build ms | Kd trace ms | Kd sort ops (M) |"
           " Kd_R: image / trace / sort ops vs Kd | Kd_A: image / trace / sort ops vs Kd | BVH ms | BVH_A ms |"
           " Embree ms | Kd_A / Kd | Kd_A / BVH_A | Kd_A / Embree |\n");
    printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  } else {
    printf("| scene@camera, workload | rays | full | requested | speculative | LBVH | Embree | QBVH (full) | req/full |"
           " spec/full | best on-demand / Embree | best on-demand / QBVH | nodes requested / full |\n");
    printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  }
  for (int i = 0; i < argc; i++)
    for (int c = 0; c < 2; c++) {
      const char *camera = c ? "close" : "outer";
      lt_scene *scene;
      char spec[256];
      snprintf(spec, sizeof spec, "%s@%s", argv[i], camera);
      if (lt_scene_load(spec, &scene) != LT_OK) return fprintf(stderr, "%s\n", lt_last_error()), 1;
      fprintf(stderr, "%s (%zu triangles)\n", spec, lt_scene_triangle_count(scene));

      /* Primary rays, then AO rays from their hits (the same for every method). */
      size_t n = (size_t)size * size;
      lt_ray *primary = malloc(n * sizeof *primary), *ao_rays = malloc(n * ao * sizeof *ao_rays);
      lt_camera cam = lt_scene_camera(scene);
      lt_camera_primary_rays(&cam, size, size, primary);
      lt_bench_batch batches[2] = {{primary, n, 0}, {ao_rays, 0, 1}};
      figures f[METHODS];
      if (run_all(scene, batches, 1, runs, f)) return 1;
      char label[300];
      snprintf(label, sizeof label, "%s, primary", spec);
      if (methods_run == KD_METHODS) print_kd_row(label, n, f, runs);
      else print_row(label, n, f, runs);
      csv_row(csv, argv[i], camera, "primary", f, runs);

      batches[1].count = lt_bench_table1_ao_rays(scene, primary, n, ao, ao_rays);
      if (run_all(scene, batches, 2, runs, f)) return 1;
      snprintf(label, sizeof label, "%s, primary + %d AO", spec, ao);
      if (methods_run == KD_METHODS) print_kd_row(label, n + batches[1].count, f, runs);
      else print_row(label, n + batches[1].count, f, runs);
      csv_row(csv, argv[i], camera, "primary+ao", f, runs);
      free(primary), free(ao_rays);
      lt_scene_destroy(scene);
    }
  return 0;
}

static int sweep(int runs, int size, int max, FILE *csv) {
  if (methods_run == KD_METHODS)
    printf("| houses | triangles | kd nodes full | kd nodes requested | kd nodes speculative | Kd ms | Kd_R ms |"
           " Kd_A ms | BVH (full) ms | Embree ms |\n|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  else
    printf("| houses | triangles | nodes full | nodes requested | nodes speculative | full ms | requested ms |"
           " speculative ms | LBVH ms | Embree ms |\n|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  int counts[] = {1, 2, 4, 6, 8, 12, 16, 24, 32};
  for (int i = 0; i < 9 && counts[i] <= max; i++) {
    char spec[64];
    snprintf(spec, sizeof spec, "house-row:%d@outer", counts[i]);
    lt_scene *scene;
    if (lt_scene_load(spec, &scene) != LT_OK) return fprintf(stderr, "%s\n", lt_last_error()), 1;
    fprintf(stderr, "%s\n", spec);
    size_t n = (size_t)size * size;
    lt_ray *rays = malloc(n * sizeof *rays);
    lt_camera cam = lt_scene_camera(scene);
    lt_camera_primary_rays(&cam, size, size, rays);
    lt_bench_batch b = {rays, n, 0};
    figures f[METHODS];
    if (run_all(scene, &b, 1, runs, f)) return 1;
    /* The columns' methods: full, requested, speculative, a fourth for comparison, Embree. */
    static const int bvh_columns[5] = {FULL, REQUESTED, SPECULATIVE, LBVH, EMBREE};
    static const int kd_columns[5] = {KD_FULL, KD_REQUESTED, KD_SPECULATIVE, FULL, EMBREE};
    const int *col = methods_run == KD_METHODS ? kd_columns : bvh_columns;
    double ms[5];
    for (int c = 0; c < 5; c++) ms[c] = f[col[c]].ok ? lt_bench_median(f[col[c]].total, runs) : -1.0;
    printf("| %d | %zu | %.0f | %.0f | %.0f | %.0f | %.0f | %.0f | %.0f | %.0f |\n", counts[i],
           lt_scene_triangle_count(scene), f[col[0]].nodes, f[col[1]].nodes, f[col[2]].nodes, ms[0], ms[1], ms[2], ms[3],
           ms[4]);
    if (csv)
      fprintf(csv, "%d,%zu,%.0f,%.0f,%.0f,%.2f,%.2f,%.2f,%.2f,%.2f\n", counts[i], lt_scene_triangle_count(scene),
              f[col[0]].nodes, f[col[1]].nodes, f[col[2]].nodes, ms[0], ms[1], ms[2], ms[3], ms[4]);
    free(rays);
    lt_scene_destroy(scene);
  }
  return 0;
}

/* Table 4: every frame rebuilds from scratch and traces 800 short rays. Every method's frames
 * are timed one by one; the table gives the median frame over all frames of all runs, and the
 * median run's total of 20 frames. */
#define FRAMES 20

static const char *const collide_labels[METHODS] = {
    "full", "requested", "speculative", "LBVH", "Kd", "Kd_R", "Kd_A", "Embree default", "Embree low", "QBVH",
    "requested, Morton top", "speculative, Morton top"};

static double median_frame(const double (*frame_ms)[MAX_RUNS * FRAMES], int m, int runs) {
  return lt_bench_median(frame_ms[m], runs * FRAMES);
}

static int collide(int argc, char **argv, int runs, FILE *csv) {
  const int agents = 100, per_agent = 8;
  static const int all_columns[] = {FULL,           REQUESTED, SPECULATIVE, REQUESTED_MORTON, SPECULATIVE_MORTON,
                                    KD_FULL,        KD_REQUESTED, KD_SPECULATIVE, LBVH, EMBREE, EMBREE_LOW};
  static const int on_demand[] = {REQUESTED, SPECULATIVE, REQUESTED_MORTON, SPECULATIVE_MORTON, KD_REQUESTED,
                                  KD_SPECULATIVE};
  /* The columns of the methods this run measures. */
  int columns[11], ncolumns = 0;
  for (int c = 0; c < 11; c++)
    if (methods_run & 1u << all_columns[c]) columns[ncolumns++] = all_columns[c];
  printf("Each method's cell: median milliseconds per frame (build plus trace), over all frames of all runs;"
         " in brackets the median run's total over %d frames.\n\n| scene | triangles |", FRAMES);
  for (int c = 0; c < ncolumns; c++) printf(" %s |", collide_labels[columns[c]]);
  printf(" best on-demand | best / Embree low | best / LBVH | best / Embree default | best / full |"
         " nodes requested per frame (BVH, BVH Morton top, Kd) |\n|---|---:|");
  for (int c = 0; c < ncolumns + 5; c++) printf("---:|");
  printf("---:|\n");
  if (csv) fprintf(csv, "scene,triangles,method,frame_ms,total_ms,nodes_per_frame\n");
  for (int i = 0; i < argc; i++) {
    lt_scene *scene;
    if (lt_scene_load(argv[i], &scene) != LT_OK) return fprintf(stderr, "%s\n", lt_last_error()), 1;
    fprintf(stderr, "%s collision\n", argv[i]);
    float *paths = malloc(6 * sizeof(float) * agents);
    lt_ray *rays = malloc((size_t)agents * per_agent * sizeof *rays);
    lt_hit *hits = malloc((size_t)agents * per_agent * sizeof *hits);
    /* The full build's hits of every frame (it runs first), which every lazytrace method must give. */
    size_t frame_rays = (size_t)agents * per_agent;
    lt_hit *full_hits = malloc(FRAMES * frame_rays * sizeof *full_hits);
    lt_collision_paths(scene, agents, 42, paths);
    figures f[METHODS];
    static double frame_ms[METHODS][MAX_RUNS * FRAMES];
    memset(f, 0, sizeof f);
    for (int run = 0; run < runs; run++)
      for (int m = 0; m < METHODS; m++) {
        if (!(methods_run & 1u << m)) continue;
        figures frame;
        double total = 0, nodes = 0;
        int failed = 0;
        for (int fr = 0; fr < FRAMES && !failed; fr++) {
          lt_collision_rays(paths, agents, per_agent, fr, FRAMES, 43, rays);
          lt_bench_batch b = {rays, (size_t)agents * per_agent, 0};
          memset(&frame, 0, sizeof frame);
          failed = run_method(scene, m, &b, 1, 0, &frame, hits);
          lt_hit *want = full_hits + fr * frame_rays;
          if (!failed && m == FULL) memcpy(want, hits, frame_rays * sizeof *hits);
          int check = !failed && m != FULL && m != EMBREE && m != EMBREE_LOW && f[FULL].ok;
          for (size_t r = 0; check && r < frame_rays; r++)
            if (hits[r].prim != want[r].prim || (hits[r].prim >= 0 && hits[r].t != want[r].t))
              return fprintf(stderr, "%s: frame %d, hit %zu differs from the full build's\n", lt_bench_method_names[m], fr, r), 1;
          frame_ms[m][run * FRAMES + fr] = frame.total[0];
          total += frame.total[0], nodes += frame.nodes;
        }
        if (failed) continue;
        f[m].total[run] = total, f[m].nodes = nodes / FRAMES, f[m].ok = 1;
        fprintf(stderr, "    %-14s run %d: %8.1f ms\n", lt_bench_method_names[m], run + 1, total);
      }

    /* The cells, then the best on-demand method per frame against the peers. */
    printf("| %s | %zu |", argv[i], lt_scene_triangle_count(scene));
    for (int c = 0; c < ncolumns; c++) {
      int m = columns[c];
      if (f[m].ok) printf(" %.1f (%.0f) |", median_frame(frame_ms, m, runs), lt_bench_median(f[m].total, runs));
      else printf(" - |");
    }
    int best = -1;
    for (int o = 0; o < 6; o++)
      if (f[on_demand[o]].ok && (best < 0 || median_frame(frame_ms, on_demand[o], runs) < median_frame(frame_ms, best, runs)))
        best = on_demand[o];
    double b = best >= 0 ? median_frame(frame_ms, best, runs) : -1.0;
    printf(" %s |", best >= 0 ? collide_labels[best] : "-");
    static const int peers[] = {EMBREE_LOW, LBVH, EMBREE, FULL};
    for (int p = 0; p < 4; p++) {
      if (best >= 0 && f[peers[p]].ok) printf(" %.2f |", b / median_frame(frame_ms, peers[p], runs));
      else printf(" - |");
    }
    static const int counted[] = {REQUESTED, REQUESTED_MORTON, KD_REQUESTED};
    for (int c = 0; c < 3; c++) {
      if (f[counted[c]].ok) printf("%s %.0f", c ? "," : "", f[counted[c]].nodes);
      else printf("%s -", c ? "," : "");
    }
    printf(" |\n");
    if (csv)
      for (int m = 0; m < METHODS; m++)
        if (f[m].ok)
          fprintf(csv, "%s,%zu,%s,%.2f,%.2f,%.0f\n", argv[i], lt_scene_triangle_count(scene), lt_bench_method_names[m],
                  median_frame(frame_ms, m, runs), lt_bench_median(f[m].total, runs),
                  m == EMBREE || m == EMBREE_LOW ? -1.0 : f[m].nodes);
    free(paths), free(rays), free(hits), free(full_hits);
    lt_scene_destroy(scene);
  }
  return 0;
}

/* Table 3: traversal steps and triangle tests per primary ray on fully built trees. */
static int steps(int argc, char **argv, int size) {
  static const lt_structure_kind kinds[] = {LT_STRUCTURE_LBVH, LT_STRUCTURE_BVH, LT_STRUCTURE_KDTREE};
  printf("| scene@camera | LBVH steps | LBVH tests | BVH steps | BVH tests | kd-tree steps | kd-tree tests |\n"
         "|---|---:|---:|---:|---:|---:|---:|\n");
  for (int i = 0; i < argc; i++)
    for (int c = 0; c < 2; c++) {
      char spec[256];
      snprintf(spec, sizeof spec, "%s@%s", argv[i], c ? "close" : "outer");
      lt_scene *scene;
      if (lt_scene_load(spec, &scene) != LT_OK) return fprintf(stderr, "%s\n", lt_last_error()), 1;
      size_t n = (size_t)size * size;
      lt_ray *rays = malloc(n * sizeof *rays);
      lt_hit *hits = malloc(n * sizeof *hits);
      lt_camera cam = lt_scene_camera(scene);
      lt_camera_primary_rays(&cam, size, size, rays);
      printf("| %s |", spec);
      for (int k = 0; k < 3; k++) {
        lt_structure_config config = lt_structure_config_default(kinds[k]);
        config.build = LT_BUILD_FULL;
        lt_stats *stats;
        lt_structure *s = NULL;
        lt_stats_create(&stats);
        lt_status status = lt_structure_create(lt_bench_context(), scene, &config, NULL, &s);
        if (!status) status = lt_structure_trace(s, rays, n, LT_QUERY_CLOSEST, hits, stats);
        if (status) return fprintf(stderr, "%s\n", lt_last_error()), 1;
        printf(" %.1f | %.1f |", lt_stats_get(stats, "traversal_steps") / n, lt_stats_get(stats, "intersections") / n);
        lt_structure_destroy(s);
        lt_stats_destroy(stats);
      }
      printf("\n");
      free(rays), free(hits);
      lt_scene_destroy(scene);
    }
  return 0;
}

int main(int argc, char **argv) {
  setvbuf(stdout, NULL, _IOLBF, 0); /* rows as they are measured: a long run stopped keeps them */
  if (argc < 2) return fprintf(stderr, "usage: bench_ondemand table|sweep|collide [options] [SCENE...]\n"), 2;
  int runs = 3, size = 1024, ao = 8, max = 16, nscenes = 0;
  const char *csv_path = NULL;
  char *scenes[64];
  for (int i = 2; i < argc; i++) {
    if (strcmp(argv[i], "--runs") == 0 && i + 1 < argc) runs = atoi(argv[++i]);
    else if (strcmp(argv[i], "--size") == 0 && i + 1 < argc) size = atoi(argv[++i]);
    else if (strcmp(argv[i], "--ao") == 0 && i + 1 < argc) ao = atoi(argv[++i]);
    else if (strcmp(argv[i], "--max") == 0 && i + 1 < argc) max = atoi(argv[++i]);
    else if (strcmp(argv[i], "--csv") == 0 && i + 1 < argc) csv_path = argv[++i];
    else if (strcmp(argv[i], "--kd") == 0) methods_run = KD_METHODS;
    else if (strcmp(argv[i], "--peers") == 0) methods_run = PEER_METHODS;
    else if (argv[i][0] != '-' && nscenes < 64) scenes[nscenes++] = argv[i];
    else return fprintf(stderr, "bench_ondemand: unknown option %s\n", argv[i]), 2;
  }
  if (runs < 1 || runs > MAX_RUNS || size < 1 || ao < 1) return fprintf(stderr, "bench_ondemand: bad option value\n"), 2;
  if (!lt_bench_native_context() || !lt_bench_context()) return fprintf(stderr, "%s\n", lt_last_error()), 1;
  FILE *csv = csv_path ? fopen(csv_path, "w") : NULL;
  int rc;
  if (strcmp(argv[1], "table") == 0 && methods_run == BVH_METHODS) methods_run = TABLE1_METHODS;
  if (strcmp(argv[1], "table") == 0) rc = table(nscenes, scenes, runs, size, ao, csv);
  else if (strcmp(argv[1], "sweep") == 0) rc = sweep(runs, size, max, csv);
  else if (strcmp(argv[1], "collide") == 0)
    rc = (methods_run = methods_run == PEER_METHODS ? PEER_METHODS : COLLIDE_METHODS, collide(nscenes, scenes, runs, csv));
  else if (strcmp(argv[1], "steps") == 0) rc = steps(nscenes, scenes, size);
  else rc = (fprintf(stderr, "bench_ondemand: unknown experiment %s\n", argv[1]), 2);
  if (csv) fclose(csv);
  return rc;
}
