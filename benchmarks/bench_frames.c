/* The on-demand paper's Table 5 in shape (Vinkler et al. 2016, section 5): animated scenes whose
 * structure is rebuilt from scratch every frame, and the average time to image per frame over
 * the animation for primary rays, primary + AO rays and primary + diffuse rays, with Embree 3's
 * low-quality (Morton) and default builds beside lazytrace's methods:
 *
 *   bench_frames [--runs R] [--size N] [--frames F] [--samples S] [--methods all|peers] [--csv FILE] SCENE...
 *
 * SCENE is anything lt_scene_load takes that moves (explode:BASE, a scene file with keyframes).
 * Every frame moves the scene (lt_scene_set_time), makes its rays (camera rays, then AO or
 * diffuse rays from the full BVH's primary hits: the same rays for every method) and runs every
 * method on them, methods interleaved frame by frame and run by run. A method's figure is the
 * median over runs of its mean over frames. The lazytrace methods' closest hits are checked
 * against the full build's, frame by frame. Markdown to stdout (the table, then a line per scene:
 * the triangles that move, the distinct triangles the camera rays hit, and the nodes BVH_R builds
 * against the full BVH's), CSV to --csv FILE. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lazytrace.h"
#include "benchmarks/median.h"
#include "benchmarks/methods.h"
#ifdef LT_HAVE_EMBREE
#include "benchmarks/embree_peer.h"
#endif

#define MAX_RUNS 16
#define METHODS LT_BENCH_METHODS
enum { FULL = LT_BENCH_FULL, EMBREE = LT_BENCH_EMBREE, EMBREE_LOW = LT_BENCH_EMBREE_LOW };

/* The table's columns, in order: every method, or (--methods peers) the full BVH (whose hits
 * are the check), the on-demand BVH with either top and the per-frame peers (the LBVH, Embree's
 * low-quality and default builds). */
static const int all_columns[] = {LT_BENCH_FULL,    LT_BENCH_REQUESTED,    LT_BENCH_SPECULATIVE,
                                  LT_BENCH_REQUESTED_MORTON, LT_BENCH_SPECULATIVE_MORTON,
                                  LT_BENCH_KD_FULL, LT_BENCH_KD_REQUESTED, LT_BENCH_KD_SPECULATIVE,
                                  LT_BENCH_LBVH,    LT_BENCH_EMBREE_LOW,   LT_BENCH_EMBREE};
static const int peer_columns[] = {LT_BENCH_FULL,   LT_BENCH_REQUESTED,  LT_BENCH_SPECULATIVE, LT_BENCH_REQUESTED_MORTON,
                                   LT_BENCH_SPECULATIVE_MORTON, LT_BENCH_LBVH, LT_BENCH_EMBREE_LOW, LT_BENCH_EMBREE};
static const int *columns = all_columns;
static int COLUMNS = (int)(sizeof all_columns / sizeof *all_columns);

/* A column's heading. */
static const char *column_name(int method) {
  switch (method) {
  case LT_BENCH_FULL: return "full BVH";
  case LT_BENCH_REQUESTED: return "BVH_R";
  case LT_BENCH_SPECULATIVE: return "BVH_A";
  case LT_BENCH_REQUESTED_MORTON: return "BVH_R Morton top";
  case LT_BENCH_SPECULATIVE_MORTON: return "BVH_A Morton top";
  case LT_BENCH_KD_FULL: return "Kd";
  case LT_BENCH_KD_REQUESTED: return "Kd_R";
  case LT_BENCH_KD_SPECULATIVE: return "Kd_A";
  case LT_BENCH_LBVH: return "LBVH";
  case LT_BENCH_EMBREE_LOW: return "Embree low";
  default: return "Embree default";
  }
}

/* Whether a method builds on demand (the "best on-demand" column's candidates). */
static int on_demand(int m) {
  return m == LT_BENCH_REQUESTED || m == LT_BENCH_SPECULATIVE || m == LT_BENCH_REQUESTED_MORTON ||
         m == LT_BENCH_SPECULATIVE_MORTON || m == LT_BENCH_KD_REQUESTED || m == LT_BENCH_KD_SPECULATIVE;
}

