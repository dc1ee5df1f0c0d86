/* The on-demand paper's Figure 6 in shape (Vinkler et al. 2016, section 5.2): time to image
 * against the number of diffuse samples per pixel, the structure built in full against built
 * on demand. Every image is rendered by lt_render from a scene's effects (primary rays, then
 * `samples` cosine-sampled diffuse rays per primary hit, one bounce, light from the sky), so
 * the batches are those `lazytrace render` traces.
 *
 *   bench_diffuse [--runs R] [--size N] [--samples 1,2,4,...] [--csv FILE] [SCENE]
 *
 * Methods: SAH BVH full, requested, speculative, and the LBVH (the paper's HLBVH row). Time to
 * image is build plus trace over all batches (statistics total_ms: for on-demand builds the
 * launches that built and traced, without the retrace that measures trace time). Medians of
 * R runs, methods interleaved run by run; every on-demand image is checked against the full
 * build's, byte for byte. Markdown goes to stdout, CSV to --csv. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lazytrace.h"
#include "benchmarks/median.h"
#include "benchmarks/methods.h"

#define MAX_RUNS    16
#define MAX_SAMPLES 16
#define METHODS 4 /* full, requested, speculative, LBVH: no Embree here */
enum { FULL = LT_BENCH_FULL, REQUESTED = LT_BENCH_REQUESTED, SPECULATIVE = LT_BENCH_SPECULATIVE, LBVH = LT_BENCH_LBVH };

typedef struct figures {
  double total[MAX_RUNS], build[MAX_RUNS], trace[MAX_RUNS];
  double nodes, rays, diffuse_rays;
} figures;

/* One render with one method; the image lands in image. */
static int run_method(lt_context *ctx, const lt_scene *scene, int method, const lt_render_config *config, float *image,
                      figures *f, int run) {
  lt_structure_config sc = lt_bench_method_config(method);
  lt_stats *stats;
  lt_structure *s = NULL;
  lt_stats_create(&stats);
  lt_status status = lt_structure_create(ctx, scene, &sc, stats, &s);
  if (!status) status = lt_render(s, scene, config, image, stats);
  lt_structure_destroy(s);
  if (status) {
    fprintf(stderr, "%s: %s\n", lt_bench_method_names[method], lt_last_error());
    lt_stats_destroy(stats);
    return 1;
  }
  f->total[run] = lt_stats_get(stats, "total_ms");
  f->build[run] = lt_stats_get(stats, "build_ms");
  f->trace[run] = lt_stats_get(stats, "trace_ms");
  f->nodes = lt_stats_get(stats, "nodes_built");
  f->rays = lt_stats_get(stats, "rays");
  f->diffuse_rays = lt_stats_get(stats, "rays_by_effect.diffuse");
  lt_stats_destroy(stats);
  return 0;
}

static int parse_samples(const char *text, int *out) {
  int n = 0;
  for (const char *p = text; *p && n < MAX_SAMPLES;) {
    char *end;
    long v = strtol(p, &end, 10);
    if (end == p || v < 1 || v > 4096) return 0;
    out[n++] = (int)v;
    p = *end == ',' ? end + 1 : end;
    if (*end && *end != ',') return 0;
  }
  return n;
}

