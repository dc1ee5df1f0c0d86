/* lazytrace render: the effects the scene calls for (a scene file's "effects", primary rays for
 * generators and mesh files), traced as batches through one structure, written as a PNG. With
 * --frames N, an animation: the scene is moved to each frame's time, the structure rebuilt
 * from scratch and each frame written as its own PNG, with statistics per frame. */
#include <stdlib.h>
#include <string.h>

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

/* What one image needs: the render's settings and the buffers it fills. */
typedef struct picture {
  lt_render_config config;
  int width, height, spp;
  float *image;
  unsigned char *rgb;
} picture;

/* Builds the structure over the scene as it is now, renders it and writes the PNG to path;
 * statistics go to stats. verbose: say what was built and traced (an animation says it once
 * per frame instead). Returns 0 on success, after printing why otherwise. */
static int render_image(lt_cli *cli, lt_context *ctx, const lt_scene *scene, picture *pic, const char *path,
                        lt_stats *stats, int verbose) {
  lt_structure *structure = NULL;
  lt_status status = lt_structure_create(ctx, scene, &cli->structure, stats, &structure);
  if (status) return lt_cli_fail("building the structure", status);
  if (verbose && cli->structure.build == LT_BUILD_FULL)
    fprintf(stderr, "lazytrace: %s built in full on %s in %.0f ms (kernels compiled in %.0f ms)\n",
            lt_structure_kind_name(cli->structure.kind), lt_context_device_name(ctx), lt_stats_get(stats, "build_ms"),
            lt_context_compile_ms(ctx));
  else if (verbose)
    fprintf(stderr, "lazytrace: %s to be built on demand (%s) on %s (kernels compiled in %.0f ms)\n",
            lt_structure_kind_name(cli->structure.kind), lt_build_mode_name(cli->structure.build),
            lt_context_device_name(ctx), lt_context_compile_ms(ctx));
  status = lt_render(structure, scene, &pic->config, pic->image, stats);
  lt_structure_destroy(structure);
  if (status) return lt_cli_fail("rendering", status);
  if (verbose) {
    say_rays(stats);
    fprintf(stderr, "lazytrace: %.0f rays: time to image %.0f ms (build %.0f, trace %.0f); %.0f nodes built\n",
            lt_stats_get(stats, "rays"), lt_stats_get(stats, "total_ms"), lt_stats_get(stats, "build_ms"),
            lt_stats_get(stats, "trace_ms"), lt_stats_get(stats, "nodes_built"));
  }

  /* Gamma-correct output: the image is linear radiance, the PNG sRGB. */
  size_t n = (size_t)pic->width * pic->height;
  lt_image_to_srgb8(pic->image, n, pic->rgb);
  if (lt_write_png(path, pic->width, pic->height, pic->rgb) != 0) {
    fprintf(stderr, "lazytrace render: %s: could not write the PNG\n", path);
    return 1;
  }
  if (verbose)
    fprintf(stderr, "lazytrace: wrote %s (%dx%d, %d sample%s per pixel)\n", path, pic->width, pic->height, pic->spp,
            pic->spp == 1 ? "" : "s");
  return 0;
}

/* Frame f's file: the output with _NNNN before its extension (out.png: out_0000.png). */
static void frame_path(const char *output, int frame, char *path, size_t size) {
  const char *slash = strrchr(output, '/'), *dot = strrchr(output, '.');
  if (!dot || (slash && dot < slash) || dot == output || (slash && dot == slash + 1)) dot = output + strlen(output);
  snprintf(path, size, "%.*s_%04d%s", (int)(dot - output), output, frame, *dot ? dot : ".png");
}

/* The counters an animation's statistics give as totals over its frames; every other value is
 * the last frame's (the structure's size, memory, the batches). */
static const char *const summed_keys[] = {
    "rays", "build_ms", "trace_ms", "total_ms", "nodes_built", "sort_ops", "traversal_steps", "intersections",
    "rays_by_effect.primary", "rays_by_effect.shadows", "rays_by_effect.ao", "rays_by_effect.diffuse",
    "rays_by_effect.mirror", "rays_by_effect.collision", "ms_by_effect.primary", "ms_by_effect.shadows",
    "ms_by_effect.ao", "ms_by_effect.diffuse", "ms_by_effect.mirror", "ms_by_effect.collision", NULL};

