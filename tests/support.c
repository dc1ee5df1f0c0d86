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