typedef enum { PRIMARY, AO, DIFFUSE, WORKLOADS } workload;
static const char *const workload_names[WORKLOADS] = {"primary", "primary + AO", "primary + diffuse"};

/* One method's time per frame summed over the frames of each run, and the nodes built. */
typedef struct figures {
  double sum[MAX_RUNS], build[MAX_RUNS], nodes;
  int ok;
} figures;

/* What a scene's animation moves and what its primary rays reach, for the notes under the
 * table: triangles that leave their place in some frame, and the distinct triangles the camera
 * rays hit, averaged over the frames. */
typedef struct reach {
  size_t moving, triangles;
  double hit, nodes_full, nodes_requested;
} reach;

#define MAX_SCENES 16
static reach reached[MAX_SCENES];

/* The triangles that are somewhere else in some frame than at time 0. */
static size_t moving_triangles(lt_scene *scene, int frames) {
  size_t n = lt_scene_triangle_count(scene), moving = 0;
  float *rest = malloc(n * 9 * sizeof *rest);
  unsigned char *moved = calloc(n ? n : 1, 1);
  if (!rest || !moved) return free(rest), free(moved), 0;
  lt_scene_set_time(scene, 0.0);
  memcpy(rest, lt_scene_triangles(scene), n * 9 * sizeof *rest);
  for (int frame = 1; frame < frames; frame++) {
    lt_scene_set_time(scene, lt_frame_time(frame, frames));
    const float *now = lt_scene_triangles(scene);
    for (size_t i = 0; i < n; i++)
      if (!moved[i] && memcmp(now + 9 * i, rest + 9 * i, 9 * sizeof *rest) != 0) moved[i] = 1, moving++;
  }
  lt_scene_set_time(scene, 0.0);
  free(rest), free(moved);
  return moving;
}

/* The distinct triangles hit by `count` closest hits. */
static size_t distinct_hits(const lt_hit *hits, size_t count, size_t triangles, unsigned char *seen) {
  size_t distinct = 0;
  memset(seen, 0, triangles);
  for (size_t i = 0; i < count; i++)
    if (hits[i].prim >= 0 && (size_t)hits[i].prim < triangles && !seen[hits[i].prim]) seen[hits[i].prim] = 1, distinct++;
  return distinct;
}

/* One frame of one method: build, then the batches (rays[0] closest hit, rays[1] if any, of
 * the workload's query); the last batch's hits in hits. Returns nonzero on failure. */
static int run_frame(const lt_scene *scene, int method, const lt_ray *const rays[2], const size_t count[2], int any,
                     lt_hit *hits, double *ms, double *build_ms, double *nodes) {
  int batches = count[1] ? 2 : 1;
  if (method == EMBREE || method == EMBREE_LOW) {
#ifdef LT_HAVE_EMBREE
    lt_embree *e = lt_embree_build_quality(scene, lt_context_work_groups(lt_bench_native_context()),
                                           method == EMBREE_LOW ? LT_EMBREE_LOW : LT_EMBREE_MEDIUM, build_ms);
    if (!e) return 1;
    *ms = *build_ms;
    for (int b = 0; b < batches; b++) *ms += lt_embree_trace(e, rays[b], count[b], b == 1 && any, hits);
    lt_embree_release(e);
    *nodes = -1;
    return 0;
#else
    return 1;
#endif
  }
  lt_stats *stats;
  if (lt_stats_create(&stats)) return 1;
  const lt_bench_batch list[2] = {{rays[0], count[0], 0}, {rays[1], count[1], any}};
  lt_status status = lt_bench_build_and_trace(scene, method, list, batches, hits, stats);
  *ms = lt_stats_get(stats, "total_ms"), *build_ms = lt_stats_get(stats, "build_ms");
  *nodes = lt_stats_get(stats, "nodes_built");
  lt_stats_destroy(stats);
  return status != LT_OK;
}