/* The animation: every frame moves the scene, rebuilds the structure from scratch and writes
 * its image; stats get one record per frame and the totals. */
static int render_frames(lt_cli *cli, lt_context *ctx, lt_scene *scene, picture *pic, const char *output,
                         lt_stats *stats) {
  lt_stats *frame_stats;
  if (lt_stats_create(&frame_stats)) return lt_cli_fail("statistics", LT_ERROR_OUT_OF_MEMORY);
  enum { KEYS = sizeof summed_keys / sizeof *summed_keys - 1 };
  double sums[KEYS];
  for (int k = 0; k < KEYS; k++) sums[k] = -1.0;
  int frames = cli->frames, rc = 0;
  if (!lt_scene_is_animated(scene))
    fprintf(stderr, "lazytrace: note: the scene does not move; every frame rebuilds the same triangles\n");
  fprintf(stderr, "lazytrace: %d frames of %s (%s) on %s, each rebuilt from scratch\n", frames,
          lt_structure_kind_name(cli->structure.kind), lt_build_mode_name(cli->structure.build),
          lt_context_device_name(ctx));
  fprintf(stderr, "frame  build_ms  trace_ms  total_ms  nodes_built  image\n");
  for (int f = 0; f < frames && !rc; f++) {
    char path[4096];
    frame_path(output, f, path, sizeof path);
    lt_scene_set_time(scene, lt_frame_time(f, frames));
    lt_stats_reset(frame_stats);
    rc = render_image(cli, ctx, scene, pic, path, frame_stats, 0);
    if (rc) break;
    lt_stats_add_frame(stats, frame_stats);
    for (int k = 0; k < KEYS; k++) {
      double v = lt_stats_get(frame_stats, summed_keys[k]);
      if (v >= 0) sums[k] = (sums[k] < 0 ? 0 : sums[k]) + v;
    }
    fprintf(stderr, "%5d  %8.1f  %8.1f  %8.1f  %11.0f  %s\n", f, lt_stats_get(frame_stats, "build_ms"),
            lt_stats_get(frame_stats, "trace_ms"), lt_stats_get(frame_stats, "total_ms"),
            lt_stats_get(frame_stats, "nodes_built"), path);
  }
  if (!rc) {
    double load_ms = lt_stats_get(stats, "load_ms");
    lt_stats_copy(stats, frame_stats);
    lt_stats_set(stats, "load_ms", load_ms);
    for (int k = 0; k < KEYS; k++) lt_stats_set(stats, summed_keys[k], sums[k]);
    fprintf(stderr, "lazytrace: %d frames, %.0f rays: time to image %.1f ms per frame (build %.1f, trace %.1f)\n",
            frames, sums[0], sums[3] / frames, sums[1] / frames, sums[2] / frames);
  }
  lt_stats_destroy(frame_stats);
  return rc;
}

int lt_cmd_render(lt_cli *cli) {
  lt_stats *stats;
  lt_context *ctx;
  lt_scene *scene;
  if (lt_stats_create(&stats)) return lt_cli_fail("statistics", LT_ERROR_OUT_OF_MEMORY);
  if (lt_cli_open(cli, &ctx, &scene, stats)) return lt_stats_destroy(stats), 1;
  const char *output = cli->output ? cli->output : "render.png";
  picture pic = {{cli->size_given ? cli->width : 0, cli->size_given ? cli->height : 0, cli->spp, NULL, cli->seed, 0, 1},
                 0, 0, 0, NULL, NULL};
  lt_render_size(scene, &pic.config, &pic.width, &pic.height, &pic.spp);
  size_t n = (size_t)pic.width * pic.height;
  pic.image = malloc(3 * n * sizeof *pic.image);
  pic.rgb = malloc(3 * n);
  int rc = 1;
  if (!pic.image || !pic.rgb) fprintf(stderr, "lazytrace render: out of memory for %dx%d\n", pic.width, pic.height);
  else if (cli->frames_given) rc = render_frames(cli, ctx, scene, &pic, output, stats);
  else rc = render_image(cli, ctx, scene, &pic, output, stats, 1);
  if (!rc) rc = lt_cli_write_stats(cli, stats);

  free(pic.image), free(pic.rgb);
  lt_scene_destroy(scene);
  lt_context_destroy(ctx);
  lt_stats_destroy(stats);
  return rc;
}
