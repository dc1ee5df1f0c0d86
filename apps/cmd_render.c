/* lazytrace render: primary rays from the scene's camera, shaded by the angle to the view. */
#include <math.h>
#include <stdlib.h>

#include "apps/cli.h"

/* Grey shading by |cos| between the view ray and the geometric normal, sky blue on a miss. */
static void shade(const lt_scene *scene, const lt_ray *ray, const lt_hit *hit, unsigned char *rgb) {
  if (hit->prim < 0) {
    float up = 0.5f + 0.5f * ray->dir[1] / sqrtf(ray->dir[0] * ray->dir[0] + ray->dir[1] * ray->dir[1] + ray->dir[2] * ray->dir[2]);
    rgb[0] = (unsigned char)(160 + 60 * up), rgb[1] = (unsigned char)(190 + 40 * up), rgb[2] = 235;
    return;
  }
  const float *t = lt_scene_triangles(scene) + 9 * (size_t)hit->prim;
  float e1[3], e2[3], n[3];
  for (int k = 0; k < 3; k++) e1[k] = t[3 + k] - t[k], e2[k] = t[6 + k] - t[k];
  n[0] = e1[1] * e2[2] - e1[2] * e2[1];
  n[1] = e1[2] * e2[0] - e1[0] * e2[2];
  n[2] = e1[0] * e2[1] - e1[1] * e2[0];
  float nl = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  float dl = sqrtf(ray->dir[0] * ray->dir[0] + ray->dir[1] * ray->dir[1] + ray->dir[2] * ray->dir[2]);
  float c = nl > 0 ? fabsf(n[0] * ray->dir[0] + n[1] * ray->dir[1] + n[2] * ray->dir[2]) / (nl * dl) : 0.0f;
  float v = 0.12f + 0.88f * c;
  rgb[0] = (unsigned char)(255 * v * 0.95f), rgb[1] = (unsigned char)(255 * v * 0.90f), rgb[2] = (unsigned char)(255 * v * 0.82f);
}

int lt_cmd_render(lt_cli *cli) {
  lt_stats *stats;
  lt_context *ctx;
  lt_scene *scene;
  lt_structure *structure = NULL;
  if (lt_stats_create(&stats)) return lt_cli_fail("statistics", LT_ERROR_OUT_OF_MEMORY);
  if (lt_cli_open(cli, &ctx, &scene, stats)) return lt_stats_destroy(stats), 1;
  const char *output = cli->output ? cli->output : "render.png";
  size_t n = (size_t)cli->width * cli->height;
  lt_ray *rays = malloc(n * sizeof *rays);
  lt_hit *hits = malloc(n * sizeof *hits);
  unsigned char *rgb = malloc(3 * n);
  int rc = 1;
  if (!rays || !hits || !rgb) {
    fprintf(stderr, "lazytrace render: out of memory for %dx%d\n", cli->width, cli->height);
    goto done;
  }

  /* Build, then trace the primary rays. */
  lt_status status = lt_structure_create(ctx, scene, &cli->structure, stats, &structure);
  if (status) {
    rc = lt_cli_fail("building the structure", status);
    goto done;
  }
  if (cli->structure.build == LT_BUILD_FULL)
    fprintf(stderr, "lazytrace: %s built in full on %s in %.0f ms (kernels compiled in %.0f ms)\n",
            lt_structure_kind_name(cli->structure.kind), lt_context_device_name(ctx), lt_stats_get(stats, "build_ms"),
            lt_context_compile_ms(ctx));
  else
    fprintf(stderr, "lazytrace: %s to be built on demand (%s) on %s (kernels compiled in %.0f ms)\n",
            lt_structure_kind_name(cli->structure.kind), lt_build_mode_name(cli->structure.build),
            lt_context_device_name(ctx), lt_context_compile_ms(ctx));
  lt_camera camera = lt_scene_camera(scene);
  lt_camera_primary_rays(&camera, cli->width, cli->height, rays);
  status = lt_structure_trace(structure, rays, n, LT_QUERY_CLOSEST, hits, stats);
  if (status) {
    rc = lt_cli_fail("tracing", status);
    goto done;
  }
  fprintf(stderr, "lazytrace: %zu primary rays: time to image %.0f ms (build %.0f, trace %.0f); %.0f nodes built\n", n,
          lt_stats_get(stats, "total_ms"), lt_stats_get(stats, "build_ms"), lt_stats_get(stats, "trace_ms"),
          lt_stats_get(stats, "nodes_built"));

  /* Shade and write. */
  for (size_t i = 0; i < n; i++) shade(scene, &rays[i], &hits[i], rgb + 3 * i);
  if (lt_write_png(output, cli->width, cli->height, rgb) != 0) {
    fprintf(stderr, "lazytrace render: %s: could not write the PNG\n", output);
    goto done;
  }
  fprintf(stderr, "lazytrace: wrote %s (%dx%d)\n", output, cli->width, cli->height);
  rc = lt_cli_write_stats(cli, stats);

done:
  free(rays), free(hits), free(rgb);
  lt_structure_destroy(structure);
  lt_scene_destroy(scene);
  lt_context_destroy(ctx);
  lt_stats_destroy(stats);
  return rc;
}
