/* Animated scenes: triangles that move with time, from 0 (the first frame) to 1 (the last).
 * A mover is a run of triangles with a rest shape, an optional explosion (each triangle flies
 * off along its own velocity, falls and spins about its centroid, like the exploding dragon
 * and the breaking lion of the on-demand paper's Table 5) and rigid poses at key times,
 * interpolated linearly. lt_scene_set_time rewrites the triangles in place, so the count and
 * the numbering never change and a structure is simply rebuilt over them. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "runtime/error.h"
#include "scenes/scene_internal.h"
#include "scenes/splitmix.h"

/* The explosion's fixed seed: the same pieces fly the same way in every run. */
#define EXPLODE_SEED 0x5eed0017u

lt__pose_turn lt__pose_turn_of(const lt__pose *pose) {
  float angle = pose->rotate_y * 3.14159265358979f / 180.0f;
  lt__pose_turn turn = {cosf(angle), sinf(angle)};
  return turn;
}

void lt__pose_apply(const lt__pose *pose, lt__pose_turn turn, const float p[3], float out[3]) {
  float c = turn.c, s = turn.s;
  float x = pose->scale * p[0], y = pose->scale * p[1], z = pose->scale * p[2];
  out[0] = c * x + s * z + pose->translate[0];
  out[1] = y + pose->translate[1];
  out[2] = -s * x + c * z + pose->translate[2];
}

static void *copy_of(const void *src, size_t bytes) {
  void *dst = malloc(bytes ? bytes : 1);
  if (dst && bytes) memcpy(dst, src, bytes);
  return dst;
}

lt_status lt__motion_add(lt_scene *scene, size_t first, size_t count, const float *rest, const float *burst,
                         const lt__pose *keys, int key_count) {
  if (!scene->motion && !(scene->motion = calloc(1, sizeof *scene->motion)))
    return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory for the scene's motion");
  lt__motion *m = scene->motion;
  if (m->count == m->capacity) {
    int capacity = m->capacity ? 2 * m->capacity : 8;
    lt__mover *grown = realloc(m->movers, (size_t)capacity * sizeof *grown);
    if (!grown) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory for the scene's motion");
    m->movers = grown, m->capacity = capacity;
  }
  lt__mover v = {first, count, copy_of(rest, 9 * count * sizeof *rest),
                 burst ? copy_of(burst, LT_BURST_FLOATS * count * sizeof *burst) : NULL,
                 copy_of(keys, (size_t)key_count * sizeof *keys), key_count};
  if (!v.rest || (burst && !v.burst) || !v.keys) {
    free(v.rest), free(v.burst), free(v.keys);
    return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory for the scene's motion");
  }
  m->movers[m->count++] = v;
  return LT_OK;
}

void lt__motion_free(lt__motion *motion) {
  if (!motion) return;
  for (int i = 0; i < motion->count; i++)
    free(motion->movers[i].rest), free(motion->movers[i].burst), free(motion->movers[i].keys);
  free(motion->movers);
  free(motion);
}

/* ---- Explosions ---- */

/* A direction uniform on the unit sphere. */
static void random_direction(uint64_t *state, float d[3]) {
  float z = 2.0f * lt__splitmix_unit(state) - 1.0f, phi = 6.28318530718f * lt__splitmix_unit(state);
  float r = sqrtf(fmaxf(0.0f, 1.0f - z * z));
  d[0] = r * cosf(phi), d[1] = r * sinf(phi), d[2] = z;
}

