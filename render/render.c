/* lt_render: the scene's effects as a sequence of ray batches through one structure. Per camera
 * sample and tile of pixels: the primary batch, then generation by generation the shadow and AO
 * batches (any hit) and the diffuse and mirror batches (closest hit) that the previous hits call
 * for, until no ray is left; then the collision frames. Every batch goes through the same
 * structure, so nodes built for one serve the next; an effect that does not apply emits no
 * batch at all. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/render_internal.h"
#include "scenes/splitmix.h"
#include "runtime/error.h"
#include "runtime/stats_internal.h"
#include "runtime/structure_internal.h"

#define DEFAULT_SIZE      1024
#define DEFAULT_MAX_BATCH (2u << 20)
#define PROGRESS_AFTER_MS 3000.0 /* renders shorter than this say nothing */
#define PROGRESS_EVERY_MS 1000.0

/* The state of one render. */
typedef struct renderer {
  lt_structure *structure; /* NULL: brute force */
  const lt_scene *scene;
  lt__shading sh;
  lt_stats *stats;
  lt_hit *hits;
  size_t hit_capacity;
  float *image;
  int width, height, spp;
  uint64_t seed;
  int progress;
  double start, last_progress;
  size_t first, stride; /* the part of the image rendered: pixels first + j * stride */
} renderer;

void lt_render_size(const lt_scene *scene, const lt_render_config *config, int *width, int *height, int *spp) {
  int w, h, s;
  lt_scene_image(scene, &w, &h, &s);
  if (config && config->width > 0) w = config->width;
  if (config && config->height > 0) h = config->height;
  if (config && config->spp > 0) s = config->spp;
  if (width) *width = w > 0 ? w : DEFAULT_SIZE;
  if (height) *height = h > 0 ? h : DEFAULT_SIZE;
  if (spp) *spp = s > 0 ? s : 1;
}

/* ---- Tracing one batch ---- */

static void say_progress(renderer *r, double done) {
  double now = lt_now_ms();
  if (!r->progress || now - r->start < PROGRESS_AFTER_MS || now - r->last_progress < PROGRESS_EVERY_MS) return;
  r->last_progress = now;
  fprintf(stderr, "\rlazytrace: rendering %dx%d: %3.0f%% after %.1f s", r->width, r->height, 100.0 * done,
          (now - r->start) / 1000.0);
  fflush(stderr);
}

/* Traces a batch of one effect; hits land in r->hits. Rays, time and nodes are recorded. */
static lt_status trace(renderer *r, lt__effect effect, const lt_ray *rays, size_t count, int any) {
  if (count == 0) return LT_OK;
  if (count > r->hit_capacity) {
    lt_hit *hits = realloc(r->hits, count * sizeof *hits);
    if (!hits) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory for %zu hits", count);
    r->hits = hits, r->hit_capacity = count;
  }
  double before = r->stats ? lt_stats_get(r->stats, "total_ms") : 0.0, start = lt_now_ms();
  lt_status status = r->structure
                         ? lt_structure_trace(r->structure, rays, count, any ? LT_QUERY_ANY : LT_QUERY_CLOSEST,
                                              r->hits, r->stats)
                         : lt_reference_trace(r->scene, rays, count, any ? LT_QUERY_ANY : LT_QUERY_CLOSEST, r->hits);
  if (status || !r->stats) return status;

  /* Build plus trace for a structure (the retrace that measures trace time is not counted);
   * wall time for brute force. */
  double ms = lt_now_ms() - start;
  if (r->structure) ms = lt_stats_get(r->stats, "total_ms") - (before > 0 ? before : 0.0);
  else lt__stats_add(r->stats, LT_STAT_RAYS, (double)count);
  lt__stats_add(r->stats, (lt_stat_id)(LT_STAT_RAYS_PRIMARY + effect), (double)count);
  lt__stats_add(r->stats, (lt_stat_id)(LT_STAT_MS_PRIMARY + effect), ms);
  lt__stats_batch(r->stats, lt__effect_names[effect], (double)count, ms, lt_stats_get(r->stats, "nodes_built"));
  return LT_OK;
}

