/* lazytrace collide: the collision-ray batches of the on-demand paper (Vinkler et al. 2016,
 * section 5): agents move along random line segments inside the scene bounds; every frame the
 * structure is rebuilt from scratch and each agent shoots rays in random directions around
 * itself, as far as its next position. With --hits, all frames' hits are written, frame after
 * frame, each frame agent after agent. An animated scene moves to each frame's time (the paths
 * stay those drawn over its first frame's bounds); the statistics keep a record per frame. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "apps/cli.h"

int lt_cmd_collide(lt_cli *cli) {
  lt_stats *stats = NULL, *frame_stats = NULL;
  lt_context *ctx;
  lt_scene *scene;
  if (lt_stats_create(&stats) || lt_stats_create(&frame_stats)) {
    lt_stats_destroy(stats);
    return lt_cli_fail("statistics", LT_ERROR_OUT_OF_MEMORY);
  }
  if (lt_cli_open(cli, &ctx, &scene, stats)) {
    lt_stats_destroy(stats), lt_stats_destroy(frame_stats);
    return 1;
  }
  size_t n = (size_t)cli->agents * cli->rays_per_agent;
  float *paths = malloc(6 * sizeof(float) * cli->agents);
  lt_ray *rays = malloc(n * sizeof *rays);
  lt_hit *hits = malloc(n * sizeof *hits);
  /* With --hits, every frame's hits are kept and written, frame after frame, in ray order. */
  lt_hit *all_hits = cli->hits ? malloc((n * cli->frames > 0 ? n * cli->frames : 1) * sizeof *all_hits) : NULL;
  int rc = 1;
  if (!paths || !rays || !hits || (cli->hits && !all_hits)) {
    fprintf(stderr, "lazytrace collide: out of memory\n");
    goto done;
  }
  lt_collision_paths(scene, cli->agents, cli->seed, paths);

  /* Every frame rebuilds the structure from scratch, as moving geometry would require. */
  double build_sum = 0, trace_sum = 0, hits_sum = 0;
  fprintf(stderr, "frame  build_ms  trace_ms  total_ms  hits\n");
  for (int f = 0; f < cli->frames; f++) {
    lt_structure *structure = NULL;
    lt_stats_reset(frame_stats);
    lt_scene_set_time(scene, lt_frame_time(f, cli->frames)); /* an animated scene moves */
    lt_collision_rays(paths, cli->agents, cli->rays_per_agent, f, cli->frames, cli->seed + 1, rays);
    lt_status status = lt_structure_create(ctx, scene, &cli->structure, frame_stats, &structure);
    if (!status) status = lt_structure_trace(structure, rays, n, LT_QUERY_CLOSEST, hits, frame_stats);
    lt_structure_destroy(structure);
    if (status) {
      rc = lt_cli_fail("collision frame", status);
      goto done;
    }
    int frame_hits = 0;
    for (size_t i = 0; i < n; i++) frame_hits += hits[i].prim >= 0;
    if (all_hits) memcpy(all_hits + (size_t)f * n, hits, n * sizeof *hits);
    lt_stats_add_frame(stats, frame_stats);
    double b = lt_stats_get(frame_stats, "build_ms"), t = lt_stats_get(frame_stats, "trace_ms");
    build_sum += b, trace_sum += t, hits_sum += frame_hits;
    fprintf(stderr, "%5d  %8.2f  %8.2f  %8.2f  %d\n", f, b, t, b + t, frame_hits);
  }
  fprintf(stderr, "lazytrace: %d frames of %zu rays: build %.1f ms, trace %.1f ms, %.0f hits\n", cli->frames, n,
          build_sum, trace_sum, hits_sum);

  lt_cli_collide_totals(stats, frame_stats, build_sum, trace_sum, (double)n * cli->frames);
  if (all_hits) {
    lt_status status = lt_hits_write(cli->hits, all_hits, n * cli->frames);
    if (status) {
      rc = lt_cli_fail("writing hits", status);
      goto done;
    }
  }
  rc = lt_cli_write_stats(cli, stats);

done:
  free(paths), free(rays), free(hits), free(all_hits);
  lt_scene_destroy(scene);
  lt_context_destroy(ctx);
  lt_stats_destroy(stats);
  lt_stats_destroy(frame_stats);
  return rc;
}

void lt_cli_collide_totals(lt_stats *stats, const lt_stats *last_frame, double build_ms, double trace_ms, double rays) {
  double load_ms = lt_stats_get(stats, "load_ms");
  lt_stats_copy(stats, last_frame);
  lt_stats_set(stats, "load_ms", load_ms);
  lt_stats_set(stats, "build_ms", build_ms);
  lt_stats_set(stats, "trace_ms", trace_ms);
  lt_stats_set(stats, "total_ms", build_ms + trace_ms);
  lt_stats_set(stats, "rays", rays);
  /* Every ray here is a collision ray, as a scene file's collision effect would count it. */
  static const char *const effects[] = {"primary", "shadows", "ao", "diffuse", "mirror", "collision"};
  for (int e = 0; e < 6; e++) {
    char key[64];
    snprintf(key, sizeof key, "rays_by_effect.%s", effects[e]);
    lt_stats_set(stats, key, e == 5 ? rays : 0.0);
    snprintf(key, sizeof key, "ms_by_effect.%s", effects[e]);
    lt_stats_set(stats, key, e == 5 ? build_ms + trace_ms : 0.0);
  }
}
