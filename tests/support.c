/* Helpers shared by the tests (see support.h). */
#define _POSIX_C_SOURCE 200809L
#include "tests/support.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <unistd.h>

#include <cmocka.h>

uint64_t lt_test_next(uint64_t *state) {
  uint64_t z = (*state += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

float lt_test_uniform(uint64_t *state) { return (lt_test_next(state) >> 40) * (1.0f / 16777216.0f); }

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
      a[k] = lo[k] + lt_test_uniform(&seed) * (hi[k] - lo[k]);
      b[k] = lo[k] + lt_test_uniform(&seed) * (hi[k] - lo[k]);
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

#define MAX_TEMP_FILES 64
#define TEMP_PATH_SIZE 512

static char temp_dir[64];
static char temp_files[MAX_TEMP_FILES][TEMP_PATH_SIZE];
static int temp_file_count;

int lt_test_temp_dir_create(void **state) {
  (void)state;
  snprintf(temp_dir, sizeof temp_dir, "/tmp/lt_test_XXXXXX");
  return mkdtemp(temp_dir) ? 0 : -1;
}

int lt_test_temp_dir_remove(void **state) {
  (void)state;
  for (int i = 0; i < temp_file_count; i++) unlink(temp_files[i]);
  temp_file_count = 0;
  return rmdir(temp_dir);
}

const char *lt_test_temp_path(const char *name) {
  assert_true(temp_file_count < MAX_TEMP_FILES);
  char *path = temp_files[temp_file_count++];
  snprintf(path, TEMP_PATH_SIZE, "%s/%s", temp_dir, name);
  return path;
}

const char *lt_test_write_file(const char *name, const char *text) {
  const char *path = lt_test_temp_path(name);
  FILE *f = fopen(path, "wb");
  assert_non_null(f);
  assert_int_equal(fwrite(text, 1, strlen(text), f), strlen(text));
  assert_int_equal(fclose(f), 0);
  return path;
}
