/* The effects as batch generators: the closest hits of one batch become shadow, ambient-
 * occlusion, diffuse and mirror rays, each emitted only where its effect applies (shadow rays
 * towards lights that exist and face the surface, mirror rays from mirror materials, AO rays
 * bounded by their distance), and the shading estimators that weigh them:
 *
 *   L(x) = Le + (1 - m) * albedo * (sum over lights of E cos / pi * V  +  indirect) + m * L(mirror)
 *
 * where indirect is estimated by cosine-sampled diffuse rays (radiance of what they hit, the
 * background where they escape), or by ambient occlusion (the background times the unoccluded
 * fraction), or, with neither, by the background times |cos| to the viewer (a light at the
 * eye, so that a primary-only image still shows shape). With both on the camera path, AO
 * carries the background's light and diffuse rays only the light from surfaces they hit. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "render/render_internal.h"
#include "scenes/ray_offset.h"
#include "scenes/splitmix.h"

#define PI 3.14159265358979f

const char *const lt__effect_names[LT_EFFECT_COUNT] = {"primary", "shadows", "ao", "diffuse", "mirror", "collision"};

/* ---- Batches and random numbers ---- */

int lt__batch_push(lt__batch *batch, const lt_ray *ray, const lt__path *path) {
  if (batch->count == batch->capacity) {
    size_t capacity = batch->capacity ? 2 * batch->capacity : 4096;
    lt_ray *rays = realloc(batch->rays, capacity * sizeof *rays);
    if (rays) batch->rays = rays;
    lt__path *paths = realloc(batch->paths, capacity * sizeof *paths);
    if (paths) batch->paths = paths;
    if (!rays || !paths) return 1;
    batch->capacity = capacity;
  }
  batch->rays[batch->count] = *ray;
  batch->paths[batch->count++] = *path;
  return 0;
}

void lt__batch_free(lt__batch *batch) {
  free(batch->rays);
  free(batch->paths);
  memset(batch, 0, sizeof *batch);
}

uint64_t lt__path_rng_mix(uint64_t state, uint64_t index) {
  uint64_t s = state ^ (index * 0xd1b54a32d192ed03ull);
  return lt__splitmix_next(&s);
}

/* ---- Vectors ---- */

static float dot(const float a[3], const float b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void cross(const float a[3], const float b[3], float out[3]) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}

static float normalise(float v[3]) {
  float len = sqrtf(dot(v, v));
  if (len > 0.0f)
    for (int k = 0; k < 3; k++) v[k] /= len;
  return len;
}

/* A cosine-weighted direction around the unit normal n. */
static void cosine_direction(const float n[3], uint64_t *rng, float out[3]) {
  float a[3] = {fabsf(n[0]) > 0.9f ? 0.0f : 1.0f, fabsf(n[0]) > 0.9f ? 1.0f : 0.0f, 0.0f}, b1[3], b2[3];
  cross(a, n, b1);
  normalise(b1);
  cross(n, b1, b2);
  float r = sqrtf(lt__splitmix_unit(rng)), phi = 2.0f * PI * lt__splitmix_unit(rng);
  float x = r * cosf(phi), y = r * sinf(phi), z = sqrtf(fmaxf(0.0f, 1.0f - r * r));
  for (int k = 0; k < 3; k++) out[k] = x * b1[k] + y * b2[k] + z * n[k];
}

static void add(float *image, int32_t pixel, const float w[3], const float c[3]) {
  for (int k = 0; k < 3; k++) image[3 * (size_t)pixel + k] += w[k] * c[k];
}

/* ---- Shading one hit ---- */

/* The surface seen by a ray: the triangle, the unit normal facing the ray, the origin of the
 * secondary rays (the hit point moved off the surface by its rounding bound), material. */
typedef struct surface {
  const float *tri;
  int prim;
  float o[3], n[3], cos_view;
  const lt_material *m;
} surface;

