/* Scene handles: growing the triangle soup, cameras, bounds, loading by spec and OBJ output. */
#include "scene_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "runtime/error.h"
#include "runtime/output_file.h"

lt_scene *lt__scene_new(void) {
  lt_scene *scene = calloc(1, sizeof *scene);
  if (scene) scene->active_camera = -1;
  return scene;
}

static int finite3(const float p[3]) { return isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2]); }

lt_status lt__scene_add_tri(lt_scene *scene, const float a[3], const float b[3], const float c[3]) {
  if (!finite3(a) || !finite3(b) || !finite3(c)) {
    scene->skipped++;
    return LT_OK;
  }
  if (scene->count == scene->capacity) {
    size_t capacity = scene->capacity ? 2 * scene->capacity : 1024;
    float *tris = realloc(scene->tris, capacity * 9 * sizeof *tris);
    if (!tris) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory growing a scene to %zu triangles", capacity);
    scene->tris = tris;
    scene->capacity = capacity;
  }
  float *t = scene->tris + 9 * scene->count++;
  memcpy(t, a, 3 * sizeof *t);
  memcpy(t + 3, b, 3 * sizeof *t);
  memcpy(t + 6, c, 3 * sizeof *t);
  return LT_OK;
}

lt_status lt__scene_add_quad(lt_scene *scene, const float a[3], const float b[3], const float c[3],
                             const float d[3]) {
  lt_status status = lt__scene_add_tri(scene, a, b, c);
  return status ? status : lt__scene_add_tri(scene, a, c, d);
}

lt_status lt__scene_add_camera(lt_scene *scene, const char *name, lt_camera camera) {
  if (scene->camera_count == LT_SCENE_MAX_CAMERAS)
    return lt__fail(LT_ERROR_CAPACITY, "a scene holds at most %d cameras", LT_SCENE_MAX_CAMERAS);
  int i = scene->camera_count++;
  snprintf(scene->camera_names[i], sizeof scene->camera_names[i], "%s", name);
  scene->cameras[i] = camera;
  if (scene->active_camera < 0) scene->active_camera = i;
  return LT_OK;
}

lt_status lt_scene_from_triangles(const float *tris, size_t n, lt_scene **out) {
  if (!out || (n && !tris)) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt_scene_from_triangles: NULL argument");
  lt_scene *scene = lt__scene_new();
  if (!scene) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory creating a scene");
  for (size_t i = 0; i < n; i++) {
    lt_status status = lt__scene_add_tri(scene, tris + 9 * i, tris + 9 * i + 3, tris + 9 * i + 6);
    if (status) {
      lt_scene_destroy(scene);
      return status;
    }
  }
  *out = scene;
  return LT_OK;
}

static int has_suffix(const char *s, const char *suffix) {
  size_t n = strlen(s), m = strlen(suffix);
  return n >= m && strcasecmp(s + n - m, suffix) == 0;
}

static int looks_like_file(const char *spec) {
  return strchr(spec, '/') || strchr(spec, '.') ? 1 : 0;
}

lt_status lt_scene_load(const char *spec, lt_scene **out) {
  if (!spec || !out) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt_scene_load: NULL argument");
  lt_scene *scene = lt__scene_new();
  if (!scene) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory creating a scene");
  lt_status status;
  const char *camera = NULL;
  char name[256];

  /* A spec that names a file is read as a mesh; anything else is a generator. */
  if (looks_like_file(spec) && !strchr(spec, ':')) {
    status = has_suffix(spec, ".obj")    ? lt__load_obj(spec, scene)
             : has_suffix(spec, ".ply")  ? lt__load_ply(spec, scene)
             : has_suffix(spec, ".json") ? lt__load_scene_file(spec, scene)
                                         : lt__load_assimp(spec, scene);
  } else {
    snprintf(name, sizeof name, "%s", spec);
    char *at = strchr(name, '@');
    if (at) {
      *at = '\0';
      camera = spec + (at - name) + 1;
    }
    char *colon = strchr(name, ':');
    if (colon) *colon = '\0';
    status = lt__generate(name, colon ? colon + 1 : NULL, scene);
  }
  if (!status && scene->count == 0)
    status = lt__fail(LT_ERROR_EMPTY_SCENE, "%s: no valid triangles (%zu skipped for NaN or infinite coordinates)",
                      spec, scene->skipped);
  if (!status && camera) {
    int found = -1;
    for (int i = 0; i < scene->camera_count; i++)
      if (strcmp(scene->camera_names[i], camera) == 0) found = i;
    if (found < 0)
      status = lt__fail(LT_ERROR_INVALID_ARGUMENT, "%s: the scene has no camera named '%s'", spec, camera);
    scene->active_camera = found;
  }
  if (status) {
    lt_scene_destroy(scene);
    return status;
  }
  *out = scene;
  return LT_OK;
}

void lt_scene_destroy(lt_scene *scene) {
  if (!scene) return;
  lt__scene_desc_free(scene->desc);
  lt__motion_free(scene->motion);
  free(scene->tris);
  free(scene);
}

size_t lt_scene_triangle_count(const lt_scene *scene) { return scene ? scene->count : 0; }
const float *lt_scene_triangles(const lt_scene *scene) { return scene ? scene->tris : NULL; }
size_t lt_scene_skipped_triangles(const lt_scene *scene) { return scene ? scene->skipped : 0; }

