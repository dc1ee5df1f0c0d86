/* The renderer's wavefront: rays in flight grouped in one batch per effect, each ray with the
 * path state that says what its answer adds to which pixel. render.c runs the batches through
 * the structure; effects.c turns the hits of one batch into the rays of the next and shades. */
#ifndef LT_RENDER_INTERNAL_H
#define LT_RENDER_INTERNAL_H

#include "lazytrace.h"

typedef enum {
  LT_EFFECT_PRIMARY = 0,
  LT_EFFECT_SHADOWS,
  LT_EFFECT_AO,
  LT_EFFECT_DIFFUSE,
  LT_EFFECT_MIRROR,
  LT_EFFECT_COLLISION,
  LT_EFFECT_COUNT
} lt__effect;

/* "primary", "shadows", ...: the keys of rays_by_effect. */
extern const char *const lt__effect_names[LT_EFFECT_COUNT];

/* What a ray's answer contributes: its radiance times weight goes to pixel. */
typedef struct lt__path {
  int32_t pixel;    /* 4 bytes: row-major index into the image */
  uint8_t camera;   /* 1 byte: on the camera path (the primary ray and mirror reflections of it) */
  uint8_t bounces;  /* 1 byte: diffuse bounces taken before this ray */
  uint8_t mirrors;  /* 1 byte: mirror reflections taken before this ray */
  uint8_t no_sky;   /* 1 byte: escaping adds nothing (AO already counted the background) */
  float weight[3];  /* 12 bytes: throughput (for shadow and AO rays: the whole contribution) */
  uint64_t rng;     /* 8 bytes: this path's random state */
} lt__path;

/* Rays of one effect waiting to be traced, with their paths. */
typedef struct lt__batch {
  lt_ray *rays;
  lt__path *paths;
  size_t count, capacity;
} lt__batch;

/* Appends a ray and its path; returns nonzero when out of memory. */
int lt__batch_push(lt__batch *batch, const lt_ray *ray, const lt__path *path);
void lt__batch_free(lt__batch *batch);

/* Everything shading needs to know, fixed for one render. */
typedef struct lt__shading {
  const lt_scene *scene;
  const float *tris;
  const lt_material *materials;
  const lt_light *lights;
  size_t light_count;
  lt_effects effects;
  float background[3];
} lt__shading;

/* Shades the closest hits of a primary, diffuse or mirror batch: emission and unshadowed light
 * go straight into image; shadow, AO, diffuse and mirror rays go into out[effect], only where
 * the effect applies. Returns nonzero when out of memory. */
int lt__shade_hits(const lt__shading *sh, const lt__batch *batch, const lt_hit *hits, float *image,
                   lt__batch out[LT_EFFECT_COUNT]);
/* Shadow and AO rays: the ones that reach their end unoccluded add their weight. */
void lt__resolve_occlusion(const lt__batch *batch, const lt_hit *hits, float *image);

/* A new state from a state and an index, for children and pixels (scenes/splitmix.h draws). */
uint64_t lt__path_rng_mix(uint64_t state, uint64_t index);

#endif
