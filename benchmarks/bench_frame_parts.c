/* Where one collision frame of an on-demand build goes (issue 17, "cheaper top levels"). Every
 * frame rebuilds, so each pays for its set-up (triangle boxes, buffers) and for the top levels
 * over all triangles (the root bins and partitions every triangle, its children half each, ...)
 * whatever its rays reach; then for the other nodes its rays request, and for the trace:
 *
 *   bench_frame_parts [--runs R] [--build requested|speculative] [--top sah|morton[:K]] SCENE...
 *
 * (--top morton:K: the Morton top, nodes of more than K triangles split by code; K 2048 when
 * left out.)
 *
 * For each frame of the collision workload (100 agents x 8 rays x 20 frames, seeds as in
 * bench_ondemand collide), on the native backend, each step on a new structure:
 *   A: create (the set-up);
 *   B: create and trace the frame's first ray that hits something (set-up plus the path from
 *      the root to one leaf: the top levels, about twice the triangles' count of binning and
 *      partitioning);
 *   C: create and trace all the frame's rays (time to image);
 *   D: as C with statistics: trace_ms (the same rays again on the tree as built) and nodes.
 * Parts: set-up = A, top path = B - A, other requested nodes = C - B - trace, trace = D's
 * trace_ms; each the median over all frames of all runs, so the parts need not add up exactly
 * to the median frame. Markdown to stdout. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "benchmarks/median.h"
#include "lazytrace.h"

#define FRAMES    20
#define MAX_RUNS  16
#define AGENTS    100
#define PER_AGENT 8

enum { SETUP, PATH, FRAME, TRACE, NODES, PARTS };

/* Creates the structure and traces rays[0, count) (none: create only); returns wall ms, or -1. */
static double timed(lt_context *ctx, const lt_scene *scene, const lt_structure_config *config, const lt_ray *rays,
                    size_t count, lt_hit *hits, lt_stats *stats) {
  lt_structure *s = NULL;
  double start = lt_now_ms();
  lt_status status = lt_structure_create(ctx, scene, config, stats, &s);
  if (!status && count) status = lt_structure_trace(s, rays, count, LT_QUERY_CLOSEST, hits, stats);
  double ms = lt_now_ms() - start;
  lt_structure_destroy(s);
  if (status) fprintf(stderr, "%s\n", lt_last_error());
  return status ? -1.0 : ms;
}

static int parts(lt_context *ctx, const char *spec, lt_build_mode build, const char *top, int runs) {
  lt_scene *scene;
  if (lt_scene_load(spec, &scene) != LT_OK) return fprintf(stderr, "%s\n", lt_last_error()), 1;
  lt_structure_config config = lt_structure_config_default(LT_STRUCTURE_BVH);
  config.build = build;
  if (strncmp(top, "morton", 6) == 0) {
    config.bvh_top = LT_BVH_TOP_MORTON;
    if (top[6] == ':') config.bvh_morton_above = atoi(top + 7);
  }
  size_t n = (size_t)AGENTS * PER_AGENT;
  float paths[6 * AGENTS];
  lt_ray rays[AGENTS * PER_AGENT];
  lt_hit hits[AGENTS * PER_AGENT];
  static double v[PARTS][MAX_RUNS * FRAMES];
  lt_collision_paths(scene, AGENTS, 42, paths);
  lt_stats *stats;
  lt_stats_create(&stats);
  for (int run = 0; run < runs; run++)
    for (int f = 0; f < FRAMES; f++) {
      lt_collision_rays(paths, AGENTS, PER_AGENT, f, FRAMES, 43, rays);
      double *x[PARTS];
      for (int p = 0; p < PARTS; p++) x[p] = &v[p][run * FRAMES + f];

      /* The whole frame first, which also finds the first ray that hits. */
      *x[FRAME] = timed(ctx, scene, &config, rays, n, hits, NULL);
      size_t first = 0;
      while (first < n && hits[first].prim < 0) first++;
      if (first == n) first = 0;
      *x[SETUP] = timed(ctx, scene, &config, NULL, 0, hits, NULL);
      *x[PATH] = timed(ctx, scene, &config, &rays[first], 1, hits, NULL);
      lt_stats_reset(stats);
      if (timed(ctx, scene, &config, rays, n, hits, stats) < 0 || *x[FRAME] < 0 || *x[SETUP] < 0 || *x[PATH] < 0)
        return 1;
      *x[TRACE] = lt_stats_get(stats, "trace_ms");
      *x[NODES] = lt_stats_get(stats, "nodes_built");
    }

  /* The parts frame by frame, then their medians. */
  static double setup[MAX_RUNS * FRAMES], path[MAX_RUNS * FRAMES], rest[MAX_RUNS * FRAMES];
  int m = runs * FRAMES;
  for (int i = 0; i < m; i++) {
    setup[i] = v[SETUP][i];
    path[i] = v[PATH][i] - v[SETUP][i];
    rest[i] = v[FRAME][i] - v[PATH][i] - v[TRACE][i];
  }
  double frame = lt_bench_median(v[FRAME], m);
  double s = lt_bench_median(setup, m), p = lt_bench_median(path, m), r = lt_bench_median(rest, m);
  double t = lt_bench_median(v[TRACE], m);
  printf("| %s | %s | %zu | %.0f | %.1f | %.1f (%.0f%%) | %.1f (%.0f%%) | %.1f (%.0f%%) | %.1f (%.0f%%) |\n", spec,
         top, lt_scene_triangle_count(scene), lt_bench_median(v[NODES], m), frame, s, 100 * s / frame, p, 100 * p / frame, r,
         100 * r / frame, t, 100 * t / frame);
  lt_stats_destroy(stats);
  lt_scene_destroy(scene);
  return 0;
}

int main(int argc, char **argv) {
  setvbuf(stdout, NULL, _IOLBF, 0);
  int runs = 3;
  lt_build_mode build = LT_BUILD_REQUESTED;
  const char *top = "sah";
  lt_context *ctx;
  lt_context_config cc = {LT_DEVICE_NATIVE, 0, 0, 0, 1};
  if (lt_context_create(&cc, &ctx) != LT_OK) return fprintf(stderr, "%s\n", lt_last_error()), 1;
  printf(
      "| scene | top | triangles | nodes per frame | frame ms | set-up ms | top path ms | other requested nodes ms |"
      " trace ms |\n|---|---|---:|---:|---:|---:|---:|---:|---:|\n");
  for (int i = 1; i < argc; i++) {
    if (strcmp(argv[i], "--runs") == 0 && i + 1 < argc)
      runs = atoi(argv[++i]);
    else if (strcmp(argv[i], "--build") == 0 && i + 1 < argc)
      build = strcmp(argv[++i], "speculative") == 0 ? LT_BUILD_SPECULATIVE : LT_BUILD_REQUESTED;
    else if (strcmp(argv[i], "--top") == 0 && i + 1 < argc)
      top = argv[++i];
    else if (runs < 1 || runs > MAX_RUNS)
      return fprintf(stderr, "bench_frame_parts: --runs 1 to %d\n", MAX_RUNS), 2;
    else if (parts(ctx, argv[i], build, top, runs))
      return 1;
  }
  lt_context_destroy(ctx);
  return 0;
}
