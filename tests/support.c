/* Helpers shared by the tests (see support.h). */
#include "tests/support.h"

#include <math.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>

void lt_test_random_rays(const lt_scene *scene, uint64_t seed, size_t n, lt_ray *out) {
  float lo[3], hi[3];
  lt_scene_bounds(scene, lo, hi);
  for (int k = 0; k < 3; k++) {
    float pad = 0.1f * (hi[k] - lo[k]);
    lo[k] -= pad, hi[k] += pad;
  }
  for (size_t i = 0; i < n; i++) {
    float a[3], b[3];
    for (int k = 0; k < 3; k++) {
      a[k] = lo[k] + lt__splitmix_unit(&seed) * (hi[k] - lo[k]);
      b[k] = lo[k] + lt__splitmix_unit(&seed) * (hi[k] - lo[k]);
    }
    out[i] = (lt_ray){{a[0], a[1], a[2]}, 0.0f, {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, INFINITY};
  }
}

void lt_test_camera_rays(const lt_scene *scene, const char *camera, int width, int height, lt_ray *out) {
  lt_camera cam;
  if (lt_scene_named_camera(scene, camera, &cam) != LT_OK) cam = lt_scene_camera(scene);
  lt_camera_primary_rays(&cam, width, height, out);
}

size_t lt_test_count_mismatches(const char *what, const lt_hit *a, const lt_hit *b, size_t n) {
  size_t bad = 0;
  for (size_t i = 0; i < n; i++) {
    int same = a[i].prim == b[i].prim && (a[i].prim < 0 || memcmp(&a[i].t, &b[i].t, sizeof(float)) == 0);
    if (same) continue;
    if (bad++ < 5)
      fprintf(stderr, "%s: ray %zu: prim %d t %.9g against prim %d t %.9g\n", what, i, a[i].prim, a[i].t, b[i].prim,
              b[i].t);
  }
  return bad;
}

size_t lt_test_count_occlusion_mismatches(const lt_hit *a, const lt_hit *b, size_t n) {
  size_t bad = 0;
  for (size_t i = 0; i < n; i++) bad += (a[i].prim >= 0) != (b[i].prim >= 0);
  return bad;
}


int lt_test_opencl_available(void) {
  if (getenv("LT_TEST_NATIVE_ONLY")) return 0;
  lt_context *ctx;
  lt_context_config config = {LT_DEVICE_OPENCL, 0, 0, 0, 1};
  if (lt_context_create(&config, &ctx) != LT_OK) return 0;
  lt_context_destroy(ctx);
  return 1;
}

size_t lt_test_small_pool_mismatches(lt_structure_kind kind) {
  enum { N = 500 };
  lt_scene *scene;
  if (lt_scene_load("sphere:5", &scene) != LT_OK) return (size_t)-1;
  lt_ray rays[N];
  lt_hit hits[N], ref[N];
  lt_test_random_rays(scene, 3, N, rays);
  size_t bad = lt_reference_trace(scene, rays, N, LT_QUERY_CLOSEST, ref) == LT_OK ? 0 : (size_t)-1;
  for (int mode = LT_BUILD_FULL; mode <= LT_BUILD_SPECULATIVE && bad != (size_t)-1; mode++) {
    lt_context *ctx;
    lt_context_config config = {LT_DEVICE_NATIVE, 2, 1, 0, 1};
    if (lt_context_create(&config, &ctx) != LT_OK) return lt_scene_destroy(scene), (size_t)-1;
    lt_structure_config sc = lt_structure_config_default(kind);
    sc.build = (lt_build_mode)mode, sc.pool_capacity = 2;
    lt_structure *s;
    if (lt_structure_create(ctx, scene, &sc, NULL, &s) == LT_OK) {
      bad = lt_structure_trace(s, rays, N, LT_QUERY_CLOSEST, hits, NULL) == LT_OK
                ? bad + lt_test_count_mismatches(lt_structure_kind_name(kind), hits, ref, N)
                : (size_t)-1;
      lt_structure_destroy(s);
    } else {
      bad = (size_t)-1;
    }
    lt_context_destroy(ctx);
  }
  lt_scene_destroy(scene);
  return bad;
}

lt_hit *lt_test_trace_with(const lt_scene *scene, const lt_test_launch *l, const lt_structure_config *sc,
                           const lt_ray *rays, size_t n, int query, lt_stats *stats) {
  lt_context *ctx;
  lt_context_config config = {l->device, 0, l->work_groups, l->local_size, 1};
  if (lt_context_create(&config, &ctx) != LT_OK) return fprintf(stderr, "context: %s\n", lt_last_error()), NULL;
  lt_structure *s;
  lt_hit *hits = NULL;
  if (lt_structure_create(ctx, scene, sc, stats, &s) != LT_OK) {
    fprintf(stderr, "create failed: %s\n", lt_last_error());
  } else {
    hits = malloc(n * sizeof *hits);
    if (hits && lt_structure_trace(s, rays, n, query, hits, stats) != LT_OK) {
      fprintf(stderr, "trace failed: %s\n", lt_last_error());
      free(hits), hits = NULL;
    }
    lt_structure_destroy(s);
  }
  lt_context_destroy(ctx);
  return hits;
}

size_t lt_test_backend_mismatches(const char *what, const lt_scene *scene, const lt_structure_config *sc,
                                  const lt_ray *rays, size_t n, const lt_hit *ref, const lt_hit *ref_any) {
  size_t mismatches = 0;
  for (int b = 0; b < 1 + lt_test_opencl_available(); b++) {
    lt_test_launch l = {b ? LT_DEVICE_OPENCL : LT_DEVICE_NATIVE, 0, 0};
    char label[160];
    snprintf(label, sizeof label, "%s on %s", what, b ? "OpenCL" : "native");
    for (int query = LT_QUERY_CLOSEST; query <= LT_QUERY_ANY; query++) {
      lt_hit *hits = lt_test_trace_with(scene, &l, sc, rays, n, query, NULL);
      if (!hits) return (size_t)-1;
      mismatches += query == LT_QUERY_CLOSEST ? lt_test_count_mismatches(label, hits, ref, n)
                                              : lt_test_count_occlusion_mismatches(hits, ref_any, n);
      free(hits);
    }
  }
  return mismatches;
}

lt_ray *lt_test_generator_rays(const lt_scene *scene, int side, size_t random, uint64_t seed, size_t *n) {
  size_t square = (size_t)side * side;
  *n = 2 * square + random;
  lt_ray *rays = malloc(*n * sizeof *rays);
  if (!rays) return NULL;
  lt_test_camera_rays(scene, "outer", side, side, rays);
  lt_test_camera_rays(scene, "close", side, side, rays + square);
  lt_test_random_rays(scene, seed, random, rays + 2 * square);
  return rays;
}

lt_ray *lt_test_ao_rays(const lt_scene *scene, int side, lt_ray *primary, size_t *n) {
  size_t count = (size_t)side * side;
  lt_ray *ao = malloc(8 * count * sizeof *ao);
  lt_hit *hits = malloc(count * sizeof *hits);
  *n = 0;
  lt_test_camera_rays(scene, "close", side, side, primary);
  if (ao && hits && lt_reference_trace(scene, primary, count, LT_QUERY_CLOSEST, hits) == LT_OK) {
    float lo[3], hi[3];
    lt_scene_bounds(scene, lo, hi);
    float reach = 0.1f * (hi[0] - lo[0] + hi[1] - lo[1] + hi[2] - lo[2]);
    *n = lt_ao_rays(scene, primary, hits, count, 8, reach, 3, ao);
  }
  free(hits);
  if (*n <= count) free(ao), ao = NULL;
  return ao;
}