/* The intersection test's determinant and distance are products of two and three coordinate
 * differences: beyond about 7e12 a cube overflows float, below about 2e-13 it vanishes into
 * subnormals. 1e12 and 1e-12 leave a margin for the sums and the ray's own origin. */
#define SERVABLE_MAX 1e12f
#define SERVABLE_MIN_SIZE 1e-12f

size_t lt_scene_unservable_triangles(const lt_scene *scene) {
  size_t n = 0;
  for (size_t i = 0; scene && i < scene->count; i++) {
    const float *t = scene->tris + 9 * i;
    float size = 0.0f, far = 0.0f;
    for (int k = 0; k < 3; k++) {
      float lo = fminf(t[k], fminf(t[3 + k], t[6 + k])), hi = fmaxf(t[k], fmaxf(t[3 + k], t[6 + k]));
      size = fmaxf(size, hi - lo), far = fmaxf(far, fmaxf(fabsf(lo), fabsf(hi)));
    }
    n += far > SERVABLE_MAX || (size > 0.0f && size < SERVABLE_MIN_SIZE);
  }
  return n;
}

void lt_scene_bounds(const lt_scene *scene, float lo[3], float hi[3]) {
  for (int k = 0; k < 3; k++) lo[k] = INFINITY, hi[k] = -INFINITY;
  for (size_t i = 0; i < 3 * scene->count; i++)
    for (int k = 0; k < 3; k++) {
      float x = scene->tris[3 * i + k];
      lo[k] = fminf(lo[k], x);
      hi[k] = fmaxf(hi[k], x);
    }
}

lt_camera lt_scene_camera(const lt_scene *scene) {
  if (scene->active_camera >= 0) return scene->cameras[scene->active_camera];

  /* No camera given: look at the bounds from the front (-z), far enough to see them whole. */
  float lo[3], hi[3];
  lt_scene_bounds(scene, lo, hi);
  lt_camera camera = {{0}, {0}, {0, 1, 0}, 60.0f};
  float radius = 0.0f;
  for (int k = 0; k < 3; k++) {
    camera.look[k] = 0.5f * (lo[k] + hi[k]);
    radius += 0.25f * (hi[k] - lo[k]) * (hi[k] - lo[k]);
  }
  radius = sqrtf(radius);
  camera.eye[0] = camera.look[0];
  camera.eye[1] = camera.look[1] + 0.3f * radius;
  camera.eye[2] = camera.look[2] - 2.2f * radius;
  return camera;
}

lt_status lt_scene_named_camera(const lt_scene *scene, const char *name, lt_camera *out) {
  for (int i = 0; i < scene->camera_count; i++)
    if (strcmp(scene->camera_names[i], name) == 0) {
      *out = scene->cameras[i];
      return LT_OK;
    }
  return lt__fail(LT_ERROR_INVALID_ARGUMENT, "the scene has no camera named '%s'", name);
}

lt_status lt_scene_write_obj(const lt_scene *scene, const char *path) {
  if (!scene || !path) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt_scene_write_obj: NULL argument");
  lt__output out;
  lt_status status = lt__output_open(&out, path); /* written whole or not at all */
  if (status) return status;
  FILE *f = out.file;
  fprintf(f, "# lazytrace scene: %zu triangles, one face per triangle in triangle-number order\n", scene->count);

  /* %.9g round-trips a float exactly, so the file reproduces the triangles bit for bit. */
  for (size_t i = 0; i < 3 * scene->count; i++)
    fprintf(f, "v %.9g %.9g %.9g\n", scene->tris[3 * i], scene->tris[3 * i + 1], scene->tris[3 * i + 2]);
  for (size_t i = 0; i < scene->count; i++) fprintf(f, "f %zu %zu %zu\n", 3 * i + 1, 3 * i + 2, 3 * i + 3);
  return lt__output_commit(&out);
}

void lt_camera_primary_rays(const lt_camera *camera, int width, int height, lt_ray *out) {
  /* An orthonormal frame: w towards the target, u to the right, v up. */
  float w[3], u[3], v[3];
  for (int k = 0; k < 3; k++) w[k] = camera->look[k] - camera->eye[k];
  float wl = sqrtf(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
  for (int k = 0; k < 3; k++) w[k] /= wl;
  const float *up = camera->up;
  u[0] = w[1] * up[2] - w[2] * up[1];
  u[1] = w[2] * up[0] - w[0] * up[2];
  u[2] = w[0] * up[1] - w[1] * up[0];
  float ul = sqrtf(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
  for (int k = 0; k < 3; k++) u[k] /= ul;
  v[0] = u[1] * w[2] - u[2] * w[1];
  v[1] = u[2] * w[0] - u[0] * w[2];
  v[2] = u[0] * w[1] - u[1] * w[0];

  /* Image plane at distance 1: half height tan(fov/2), half width scaled by the aspect. */
  float half_h = tanf(0.5f * camera->fov_deg * 3.14159265f / 180.0f);
  float half_w = half_h * (float)width / (float)height;
  for (int y = 0; y < height; y++)
    for (int x = 0; x < width; x++) {
      float sx = (2.0f * (x + 0.5f) / width - 1.0f) * half_w;
      float sy = (1.0f - 2.0f * (y + 0.5f) / height) * half_h;
      lt_ray *ray = &out[(size_t)y * width + x];
      for (int k = 0; k < 3; k++) {
        ray->org[k] = camera->eye[k];
        ray->dir[k] = w[k] + sx * u[k] + sy * v[k];
      }
      ray->tmin = 0.0f;
      ray->tmax = INFINITY;
    }
}