/* A secondary ray from the surface: from its origin, starting past the surface itself. */
static lt_ray secondary_ray(const surface *s, const float dir[3], float tmax) {
  lt_ray ray = {{s->o[0], s->o[1], s->o[2]}, 0.0f, {dir[0], dir[1], dir[2]}, tmax};
  ray.tmin = lt__secondary_tmin(s->tri, s->prim, s->o, dir, tmax);
  return ray;
}

/* The surface a hit sees; the origin (o) only when lights or secondary rays need it. */
static int surface_at(const lt__shading *sh, const lt_ray *ray, const lt_hit *hit, int spawns, surface *s) {
  const float *t = sh->tris + 9 * (size_t)hit->prim;
  float e1[3], e2[3], d[3] = {ray->dir[0], ray->dir[1], ray->dir[2]};
  for (int k = 0; k < 3; k++) e1[k] = t[3 + k] - t[k], e2[k] = t[6 + k] - t[k];
  cross(e1, e2, s->n);
  if (!(normalise(s->n) > 0.0f) || !(normalise(d) > 0.0f)) return 0;
  s->cos_view = -dot(s->n, d);
  if (s->cos_view < 0.0f)
    for (int k = 0; k < 3; k++) s->n[k] = -s->n[k];
  s->cos_view = fabsf(s->cos_view);
  s->tri = t, s->prim = hit->prim;
  if (spawns) lt__offset_origin(t, hit->u, hit->v, s->n, s->o);
  s->m = &sh->materials[lt_scene_triangle_material(sh->scene, (size_t)hit->prim)];
  return 1;
}

/* Direct light from every light facing the surface: a shadow ray each with shadows on,
 * the unshadowed contribution straight into the image without. */
static int direct_light(const lt__shading *sh, const surface *s, const lt__path *path, const float wd[3],
                        float *image, lt__batch *shadows) {
  for (size_t l = 0; l < sh->light_count; l++) {
    const lt_light *light = &sh->lights[l];
    float dir[3], falloff = 1.0f, tmax = INFINITY, len;
    if (light->kind == LT_LIGHT_POINT) {
      for (int k = 0; k < 3; k++) dir[k] = light->vector[k] - s->o[k];
      len = sqrtf(dot(dir, dir));
      if (!(len > 0.0f)) continue;
      falloff = 1.0f / (len * len);
      tmax = 1.0f; /* the light itself: a point with no surface */
    } else {
      for (int k = 0; k < 3; k++) dir[k] = -light->vector[k];
      len = normalise(dir);
    }
    float cos_light = dot(s->n, dir) / len;
    if (!(cos_light > 0.0f)) continue;
    lt__path shadow = *path;
    for (int k = 0; k < 3; k++) shadow.weight[k] = wd[k] * light->intensity[k] * cos_light * falloff / PI;
    if (!sh->effects.shadows) {
      add(image, path->pixel, shadow.weight, (const float[3]){1, 1, 1});
      continue;
    }
    lt_ray ray = secondary_ray(s, dir, tmax);
    if (lt__batch_push(shadows, &ray, &shadow)) return 1;
  }
  return 0;
}

