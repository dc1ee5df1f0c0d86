/* The methods the benchmarks compare (methods.h). */
#include "benchmarks/methods.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *const lt_bench_method_names[LT_BENCH_METHODS] = {
    "full", "requested", "speculative", "lbvh", "kd-full", "kd-requested", "kd-speculative", "embree", "embree-low", "qbvh",
    "requested-morton", "speculative-morton"};

lt_context *lt_bench_native_context(void) {
  static lt_context *ctx;
  lt_context_config config = {LT_DEVICE_NATIVE, 0, 0, 0, 1};
  if (!ctx && lt_context_create(&config, &ctx) != LT_OK) return NULL;
  return ctx;
}

size_t lt_bench_table1_ao_rays(const lt_scene *scene, const lt_ray *primary, size_t n, int ao, lt_ray *ao_rays) {
  lt_hit *hits = malloc(n * sizeof *hits);
  if (!hits) return 0;
  lt_structure *full;
  lt_structure_config fc = lt_structure_config_default(LT_STRUCTURE_BVH);
  fc.build = LT_BUILD_FULL;
  float lo[3], hi[3];
  lt_scene_bounds(scene, lo, hi);
  float diag = sqrtf((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
  lt_structure_create(lt_bench_native_context(), scene, &fc, NULL, &full);
  lt_structure_trace(full, primary, n, LT_QUERY_CLOSEST, hits, NULL);
  lt_structure_destroy(full);
  size_t count = lt_ao_rays(scene, primary, hits, n, ao, 0.05f * diag, 1, ao_rays);
  free(hits);
  return count;
}

lt_context *lt_bench_context(void) {
  static lt_context *ctx;
  const char *device = getenv("LT_BENCH_DEVICE");
  if (!device || strcmp(device, "native") == 0) return lt_bench_native_context();
  if (strcmp(device, "opencl") != 0) {
    fprintf(stderr, "LT_BENCH_DEVICE=%s: expected native or opencl\n", device);
    return NULL;
  }
  lt_context_config config = {LT_DEVICE_OPENCL, 0, 0, 0, 1};
  if (!ctx && lt_context_create(&config, &ctx) != LT_OK) return NULL;
  return ctx;
}

lt_status lt_bench_build_and_trace(const lt_scene *scene, int method, const lt_bench_batch *batches, int count,
                                   lt_hit *hits, lt_stats *stats) {
  lt_structure_config config = lt_bench_method_config(method);
  lt_structure *s = NULL;
  lt_context *ctx = lt_bench_context();
  lt_status status = ctx ? lt_structure_create(ctx, scene, &config, stats, &s) : LT_ERROR_INVALID_ARGUMENT;
  for (int b = 0; !status && b < count; b++)
    status = lt_structure_trace(s, batches[b].rays, batches[b].count, batches[b].any ? LT_QUERY_ANY : LT_QUERY_CLOSEST,
                                hits, stats);
  if (status) fprintf(stderr, "%s: %s\n", lt_bench_method_names[method], lt_last_error());
  lt_structure_destroy(s);
  return status;
}

lt_structure_config lt_bench_method_config(int method) {
  int kd = method >= LT_BENCH_KD_FULL && method <= LT_BENCH_KD_SPECULATIVE;
  int morton = method == LT_BENCH_REQUESTED_MORTON || method == LT_BENCH_SPECULATIVE_MORTON;
  int mode = kd ? method - LT_BENCH_KD_FULL : morton ? method - LT_BENCH_REQUESTED_MORTON + LT_BENCH_REQUESTED : method;
  lt_build_mode build = mode == LT_BENCH_REQUESTED     ? LT_BUILD_REQUESTED
                        : mode == LT_BENCH_SPECULATIVE ? LT_BUILD_SPECULATIVE
                                                       : LT_BUILD_FULL;
  lt_structure_kind kind = kd                        ? LT_STRUCTURE_KDTREE
                           : method == LT_BENCH_LBVH ? LT_STRUCTURE_LBVH
                           : method == LT_BENCH_QBVH ? LT_STRUCTURE_QBVH
                                                     : LT_STRUCTURE_BVH;
  lt_structure_config config = lt_structure_config_default(kind);
  config.build = build;
  if (morton) config.bvh_top = LT_BVH_TOP_MORTON;
  return config;
}