/* Every frame of one workload, every method, `runs` times. */
static int run_workload(lt_scene *scene, workload w, int runs, int size, int frames, int samples, float ao_distance,
                        figures f[METHODS], reach *r) {
  size_t n = (size_t)size * size, most = n * (size_t)samples;
  lt_ray *primary = malloc(n * sizeof *primary), *secondary = malloc((most + 1) * sizeof *secondary);
  lt_hit *ref = malloc((most + 1) * sizeof *ref), *hits = malloc((most + 1) * sizeof *hits);
  unsigned char *seen = malloc(r->triangles ? r->triangles : 1);
  if (!primary || !secondary || !ref || !hits || !seen) return fprintf(stderr, "out of memory\n"), 1;
  memset(f, 0, METHODS * sizeof *f);
  int failed = 0;
  for (int frame = 0; frame < frames && !failed; frame++) {
    /* The frame's rays: camera rays, then AO or diffuse rays from the full BVH's hits. */
    lt_scene_set_time(scene, lt_frame_time(frame, frames));
    lt_camera cam = lt_scene_camera(scene);
    lt_camera_primary_rays(&cam, size, size, primary);
    const lt_ray *rays[2] = {primary, secondary};
    size_t count[2] = {n, 0};
    if (w != PRIMARY) {
      double ms, build, nodes;
      size_t zero[2] = {n, 0};
      if (run_frame(scene, FULL, rays, zero, 0, hits, &ms, &build, &nodes)) return 1;
      count[1] = lt_ao_rays(scene, primary, hits, n, samples, w == AO ? ao_distance : INFINITY, 1 + (uint64_t)frame,
                            secondary);
    }
    for (int run = 0; run < runs && !failed; run++)
      for (int c = 0; c < COLUMNS && !failed; c++) {
        int m = columns[c];
        double ms, build, nodes;
        if (run_frame(scene, m, rays, count, w == AO, m == FULL ? ref : hits, &ms, &build, &nodes)) {
          if (m == EMBREE || m == EMBREE_LOW) continue; /* no Embree here: its columns stay empty */
          failed = 1;
          break;
        }
        f[m].sum[run] += ms, f[m].build[run] += build, f[m].ok = 1;
        if (run == 0) f[m].nodes += nodes;

        /* Closest hits (primary, diffuse) must be the full build's, ray for ray. */
        size_t last = count[1] ? count[1] : count[0];
        if (m != FULL && m != EMBREE && m != EMBREE_LOW && w != AO)
          for (size_t i = 0; i < last; i++)
            if (hits[i].prim != ref[i].prim || (hits[i].prim >= 0 && hits[i].t != ref[i].t)) {
              fprintf(stderr, "%s: frame %d: hit %zu differs from the full build's\n", lt_bench_method_names[m],
                      frame, i);
              failed = 1;
              break;
            }
      }
    if (w == PRIMARY && !failed) r->hit += (double)distinct_hits(ref, n, r->triangles, seen) / frames;
    fprintf(stderr, "  %s, frame %d of %d: %zu rays\n", workload_names[w], frame + 1, frames, count[0] + count[1]);
  }
  lt_scene_set_time(scene, 0.0);
  free(primary), free(secondary), free(ref), free(hits), free(seen);
  return failed;
}

/* A method's average milliseconds per frame (of v: sum or build): the median over runs of the
 * mean over frames. */
static double per_frame(const double *v, int runs, int frames) {
  double mean[MAX_RUNS];
  for (int r = 0; r < runs; r++) mean[r] = v[r] / frames;
  return lt_bench_median(mean, runs);
}