lt_status lt__motion_explode(lt_scene *scene) {
  if (scene->motion) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "explode: the base scene already moves");
  float lo[3], hi[3], centre[3], radius = 0.0f;
  lt_scene_bounds(scene, lo, hi);
  for (int k = 0; k < 3; k++) centre[k] = 0.5f * (lo[k] + hi[k]), radius += 0.25f * (hi[k] - lo[k]) * (hi[k] - lo[k]);
  radius = sqrtf(radius);
  float *burst = malloc(LT_BURST_FLOATS * (scene->count ? scene->count : 1) * sizeof *burst);
  if (!burst) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory for the explosion");

  /* Each triangle flies outwards from the centre through its centroid, at a speed of half to
   * one and a half radii per unit of time, its direction scattered a little so that pieces
   * from one region do not stay a sheet; it falls by one radius per unit of time squared and
   * spins about a random axis at a quarter to one and a quarter turns per unit of time. */
  for (size_t t = 0; t < scene->count; t++) {
    uint64_t state = EXPLODE_SEED ^ (0x9e3779b97f4a7c15ull * (t + 1));
    const float *v = scene->tris + 9 * t;
    float out[3], scatter[3], *b = burst + LT_BURST_FLOATS * t, length = 0.0f;
    for (int k = 0; k < 3; k++) out[k] = (v[k] + v[3 + k] + v[6 + k]) / 3.0f - centre[k], length += out[k] * out[k];
    length = sqrtf(length);
    random_direction(&state, scatter);
    if (!(length > 1e-6f * radius)) memcpy(out, scatter, sizeof out), length = 1.0f;
    float speed = radius * (0.5f + lt__splitmix_unit(&state));
    for (int k = 0; k < 3; k++) b[k] = speed * (out[k] / length + 0.3f * scatter[k]);
    random_direction(&state, b + 3);
    b[6] = 6.28318530718f * (0.25f + lt__splitmix_unit(&state));
    b[7] = radius;
  }
  lt__pose still = {0.0f, {0, 0, 0}, 0.0f, 1.0f};
  lt_status status = lt__motion_add(scene, 0, scene->count, scene->tris, burst, &still, 1);
  free(burst);
  return status;
}

/* Vertex p of a triangle with centroid g at time t of its burst b: turned about g by the spin
 * (Rodrigues' formula), then carried along the velocity and down by the fall. */
static void burst_apply(const float *b, const float g[3], const float p[3], float t, float out[3]) {
  const float *a = b + 3;
  float angle = b[6] * t, c = cosf(angle), s = sinf(angle);
  float r[3] = {p[0] - g[0], p[1] - g[1], p[2] - g[2]};
  float dot = a[0] * r[0] + a[1] * r[1] + a[2] * r[2];
  float cross[3] = {a[1] * r[2] - a[2] * r[1], a[2] * r[0] - a[0] * r[2], a[0] * r[1] - a[1] * r[0]};
  for (int k = 0; k < 3; k++) out[k] = g[k] + c * r[k] + s * cross[k] + (1.0f - c) * dot * a[k] + b[k] * t;
  out[1] -= 0.5f * b[7] * t * t;
}

/* ---- Poses over time ---- */

/* The pose at time t: the first key's before it, the last key's after it, linear between. */
static lt__pose pose_at(const lt__mover *m, float t) {
  if (t <= m->keys[0].time) return m->keys[0];
  if (t >= m->keys[m->key_count - 1].time) return m->keys[m->key_count - 1];
  int i = 1;
  while (m->keys[i].time < t) i++;
  const lt__pose *a = &m->keys[i - 1], *b = &m->keys[i];
  float w = (t - a->time) / (b->time - a->time);
  lt__pose p = {t, {0, 0, 0}, a->rotate_y + w * (b->rotate_y - a->rotate_y), a->scale + w * (b->scale - a->scale)};
  for (int k = 0; k < 3; k++) p.translate[k] = a->translate[k] + w * (b->translate[k] - a->translate[k]);
  return p;
}

int lt_scene_is_animated(const lt_scene *scene) { return scene && scene->motion && scene->motion->count > 0; }

double lt_frame_time(int frame, int frames) { return frames > 1 ? (double)frame / (frames - 1) : 0.0; }

void lt_scene_set_time(lt_scene *scene, double time) {
  if (!lt_scene_is_animated(scene)) return;
  float t = isnan(time) ? 0.0f : (float)fmin(1.0, fmax(0.0, time));
  for (int i = 0; i < scene->motion->count; i++) {
    const lt__mover *m = &scene->motion->movers[i];
    lt__pose pose = pose_at(m, t);
    lt__pose_turn turn = lt__pose_turn_of(&pose);
    /* Time 0 leaves the rest shape untouched, so that the first frame is the loaded scene. */
    int bursts = m->burst && t > 0.0f;
    for (size_t tri = 0; tri < m->count; tri++) {
      const float *rest = m->rest + 9 * tri;
      float *out = scene->tris + 9 * (m->first + tri), g[3], moved[3];
      if (bursts)
        for (int k = 0; k < 3; k++) g[k] = (rest[k] + rest[3 + k] + rest[6 + k]) / 3.0f;
      for (int v = 0; v < 3; v++) {
        if (bursts) burst_apply(m->burst + LT_BURST_FLOATS * tri, g, rest + 3 * v, t, moved);
        else memcpy(moved, rest + 3 * v, sizeof moved);
        lt__pose_apply(&pose, turn, moved, out + 3 * v);
      }
    }
  }
}
