/* lazytrace render: the effects the scene calls for (a scene file's "effects", primary rays for
 * generators and mesh files), traced as batches through one structure, written as a PNG. */
#include <stdlib.h>

#include "apps/cli.h"

/* One line of what was traced, effects not called for left out. */
static void say_rays(const lt_stats *stats) {
  static const char *const effects[] = {"primary", "shadows", "ao", "diffuse", "mirror", "collision"};
  fprintf(stderr, "lazytrace: rays by effect:");
  for (int e = 0; e < 6; e++) {
    char key[64];
    snprintf(key, sizeof key, "rays_by_effect.%s", effects[e]);
    double n = lt_stats_get(stats, key);
    snprintf(key, sizeof key, "ms_by_effect.%s", effects[e]);
    if (n > 0) fprintf(stderr, " %s %.0f (%.0f ms)", effects[e], n, lt_stats_get(stats, key));
  }
  fputc('\n', stderr);
}

int lt_cmd_render(lt_cli *cli) {
  lt_stats *stats;
  lt_context *ctx;
  lt_scene *scene;
  lt_structure *structure = NULL;
  float *image = NULL;
  unsigned char *rgb = NULL;
  if (lt_stats_create(&stats)) return lt_cli_fail("statistics", LT_ERROR_OUT_OF_MEMORY);
  if (lt_cli_open(cli, &ctx, &scene, stats)) return lt_stats_destroy(stats), 1;
  const char *output = cli->output ? cli->output : "render.png";
  lt_render_config config = {cli->size_given ? cli->width : 0, cli->size_given ? cli->height : 0, cli->spp, NULL,
                             cli->seed, 0, 1};
  int width, height, spp;
  lt_render_size(scene, &config, &width, &height, &spp);
  size_t n = (size_t)width * height;
  image = malloc(3 * n * sizeof *image);
  rgb = malloc(3 * n);
  int rc = 1;
  if (!image || !rgb) {
    fprintf(stderr, "lazytrace render: out of memory for %dx%d\n", width, height);
    goto done;
  }

  /* Build (or prepare to build on demand), then trace the effects' batches. */
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
  status = lt_render(structure, scene, &config, image, stats);
  if (status) {
    rc = lt_cli_fail("rendering", status);
    goto done;
  }
  say_rays(stats);
  fprintf(stderr, "lazytrace: %.0f rays: time to image %.0f ms (build %.0f, trace %.0f); %.0f nodes built\n",
          lt_stats_get(stats, "rays"), lt_stats_get(stats, "total_ms"), lt_stats_get(stats, "build_ms"),
          lt_stats_get(stats, "trace_ms"), lt_stats_get(stats, "nodes_built"));

  /* Gamma-correct output: the image is linear radiance, the PNG sRGB. */
  lt_image_to_srgb8(image, n, rgb);
  if (lt_write_png(output, width, height, rgb) != 0) {
    fprintf(stderr, "lazytrace render: %s: could not write the PNG\n", output);
    goto done;
  }
  fprintf(stderr, "lazytrace: wrote %s (%dx%d, %d sample%s per pixel)\n", output, width, height, spp,
          spp == 1 ? "" : "s");
  rc = lt_cli_write_stats(cli, stats);

done:
  free(image), free(rgb);
  lt_structure_destroy(structure);
  lt_scene_destroy(scene);
  lt_context_destroy(ctx);
  lt_stats_destroy(stats);
  return rc;
}