/* ---- Camera ---- */

typedef struct camera_frame {
  float eye[3], u[3], v[3], w[3], half_w, half_h;
} camera_frame;

/* The same frame as lt_camera_primary_rays: w towards the target, u right, v up, the image
 * plane at distance 1. */
static camera_frame frame_of(const lt_camera *c, int width, int height) {
  camera_frame f;
  float wl = 0, ul = 0;
  for (int k = 0; k < 3; k++) f.eye[k] = c->eye[k], f.w[k] = c->look[k] - c->eye[k], wl += f.w[k] * f.w[k];
  for (int k = 0; k < 3; k++) f.w[k] /= sqrtf(wl);
  f.u[0] = f.w[1] * c->up[2] - f.w[2] * c->up[1];
  f.u[1] = f.w[2] * c->up[0] - f.w[0] * c->up[2];
  f.u[2] = f.w[0] * c->up[1] - f.w[1] * c->up[0];
  for (int k = 0; k < 3; k++) ul += f.u[k] * f.u[k];
  for (int k = 0; k < 3; k++) f.u[k] /= sqrtf(ul);
  f.v[0] = f.u[1] * f.w[2] - f.u[2] * f.w[1];
  f.v[1] = f.u[2] * f.w[0] - f.u[0] * f.w[2];
  f.v[2] = f.u[0] * f.w[1] - f.u[1] * f.w[0];
  f.half_h = tanf(0.5f * c->fov_deg * 3.14159265f / 180.0f);
  f.half_w = f.half_h * (float)width / (float)height;
  return f;
}

/* The primary rays of the part's pixels [first, last) (counted within the part) for camera
 * sample `pass`: through pixel centres with one sample per pixel, jittered within the pixel with
 * more. A pixel's random numbers derive from its index in the image, never from the part. */
static lt_status primary_batch(renderer *r, const camera_frame *f, int pass, size_t first, size_t last,
                               lt__batch *out) {
  for (size_t j = first; j < last; j++) {
    size_t i = r->first + j * r->stride;
    int x = (int)(i % (size_t)r->width), y = (int)(i / (size_t)r->width);
    lt__path path = {(int32_t)i, 1, 0, 0, 0, {1.0f / r->spp, 1.0f / r->spp, 1.0f / r->spp}, 0};
    path.rng = lt__path_rng_mix(lt__path_rng_mix(r->seed, (uint64_t)pass), i);
    float jx = 0.5f, jy = 0.5f;
    if (r->spp > 1) jx = lt__splitmix_unit(&path.rng), jy = lt__splitmix_unit(&path.rng);
    float sx = (2.0f * (x + jx) / r->width - 1.0f) * f->half_w, sy = (1.0f - 2.0f * (y + jy) / r->height) * f->half_h;
    lt_ray ray = {{f->eye[0], f->eye[1], f->eye[2]}, 0.0f, {0, 0, 0}, INFINITY};
    for (int k = 0; k < 3; k++) ray.dir[k] = f->w[k] + sx * f->u[k] + sy * f->v[k];
    if (lt__batch_push(out, &ray, &path)) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory for primary rays");
  }
  return LT_OK;
}

/* ---- Generations ---- */

static void clear(lt__batch b[LT_EFFECT_COUNT]) {
  for (int e = 0; e < LT_EFFECT_COUNT; e++) b[e].count = 0;
}

