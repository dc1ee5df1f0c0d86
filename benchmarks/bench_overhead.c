/* The C side of the Python overhead benchmark (benchmarks/python_overhead.sh): the median time
 * of lt_structure_trace on the first N rays of a ray file, for each N given, on a fully built
 * BVH (so that every call does the same work), after one call that warms the structure up.
 *   bench_overhead SCENE RAYS DEVICE N:RUNS...     prints "N median_ms" per N */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "benchmarks/median.h"
#include "lazytrace.h"

static int fail(const char *what) {
  fprintf(stderr, "bench_overhead: %s: %s\n", what, lt_last_error());
  return 1;
}

int main(int argc, char **argv) {
  if (argc < 5) return fprintf(stderr, "usage: bench_overhead SCENE RAYS native|opencl N:RUNS...\n"), 2;
  enum { MAX_RUNS = 1000 };
  lt_ray *rays;
  size_t count;
  if (lt_rays_read(argv[2], &rays, &count)) return fail(argv[2]);
  lt_context_config cc = {.device = strcmp(argv[3], "opencl") == 0 ? LT_DEVICE_OPENCL : LT_DEVICE_NATIVE, .quiet = 1};
  lt_structure_config sc = lt_structure_config_default(LT_STRUCTURE_BVH);
  sc.build = LT_BUILD_FULL;
  lt_context *ctx;
  lt_scene *scene;
  lt_structure *bvh;
  if (lt_context_create(&cc, &ctx)) return fail("context");
  if (lt_scene_load(argv[1], &scene)) return fail(argv[1]);
  if (lt_structure_create(ctx, scene, &sc, NULL, &bvh)) return fail("structure");
  lt_hit *hits = malloc(count * sizeof *hits);
  double *ms = malloc(MAX_RUNS * sizeof *ms);
  if (!hits || !ms) return fprintf(stderr, "bench_overhead: out of memory\n"), 1;
  if (lt_structure_trace(bvh, rays, count, LT_QUERY_CLOSEST, hits, NULL)) return fail("warm-up trace");

  /* Each size in turn, timed call by call. */
  for (int a = 4; a < argc; a++) {
    char *colon;
    size_t n = strtoul(argv[a], &colon, 10);
    int runs = *colon == ':' ? atoi(colon + 1) : 0;
    if (n == 0 || n > count || runs < 1 || runs > MAX_RUNS)
      return fprintf(stderr, "bench_overhead: '%s': expected N:RUNS, N up to %zu, RUNS up to %d\n", argv[a], count,
                     MAX_RUNS),
             2;
    for (int r = 0; r < runs; r++) {
      double start = lt_now_ms();
      if (lt_structure_trace(bvh, rays, n, LT_QUERY_CLOSEST, hits, NULL)) return fail("trace");
      ms[r] = lt_now_ms() - start;
    }
    printf("%zu %.6f\n", n, lt_bench_median(ms, runs));
  }
  free(rays), free(hits), free(ms);
  lt_structure_destroy(bvh);
  lt_scene_destroy(scene);
  lt_context_destroy(ctx);
  return 0;
}