/* Light arriving from the rest of the scene: diffuse rays, else AO rays, else the fallback. */
static int indirect_light(const lt__shading *sh, const surface *s, const lt__path *path, const float wd[3],
                          float *image, lt__batch out[LT_EFFECT_COUNT]) {
  const lt_effects *fx = &sh->effects;
  int ao = path->camera && fx->ao_samples > 0;
  if (fx->diffuse_samples > 0 && path->bounces < fx->diffuse_bounces) {
    /* Cosine sampling cancels the cosine and 1/pi: each ray carries albedo / samples. The
     * camera path branches into all samples, later bounces continue with one ray. */
    int k = path->camera ? fx->diffuse_samples : 1;
    for (int i = 0; i < k; i++) {
      lt__path child = *path;
      child.camera = 0, child.bounces = (uint8_t)(path->bounces + 1), child.rng = lt__path_rng_mix(path->rng, 2 * i + 1);
      child.no_sky = (uint8_t)ao;
      for (int c = 0; c < 3; c++) child.weight[c] = wd[c] / k;
      float dir[3];
      cosine_direction(s->n, &child.rng, dir);
      lt_ray ray = secondary_ray(s, dir, INFINITY);
      if (lt__batch_push(&out[LT_EFFECT_DIFFUSE], &ray, &child)) return 1;
    }
  }
  if (ao) {
    /* The background from every unoccluded direction within the distance. */
    uint64_t rng = lt__path_rng_mix(path->rng, 0);
    for (int i = 0; i < fx->ao_samples; i++) {
      lt__path occlusion = *path;
      for (int c = 0; c < 3; c++) occlusion.weight[c] = wd[c] * sh->background[c] / fx->ao_samples;
      float dir[3];
      cosine_direction(s->n, &rng, dir);
      lt_ray ray = secondary_ray(s, dir, fx->ao_distance);
      if (lt__batch_push(&out[LT_EFFECT_AO], &ray, &occlusion)) return 1;
    }
  } else if (path->camera && fx->diffuse_samples == 0) {
    float c = s->cos_view;
    add(image, path->pixel, wd, (const float[3]){c * sh->background[0], c * sh->background[1], c * sh->background[2]});
  }
  return 0;
}

int lt__shade_hits(const lt__shading *sh, const lt__batch *batch, const lt_hit *hits, float *image,
                   lt__batch out[LT_EFFECT_COUNT]) {
  const lt_effects *fx = &sh->effects;
  /* The origin serves the secondary rays and the direction to point lights. */
  int spawns = sh->light_count > 0 || fx->ao_samples > 0 || fx->diffuse_samples > 0 || fx->mirror_depth > 0;
  for (size_t i = 0; i < batch->count; i++) {
    const lt__path *path = &batch->paths[i];
    const lt_ray *ray = &batch->rays[i];
    surface s;

    /* A ray that escapes sees the background. */
    if (hits[i].prim < 0) {
      if (!path->no_sky) add(image, path->pixel, path->weight, sh->background);
      continue;
    }
    if (!surface_at(sh, ray, &hits[i], spawns, &s)) continue;
    add(image, path->pixel, path->weight, s.m->emission);

    /* The mirror part only where mirrors are simulated; else the surface is all diffuse. */
    float mirror = fx->mirror_depth > 0 ? s.m->mirror : 0.0f, wd[3];
    for (int k = 0; k < 3; k++) wd[k] = path->weight[k] * (1.0f - mirror) * s.m->diffuse[k];
    if (wd[0] > 0.0f || wd[1] > 0.0f || wd[2] > 0.0f) {
      if (direct_light(sh, &s, path, wd, image, &out[LT_EFFECT_SHADOWS])) return 1;
      if (indirect_light(sh, &s, path, wd, image, out)) return 1;
    }
    if (!(mirror > 0.0f)) continue;

    /* A perfect reflection, followed up to the depth; past it, the background stands in. */
    lt__path child = *path;
    for (int k = 0; k < 3; k++) child.weight[k] = path->weight[k] * mirror;
    if (path->mirrors >= fx->mirror_depth) {
      add(image, path->pixel, child.weight, sh->background);
      continue;
    }
    float d[3] = {ray->dir[0], ray->dir[1], ray->dir[2]};
    normalise(d);
    float dn = dot(d, s.n);
    float r[3];
    for (int k = 0; k < 3; k++) r[k] = d[k] - 2.0f * dn * s.n[k];
    lt_ray reflected = secondary_ray(&s, r, INFINITY);
    child.mirrors = (uint8_t)(path->mirrors + 1), child.rng = lt__path_rng_mix(path->rng, 2 * fx->diffuse_samples + 2);
    if (lt__batch_push(&out[LT_EFFECT_MIRROR], &reflected, &child)) return 1;
  }
  return 0;
}

void lt__resolve_occlusion(const lt__batch *batch, const lt_hit *hits, float *image) {
  static const float one[3] = {1, 1, 1};
  for (size_t i = 0; i < batch->count; i++)
    if (hits[i].prim < 0) add(image, batch->paths[i].pixel, batch->paths[i].weight, one);
}