/* One tile: the primary batch, then batches generation by generation until no ray is left. */
static lt_status render_tile(renderer *r, lt__batch *primary, lt__batch cur[LT_EFFECT_COUNT],
                             lt__batch next[LT_EFFECT_COUNT]) {
  clear(cur);
  lt_status status = trace(r, LT_EFFECT_PRIMARY, primary->rays, primary->count, 0);
  if (status) return status;
  if (lt__shade_hits(&r->sh, primary, r->hits, r->image, cur))
    return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory for secondary rays");

  for (;;) {
    /* Occlusion queries settle their contribution at once. */
    static const lt__effect occlusion[2] = {LT_EFFECT_SHADOWS, LT_EFFECT_AO};
    for (int o = 0; o < 2; o++) {
      lt__batch *b = &cur[occlusion[o]];
      if ((status = trace(r, occlusion[o], b->rays, b->count, 1))) return status;
      if (b->count) lt__resolve_occlusion(b, r->hits, r->image);
    }

    /* Diffuse and mirror hits are the next generation's shading points. */
    static const lt__effect onward[2] = {LT_EFFECT_DIFFUSE, LT_EFFECT_MIRROR};
    clear(next);
    for (int o = 0; o < 2; o++) {
      lt__batch *b = &cur[onward[o]];
      if ((status = trace(r, onward[o], b->rays, b->count, 0))) return status;
      if (b->count && lt__shade_hits(&r->sh, b, r->hits, r->image, next))
        return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory for secondary rays");
    }
    size_t left = 0;
    for (int e = 0; e < LT_EFFECT_COUNT; e++) {
      left += next[e].count;
      lt__batch t = cur[e];
      cur[e] = next[e], next[e] = t;
    }
    if (left == 0) return LT_OK;
  }
}

/* Rays a pixel may put into one batch at most, to size tiles: one primary, a shadow ray per
 * light, the AO samples, and the diffuse samples, each of which may hit a mirror or cast
 * shadow rays in the next generation. */
static size_t rays_per_pixel(const lt__shading *sh) {
  const lt_effects *fx = &sh->effects;
  size_t lights = sh->light_count ? sh->light_count : 1, diffuse = (size_t)fx->diffuse_samples;
  return 2 + (diffuse + 1) * lights + (size_t)fx->ao_samples + diffuse;
}

/* The collision effect: agents moving through the scene, one batch per frame, on the same
 * structure (the scene does not move, so nothing is rebuilt). */
static lt_status collision(renderer *r) {
  const lt_effects *fx = &r->sh.effects;
  size_t n = (size_t)fx->collision_agents * fx->collision_rays;
  float *paths = malloc(6 * sizeof(float) * fx->collision_agents);
  lt_ray *rays = malloc(n * sizeof *rays);
  lt_status status = paths && rays ? LT_OK : lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory for collision rays");
  if (!status) lt_collision_paths(r->scene, fx->collision_agents, r->seed, paths);
  for (int f = 0; f < fx->collision_frames && !status; f++) {
    lt_collision_rays(paths, fx->collision_agents, fx->collision_rays, f, fx->collision_frames, r->seed + 1, rays);
    status = trace(r, LT_EFFECT_COLLISION, rays, n, 0);
  }
  free(paths), free(rays);
  return status;
}

lt_status lt_render(lt_structure *structure, const lt_scene *scene, const lt_render_config *config, float *rgb,
                    lt_stats *stats) {
  if (!scene || !rgb) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt_render: NULL argument");
  int width, height;
  lt_render_size(scene, config, &width, &height, NULL);
  return lt_render_part(structure, scene, config, 0, (size_t)width * height, 1, rgb, stats);
}

