/* lazytrace collide: the collision-ray batches of the on-demand paper (Vinkler et al. 2016,
 * section 5): agents move along random line segments inside the scene bounds; every frame the
 * structure is rebuilt from scratch and each agent shoots rays in random directions around
 * itself, as far as its next position. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "apps/cli.h"

/* splitmix64: a small deterministic generator, so a seed gives the same batches anywhere. */
static uint64_t next_u64(uint64_t *state) {
  uint64_t z = (*state += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}
static float uniform(uint64_t *state) { return (next_u64(state) >> 40) * (1.0f / 16777216.0f); }

/* Path endpoints of every agent: 6 floats (start, end) each. */
static void place_agents(const lt_scene *scene, int agents, uint64_t *rng, float *paths) {
  float lo[3], hi[3];
  lt_scene_bounds(scene, lo, hi);
  for (int a = 0; a < 6 * agents; a++) paths[a] = lo[a % 3] + uniform(rng) * (hi[a % 3] - lo[a % 3]);
}

/* The rays of one frame: from each agent's position, uniformly on the sphere, up to the next. */
static void frame_rays(const float *paths, int agents, int per_agent, int frame, int frames, uint64_t *rng, lt_ray *out) {
  for (int a = 0; a < agents; a++) {
    const float *p = paths + 6 * a;
    float s0 = (float)frame / frames, s1 = (float)(frame + 1) / frames, pos[3], step = 0.0f;
    for (int k = 0; k < 3; k++) {
      pos[k] = p[k] + s0 * (p[3 + k] - p[k]);
      float d = (s1 - s0) * (p[3 + k] - p[k]);
      step += d * d;
    }
    for (int r = 0; r < per_agent; r++) {
      float z = 2.0f * uniform(rng) - 1.0f, phi = 6.2831853f * uniform(rng), s = sqrtf(fmaxf(0.0f, 1.0f - z * z));
      lt_ray *ray = &out[(size_t)a * per_agent + r];
      *ray = (lt_ray){{pos[0], pos[1], pos[2]}, 0.0f, {s * cosf(phi), s * sinf(phi), z}, sqrtf(step)};
    }
  }
}

int lt_cmd_collide(lt_cli *cli) {
  lt_stats *stats, *frame_stats;
  lt_context *ctx;
  lt_scene *scene;
  if (lt_stats_create(&stats) || lt_stats_create(&frame_stats)) return lt_cli_fail("statistics", LT_ERROR_OUT_OF_MEMORY);
  if (lt_cli_open(cli, &ctx, &scene, stats)) return 1;
  size_t n = (size_t)cli->agents * cli->rays_per_agent;
  float *paths = malloc(6 * sizeof(float) * cli->agents);
  lt_ray *rays = malloc(n * sizeof *rays);
  lt_hit *hits = malloc(n * sizeof *hits);
  uint64_t rng = cli->seed;
  int rc = 1;
  if (!paths || !rays || !hits) {
    fprintf(stderr, "lazytrace collide: out of memory\n");
    goto done;
  }
  place_agents(scene, cli->agents, &rng, paths);

  /* Every frame rebuilds the structure from scratch, as moving geometry would require. */
  double build_sum = 0, trace_sum = 0, hits_sum = 0;
  fprintf(stderr, "frame  build_ms  trace_ms  total_ms  hits\n");
  for (int f = 0; f < cli->frames; f++) {
    lt_structure *structure;
    lt_stats_reset(frame_stats);
    frame_rays(paths, cli->agents, cli->rays_per_agent, f, cli->frames, &rng, rays);
    lt_status status = lt_structure_create(ctx, scene, &cli->structure, frame_stats, &structure);
    if (!status) status = lt_structure_trace(structure, rays, n, LT_QUERY_CLOSEST, hits, frame_stats);
    lt_structure_destroy(structure);
    if (status) {
      rc = lt_cli_fail("collision frame", status);
      goto done;
    }
    int frame_hits = 0;
    for (size_t i = 0; i < n; i++) frame_hits += hits[i].prim >= 0;
    double b = lt_stats_get(frame_stats, "build_ms"), t = lt_stats_get(frame_stats, "trace_ms");
    build_sum += b, trace_sum += t, hits_sum += frame_hits;
    fprintf(stderr, "%5d  %8.2f  %8.2f  %8.2f  %d\n", f, b, t, b + t, frame_hits);
  }
  fprintf(stderr, "lazytrace: %d frames of %zu rays: build %.1f ms, trace %.1f ms, %.0f hits\n", cli->frames, n,
          build_sum, trace_sum, hits_sum);

  /* Totals over all frames; the node and memory figures are those of the last frame. */
  for (const char *const *key = (const char *const[]){"triangles", "nodes_built", "nodes_full", "references",
                                                        "memory_bytes", "node_bytes", "reference_bytes", "pool_bytes",
                                                        "compile_ms", NULL};
       *key; key++)
    lt_stats_set(stats, *key, lt_stats_get(frame_stats, *key));
  lt_stats_set(stats, "build_ms", build_sum);
  lt_stats_set(stats, "trace_ms", trace_sum);
  lt_stats_set(stats, "total_ms", build_sum + trace_sum);
  lt_stats_set(stats, "rays", (double)n * cli->frames);
  rc = lt_cli_write_stats(cli, stats);

done:
  free(paths), free(rays), free(hits);
  lt_scene_destroy(scene);
  lt_context_destroy(ctx);
  lt_stats_destroy(stats);
  lt_stats_destroy(frame_stats);
  return rc;
}
