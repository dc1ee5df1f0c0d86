/* lazytrace trace: answers a ray file and writes a hit file. */
#include <stdlib.h>

#include "apps/cli.h"

int lt_cmd_trace(lt_cli *cli) {
  if (!cli->rays || !cli->hits)
    return fprintf(stderr, "lazytrace trace: --rays RAYS and --hits HITS are required (run 'lazytrace help trace')\n"), 2;
  lt_ray *rays;
  size_t n;
  lt_status status = lt_rays_read(cli->rays, &rays, &n);
  if (status) return lt_cli_fail("reading rays", status);

  lt_stats *stats;
  lt_context *ctx;
  lt_scene *scene;
  lt_structure *structure = NULL;
  lt_hit *hits = malloc((n ? n : 1) * sizeof *hits);
  if (!hits || lt_stats_create(&stats)) return free(rays), free(hits), lt_cli_fail("allocating", LT_ERROR_OUT_OF_MEMORY);
  if (lt_cli_open(cli, &ctx, &scene, stats)) return free(rays), free(hits), lt_stats_destroy(stats), 1;
  int rc = 1;
  status = lt_structure_create(ctx, scene, &cli->structure, stats, &structure);
  if (status) {
    rc = lt_cli_fail("building the structure", status);
    goto done;
  }
  status = lt_structure_trace(structure, rays, n, cli->any ? LT_QUERY_ANY : LT_QUERY_CLOSEST, hits, stats);
  if (status) {
    rc = lt_cli_fail("tracing", status);
    goto done;
  }
  lt_stats_set(stats, "rays", (double)n);
  status = lt_hits_write(cli->hits, hits, n);
  if (status) {
    rc = lt_cli_fail("writing hits", status);
    goto done;
  }
  fprintf(stderr, "lazytrace: %zu rays traced in %.1f ms on %s; hits in %s\n", n, lt_stats_get(stats, "trace_ms"),
          lt_context_device_name(ctx), cli->hits);
  rc = lt_cli_write_stats(cli, stats);

done:
  free(rays), free(hits);
  lt_structure_destroy(structure);
  lt_scene_destroy(scene);
  lt_context_destroy(ctx);
  lt_stats_destroy(stats);
  return rc;
}