lt_status lt_render_part(lt_structure *structure, const lt_scene *scene, const lt_render_config *config, size_t first,
                         size_t count, size_t stride, float *rgb, lt_stats *stats) {
  if (!scene || !rgb) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt_render: NULL argument");
  if (structure && structure->scene != scene)
    return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt_render: the structure was built over another scene");
  renderer r = {structure, scene, {0}, stats, NULL, 0, rgb, 0, 0, 0, config ? config->seed : 0,
                config ? config->progress : 0, lt_now_ms(), 0.0, first, stride};
  lt_render_size(scene, config, &r.width, &r.height, &r.spp);
  size_t image_pixels = (size_t)r.width * r.height;
  if (stride < 1 || (count && (first >= image_pixels || (count - 1) > (image_pixels - 1 - first) / stride)))
    return lt__fail(LT_ERROR_INVALID_ARGUMENT,
                    "lt_render_part: pixels %zu + j * %zu for j < %zu reach beyond the %dx%d image", first, stride,
                    count, r.width, r.height);
  r.sh = (lt__shading){scene, lt_scene_triangles(scene), lt_scene_materials(scene), lt_scene_lights(scene),
                       lt_scene_light_count(scene), config && config->effects ? *config->effects : lt_scene_effects(scene),
                       {0, 0, 0}};
  lt_scene_background(scene, r.sh.background);
  /* Only the part's pixels are touched; in a whole render that is every pixel. */
  size_t pixels = count;
  for (size_t j = 0; j < pixels; j++) memset(rgb + 3 * (first + j * stride), 0, 3 * sizeof *rgb);

  /* Every effect's count is there, zero for those the scene does not call for. */
  for (int e = 0; e < LT_EFFECT_COUNT; e++) {
    lt__stats_put(stats, (lt_stat_id)(LT_STAT_RAYS_PRIMARY + e), 0.0);
    lt__stats_put(stats, (lt_stat_id)(LT_STAT_MS_PRIMARY + e), 0.0);
  }

  /* Tiles small enough that no batch exceeds the cap. */
  size_t cap = config && config->max_batch ? config->max_batch : DEFAULT_MAX_BATCH;
  size_t tile = cap / rays_per_pixel(&r.sh);
  if (tile < 1) tile = 1;
  if (tile > pixels) tile = pixels;
  size_t tiles = pixels ? (pixels + tile - 1) / tile : 0;

  lt__batch primary = {0}, cur[LT_EFFECT_COUNT] = {{0}}, next[LT_EFFECT_COUNT] = {{0}};
  lt_status status = LT_OK;
  if (r.sh.effects.primary) {
    lt_camera camera = lt_scene_camera(scene);
    camera_frame f = frame_of(&camera, r.width, r.height);
    for (int pass = 0; pass < r.spp && !status; pass++)
      for (size_t t = 0; t < tiles && !status; t++) {
        primary.count = 0;
        size_t first = t * tile, last = first + tile < pixels ? first + tile : pixels;
        status = primary_batch(&r, &f, pass, first, last, &primary);
        if (!status) status = render_tile(&r, &primary, cur, next);
        say_progress(&r, (pass * tiles + t + 1.0) / ((double)r.spp * tiles));
      }
  } else {
    /* Nothing is traced from the camera: the image is the background. */
    for (size_t j = 0; j < pixels; j++) memcpy(rgb + 3 * (first + j * stride), r.sh.background, 3 * sizeof *rgb);
  }
  /* The collision frames draw no pixel: the part that holds pixel 0 traces them, once. */
  if (!status && r.sh.effects.collision_agents > 0 && first == 0) status = collision(&r);
  if (r.last_progress > 0) fputc('\n', stderr);

  lt__batch_free(&primary);
  for (int e = 0; e < LT_EFFECT_COUNT; e++) lt__batch_free(&cur[e]), lt__batch_free(&next[e]);
  free(r.hits);
  return status;
}

void lt_image_to_srgb8(const float *rgb, size_t pixels, unsigned char *out) {
  for (size_t i = 0; i < 3 * pixels; i++) {
    float c = rgb[i] > 0.0f ? (rgb[i] < 1.0f ? rgb[i] : 1.0f) : 0.0f;
    float s = c <= 0.0031308f ? 12.92f * c : 1.055f * powf(c, 1.0f / 2.4f) - 0.055f;
    out[i] = (unsigned char)(255.0f * s + 0.5f);
  }
}