int main(int argc, char **argv) {
  int runs = 3, size = 256, samples[MAX_SAMPLES] = {1, 2, 4, 8, 16, 32, 64}, nsamples = 7;
  const char *csv_path = NULL, *spec = "house-grid:3x3";
  for (int i = 1; i < argc; i++) {
    if (strcmp(argv[i], "--runs") == 0 && i + 1 < argc) runs = atoi(argv[++i]);
    else if (strcmp(argv[i], "--size") == 0 && i + 1 < argc) size = atoi(argv[++i]);
    else if (strcmp(argv[i], "--samples") == 0 && i + 1 < argc) nsamples = parse_samples(argv[++i], samples);
    else if (strcmp(argv[i], "--csv") == 0 && i + 1 < argc) csv_path = argv[++i];
    else if (argv[i][0] != '-') spec = argv[i];
    else return fprintf(stderr, "bench_diffuse: unknown option %s\n", argv[i]), 2;
  }
  if (runs < 1 || runs > MAX_RUNS || size < 1 || nsamples < 1)
    return fprintf(stderr, "bench_diffuse: bad option value\n"), 2;

  lt_context *ctx;
  lt_context_config cc = {LT_DEVICE_NATIVE, 0, 0, 0, 1};
  lt_scene *scene;
  if (lt_context_create(&cc, &ctx) || lt_scene_load(spec, &scene)) return fprintf(stderr, "%s\n", lt_last_error()), 1;
  fprintf(stderr, "%s: %zu triangles, %dx%d\n", spec, lt_scene_triangle_count(scene), size, size);
  FILE *csv = csv_path ? fopen(csv_path, "w") : NULL;
  if (csv) fprintf(csv, "samples,rays,full_ms,requested_ms,speculative_ms,lbvh_ms,full_nodes,requested_nodes,"
                        "speculative_nodes,full_mrays_s,requested_mrays_s,speculative_mrays_s,lbvh_mrays_s\n");

  printf("| diffuse samples | rays | full ms | requested ms | speculative ms | LBVH ms | requested / full |"
         " speculative / full | full Mrays/s | speculative Mrays/s | nodes requested / full | nodes speculative / full |\n");
  printf("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  size_t pixels = (size_t)size * size;
  float *reference = malloc(3 * pixels * sizeof(float)), *image = malloc(3 * pixels * sizeof(float));
  int rc = 0;
  for (int s = 0; s < nsamples && !rc; s++) {
    lt_effects fx = {.primary = 1, .diffuse_samples = samples[s], .diffuse_bounces = 1};
    lt_render_config config = {size, size, 1, &fx, 1, 0, 0};
    figures f[METHODS];
    memset(f, 0, sizeof f);

    /* Methods interleaved run by run; each on-demand image must equal the full build's. */
    for (int run = 0; run < runs && !rc; run++)
      for (int m = 0; m < METHODS && !rc; m++) {
        rc = run_method(ctx, scene, m, &config, m == FULL ? reference : image, &f[m], run);
        if (!rc && m != FULL && m != LBVH && memcmp(reference, image, 3 * pixels * sizeof(float)) != 0)
          rc = (fprintf(stderr, "%s: image differs from the full build's\n", lt_bench_method_names[m]), 1);
        if (!rc) fprintf(stderr, "  %2d samples %-11s run %d: %8.1f ms\n", samples[s], lt_bench_method_names[m], run + 1,
                         f[m].total[run]);
      }
    if (rc) break;
    double ms[METHODS];
    for (int m = 0; m < METHODS; m++) ms[m] = lt_bench_median(f[m].total, runs);
    double rays = f[FULL].rays;
    printf("| %d | %.2fM | %.0f | %.0f | %.0f | %.0f | %.2f | %.2f | %.2f | %.2f | %.1f%% | %.1f%% |\n", samples[s],
           rays / 1e6, ms[FULL], ms[REQUESTED], ms[SPECULATIVE], ms[LBVH], ms[REQUESTED] / ms[FULL],
           ms[SPECULATIVE] / ms[FULL], rays / ms[FULL] / 1e3, rays / ms[SPECULATIVE] / 1e3,
           100.0 * f[REQUESTED].nodes / f[FULL].nodes, 100.0 * f[SPECULATIVE].nodes / f[FULL].nodes);
    fflush(stdout);
    if (csv)
      fprintf(csv, "%d,%.0f,%.2f,%.2f,%.2f,%.2f,%.0f,%.0f,%.0f,%.3f,%.3f,%.3f,%.3f\n", samples[s], rays, ms[FULL],
              ms[REQUESTED], ms[SPECULATIVE], ms[LBVH], f[FULL].nodes, f[REQUESTED].nodes, f[SPECULATIVE].nodes,
              rays / ms[FULL] / 1e3, rays / ms[REQUESTED] / 1e3, rays / ms[SPECULATIVE] / 1e3, rays / ms[LBVH] / 1e3);
  }
  if (csv) fclose(csv);
  free(reference), free(image);
  lt_scene_destroy(scene);
  lt_context_destroy(ctx);
  return rc;
}