int main(int argc, char **argv) {
  int runs = 3, size = 256, frames = 8, samples = 8, first = 1;
  FILE *csv = NULL;
  for (; first + 1 < argc && argv[first][0] == '-'; first += 2) {
    const char *o = argv[first], *v = argv[first + 1];
    if (strcmp(o, "--runs") == 0) runs = atoi(v);
    else if (strcmp(o, "--size") == 0) size = atoi(v);
    else if (strcmp(o, "--frames") == 0) frames = atoi(v);
    else if (strcmp(o, "--samples") == 0) samples = atoi(v);
    else if (strcmp(o, "--methods") == 0 && strcmp(v, "peers") == 0)
      columns = peer_columns, COLUMNS = (int)(sizeof peer_columns / sizeof *peer_columns);
    else if (strcmp(o, "--methods") == 0 && strcmp(v, "all") != 0) return fprintf(stderr, "--methods all|peers\n"), 2;
    else if (strcmp(o, "--csv") == 0 && !(csv = fopen(v, "w"))) return fprintf(stderr, "%s: cannot write\n", v), 1;
    else if (strcmp(o, "--csv") != 0 && strcmp(o, "--methods") != 0) return fprintf(stderr, "unknown option %s\n", o), 2;
  }
  if (first >= argc || runs < 1 || runs > MAX_RUNS || size < 1 || frames < 1 || samples < 1)
    return fprintf(stderr, "usage: bench_frames [--runs 1-%d] [--size N] [--frames F] [--samples S] [--methods all|peers] [--csv FILE] "
                           "SCENE...\n", MAX_RUNS), 2;
  if (!lt_bench_native_context()) return fprintf(stderr, "%s\n", lt_last_error()), 1;
  if (csv) fprintf(csv, "scene,workload,method,ms_per_frame,build_ms_per_frame,nodes_per_frame\n");

  printf("| scene, rays per frame |");
  for (int c = 0; c < COLUMNS; c++) printf(" %s |", column_name(columns[c]));
  printf(" best on-demand / Embree low |\n|---|");
  for (int c = 0; c <= COLUMNS; c++) printf("---:|");
  printf("\n");
  for (int i = first; i < argc; i++) {
    lt_scene *scene;
    if (lt_scene_load(argv[i], &scene) != LT_OK) return fprintf(stderr, "%s\n", lt_last_error()), 1;
    fprintf(stderr, "%s: %zu triangles, %s\n", argv[i], lt_scene_triangle_count(scene),
            lt_scene_is_animated(scene) ? "animated" : "static (every frame the same)");
    float lo[3], hi[3];
    lt_scene_bounds(scene, lo, hi);
    float diag = sqrtf((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                       (hi[2] - lo[2]) * (hi[2] - lo[2]));
    reach *r = &reached[i - first < MAX_SCENES ? i - first : MAX_SCENES - 1];
    r->triangles = lt_scene_triangle_count(scene), r->moving = moving_triangles(scene, frames), r->hit = 0;
    for (int w = 0; w < WORKLOADS; w++) {
      figures f[METHODS];
      if (run_workload(scene, (workload)w, runs, size, frames, samples, 0.05f * diag, f, r)) return 1;
      if (w == PRIMARY) {
        r->nodes_full = f[FULL].nodes / frames;
        r->nodes_requested = f[LT_BENCH_REQUESTED].ok ? f[LT_BENCH_REQUESTED].nodes / frames : -1;
      }
      if (w == PRIMARY) printf("| %s, primary |", argv[i]);
      else printf("| %s, %s (%d samples) |", argv[i], workload_names[w], samples);
      double best = INFINITY;
      for (int c = 0; c < COLUMNS; c++) {
        int m = columns[c];
        double ms = f[m].ok ? per_frame(f[m].sum, runs, frames) : -1.0;
        if (ms >= 0) printf(" %.1f |", ms);
        else printf(" - |");
        if (ms >= 0 && on_demand(m) && ms < best) best = ms;
        if (csv && ms >= 0)
          fprintf(csv, "%s,%s,%s,%.2f,%.2f,%.0f\n", argv[i], workload_names[w], lt_bench_method_names[m], ms,
                  per_frame(f[m].build, runs, frames), f[m].nodes / frames);
      }
      if (f[EMBREE_LOW].ok) printf(" %.2f |\n", best / per_frame(f[EMBREE_LOW].sum, runs, frames));
      else printf(" - |\n");
      fflush(stdout);
    }
    lt_scene_destroy(scene);
  }

  /* Under the table: what each scene moves and what its primary rays reach. */
  printf("\n");
  for (int i = first; i < argc && i - first < MAX_SCENES; i++) {
    const reach *r = &reached[i - first];
    printf("- %s: %zu of %zu triangles move (%.2f%%); the primary rays hit %.0f distinct triangles a frame "
           "(%.2f%%)", argv[i], r->moving, r->triangles, 100.0 * r->moving / r->triangles, r->hit,
           100.0 * r->hit / r->triangles);
    if (r->nodes_requested >= 0 && r->nodes_full > 0)
      printf("; the requested BVH builds %.0f of the full BVH's %.0f nodes a frame (%.1f%%)", r->nodes_requested,
             r->nodes_full, 100.0 * r->nodes_requested / r->nodes_full);
    printf("\n");
  }
  if (csv) fclose(csv);
  return 0;
}
