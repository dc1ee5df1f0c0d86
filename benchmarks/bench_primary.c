/* Primary rays with the full SAH BVH on both backends and, where installed, Embree 3 on the
 * same triangles and rays with the same thread count. Prints a markdown table of medians.
 *
 *   bench_primary [SCENE] [--size N] [--runs R]     (defaults: house-grid:3x3, 1024, 5)
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lazytrace.h"
#ifdef LT_HAVE_EMBREE
#include "benchmarks/embree_peer.h"
#include "benchmarks/median.h"
#endif

#define MAX_RUNS 64

typedef struct row {
  const char *name;
  double build[MAX_RUNS], trace[MAX_RUNS];
  double compile_ms;
  int ok;
} row;

static void print_row(row *r, int runs, size_t rays, double embree_total) {
  double b = lt_bench_median(r->build, runs), t = lt_bench_median(r->trace, runs);
  printf("| %s | %.1f | %.1f | %.1f | %.2f |", r->name, b, t, b + t, rays / 1e3 / t);
  if (embree_total > 0) printf(" %.2fx |\n", (b + t) / embree_total);
  else printf(" - |\n");
}

/* Builds and traces with lazytrace on one backend, `runs` times. */
static int run_lazytrace(const lt_scene *scene, lt_device_kind kind, const lt_ray *rays, size_t n, int runs,
                         row *r, lt_hit *hits) {
  lt_context *ctx;
  lt_context_config config = {kind, 0, 0, 0, 1};
  if (lt_context_create(&config, &ctx) != LT_OK) return fprintf(stderr, "%s: %s\n", r->name, lt_last_error()), 1;
  for (int i = 0; i < runs; i++) {
    lt_stats *stats;
    lt_structure *bvh;
    lt_structure_config full = lt_structure_config_default(LT_STRUCTURE_BVH);
    full.build = LT_BUILD_FULL;
    lt_stats_create(&stats);
    if (lt_structure_create(ctx, scene, &full, stats, &bvh) != LT_OK ||
        lt_structure_trace(bvh, rays, n, LT_QUERY_CLOSEST, hits, stats) != LT_OK) {
      fprintf(stderr, "%s: %s\n", r->name, lt_last_error());
      return 1;
    }
    r->build[i] = lt_stats_get(stats, "build_ms");
    r->trace[i] = lt_stats_get(stats, "trace_ms");
    lt_structure_destroy(bvh);
    lt_stats_destroy(stats);
    fprintf(stderr, "  %s run %d: build %.1f ms, trace %.1f ms\n", r->name, i + 1, r->build[i], r->trace[i]);
  }
  r->compile_ms = lt_context_compile_ms(ctx);
  r->ok = 1;
  lt_context_destroy(ctx);
  return 0;
}

int main(int argc, char **argv) {
  const char *spec = "house-grid:3x3";
  int size = 1024, runs = 5;
  for (int i = 1; i < argc; i++) {
    if (strcmp(argv[i], "--size") == 0 && i + 1 < argc) size = atoi(argv[++i]);
    else if (strcmp(argv[i], "--runs") == 0 && i + 1 < argc) runs = atoi(argv[++i]);
    else if (argv[i][0] != '-') spec = argv[i];
    else return fprintf(stderr, "usage: bench_primary [SCENE] [--size N] [--runs R]\n"), 2;
  }
  if (runs < 1 || runs > MAX_RUNS || size < 1) return fprintf(stderr, "bench_primary: bad --runs or --size\n"), 2;

  lt_scene *scene;
  if (lt_scene_load(spec, &scene) != LT_OK) return fprintf(stderr, "%s\n", lt_last_error()), 1;
  size_t n = (size_t)size * size;
  lt_ray *rays = malloc(n * sizeof *rays);
  lt_hit *hits_cl = malloc(n * sizeof(lt_hit)), *hits_native = malloc(n * sizeof(lt_hit));
  lt_camera camera = lt_scene_camera(scene);
  lt_camera_primary_rays(&camera, size, size, rays);

  row opencl = {"lazytrace BVH, OpenCL (PoCL)", {0}, {0}, 0, 0}, native = {"lazytrace BVH, native", {0}, {0}, 0, 0};
  run_lazytrace(scene, LT_DEVICE_OPENCL, rays, n, runs, &opencl, hits_cl);
  run_lazytrace(scene, LT_DEVICE_NATIVE, rays, n, runs, &native, hits_native);

  /* Embree with as many threads as the native backend runs work-groups. */
  double embree_total = 0;
  row embree = {"Embree 3 (robust)", {0}, {0}, 0, 0};
#ifdef LT_HAVE_EMBREE
  lt_hit *hits_embree = malloc(n * sizeof(lt_hit));
  lt_context *probe;
  lt_context_config native_config = {LT_DEVICE_NATIVE, 0, 0, 0, 1};
  lt_context_create(&native_config, &probe);
  int threads = atoi(strstr(lt_context_device_name(probe), "(") + 1);
  lt_context_destroy(probe);
  for (int i = 0; i < runs; i++) {
    lt_embree_times t;
    if (lt_embree_run(scene, rays, n, threads, hits_embree, &t) != 0) break;
    embree.build[i] = t.build_ms, embree.trace[i] = t.trace_ms, embree.ok = 1;
    fprintf(stderr, "  Embree run %d: build %.1f ms, trace %.1f ms\n", i + 1, t.build_ms, t.trace_ms);
  }
  if (embree.ok) {
    double b[MAX_RUNS], t[MAX_RUNS];
    memcpy(b, embree.build, sizeof b), memcpy(t, embree.trace, sizeof t);
    embree_total = lt_bench_median(b, runs) + lt_bench_median(t, runs);
  }
#endif

  /* The table: medians over the runs, ratios of time to image against Embree. */
  printf("Scene `%s`: %zu triangles, %dx%d primary rays from the `outer` camera, %d runs, medians.\n\n", spec,
         lt_scene_triangle_count(scene), size, size, runs);
  printf("| method | build ms | trace ms | build + trace ms | Mrays/s (trace) | time vs Embree |\n");
  printf("|---|---:|---:|---:|---:|---:|\n");
  if (opencl.ok) print_row(&opencl, runs, n, embree_total);
  if (native.ok) print_row(&native, runs, n, embree_total);
  if (embree.ok) print_row(&embree, runs, n, embree_total);
  printf("\n");
  if (opencl.ok) printf("OpenCL kernel compile time (not included above): %.0f ms.\n", opencl.compile_ms);
  if (opencl.ok && native.ok)
    printf("OpenCL and native hits are %s.\n", memcmp(hits_cl, hits_native, n * sizeof(lt_hit)) == 0 ? "byte-identical" : "DIFFERENT");
#ifdef LT_HAVE_EMBREE
  if (embree.ok && (native.ok || opencl.ok)) {
    const lt_hit *ours = native.ok ? hits_native : hits_cl;
    size_t same_prim = 0, both_miss = 0;
    for (size_t i = 0; i < n; i++) {
      same_prim += ours[i].prim == hits_embree[i].prim && ours[i].prim >= 0;
      both_miss += ours[i].prim < 0 && hits_embree[i].prim < 0;
    }
    printf("Embree agrees on the hit triangle for %.3f%% of the rays (%zu hits, %zu misses in common).\n",
           100.0 * (same_prim + both_miss) / n, same_prim, both_miss);
  }
  free(hits_embree);
#endif
  free(rays), free(hits_cl), free(hits_native);
  lt_scene_destroy(scene);
  return 0;
}
