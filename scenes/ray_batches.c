/* Ray batches beyond the camera's: ambient-occlusion rays from primary hits, and the
 * collision rays of agents moving through a scene (the on-demand paper, section 5). */
#include <math.h>
#include <string.h>

#include "runtime/error.h"
#include "scenes/scene_internal.h"
#include "scenes/ray_offset.h"
#include "scenes/splitmix.h"

size_t lt_ao_rays(const lt_scene *scene, const lt_ray *primary, const lt_hit *hits, size_t count, int samples,
                  float distance, uint64_t seed, lt_ray *out) {
  size_t m = 0;
  for (size_t i = 0; i < count; i++) {
    if (hits[i].prim < 0) continue;
    const float *t = scene->tris + 9 * (size_t)hits[i].prim;

    /* The geometric normal, turned towards the side the primary ray came from. */
    float e1[3], e2[3], n[3], p[3];
    for (int k = 0; k < 3; k++) e1[k] = t[3 + k] - t[k], e2[k] = t[6 + k] - t[k];
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    float len = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(len > 0.0f)) continue;
    float facing = n[0] * primary[i].dir[0] + n[1] * primary[i].dir[1] + n[2] * primary[i].dir[2];
    for (int k = 0; k < 3; k++) n[k] *= (facing > 0 ? -1.0f : 1.0f) / len;

    /* The origin, moved off the surface by the hit point's error bound. */
    lt__offset_origin(t, hits[i].u, hits[i].v, n, p);

    /* An orthonormal frame around the normal, then cosine-weighted directions. */
    float a[3] = {fabsf(n[0]) > 0.9f ? 0.0f : 1.0f, fabsf(n[0]) > 0.9f ? 1.0f : 0.0f, 0.0f}, b1[3], b2[3];
    b1[0] = a[1] * n[2] - a[2] * n[1], b1[1] = a[2] * n[0] - a[0] * n[2], b1[2] = a[0] * n[1] - a[1] * n[0];
    float bl = sqrtf(b1[0] * b1[0] + b1[1] * b1[1] + b1[2] * b1[2]);
    for (int k = 0; k < 3; k++) b1[k] /= bl;
    b2[0] = n[1] * b1[2] - n[2] * b1[1], b2[1] = n[2] * b1[0] - n[0] * b1[2], b2[2] = n[0] * b1[1] - n[1] * b1[0];
    uint64_t rng = seed ^ (i * 0x9e3779b97f4a7c15ull);
    for (int s = 0; s < samples; s++) {
      float r = sqrtf(lt__splitmix_unit(&rng)), phi = 6.2831853f * lt__splitmix_unit(&rng), z = sqrtf(fmaxf(0.0f, 1.0f - r * r));
      float x = r * cosf(phi), y = r * sinf(phi);
      lt_ray *ray = &out[m++];
      for (int k = 0; k < 3; k++) {
        ray->org[k] = p[k];
        ray->dir[k] = x * b1[k] + y * b2[k] + z * n[k];
      }
      ray->tmin = 0.0f;
      ray->tmax = distance;

      ray->tmin = lt__secondary_tmin(t, hits[i].prim, p, ray->dir, distance);
    }
  }
  return m;
}

void lt_collision_paths(const lt_scene *scene, int agents, uint64_t seed, float *paths) {
  float lo[3], hi[3];
  lt_scene_bounds(scene, lo, hi);
  for (int a = 0; a < 6 * agents; a++) paths[a] = lo[a % 3] + lt__splitmix_unit(&seed) * (hi[a % 3] - lo[a % 3]);
}

void lt_collision_rays(const float *paths, int agents, int rays_per_agent, int frame, int frames, uint64_t seed,
                       lt_ray *out) {
  uint64_t rng = seed ^ ((uint64_t)frame * 0xbf58476d1ce4e5b9ull);
  for (int a = 0; a < agents; a++) {
    /* From this frame's position, as far as the next frame's. */
    const float *p = paths + 6 * a;
    float s0 = (float)frame / frames, s1 = (float)(frame + 1) / frames, pos[3], step = 0.0f;
    for (int k = 0; k < 3; k++) {
      pos[k] = p[k] + s0 * (p[3 + k] - p[k]);
      float d = (s1 - s0) * (p[3 + k] - p[k]);
      step += d * d;
    }
    for (int r = 0; r < rays_per_agent; r++) {
      float z = 2.0f * lt__splitmix_unit(&rng) - 1.0f, phi = 6.2831853f * lt__splitmix_unit(&rng), s = sqrtf(fmaxf(0.0f, 1.0f - z * z));
      out[(size_t)a * rays_per_agent + r] = (lt_ray){{pos[0], pos[1], pos[2]}, 0.0f, {s * cosf(phi), s * sinf(phi), z}, sqrtf(step)};
    }
  }
}
