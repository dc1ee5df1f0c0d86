/* Conservative ray/box slab test: a box the ray touches is never culled. The far distance is
 * widened by the rounding bound of the slab arithmetic (Ize, "Robust BVH Ray Traversal", JCGT
 * 2013), and an axis the ray runs parallel to is decided by the origin alone, so that rays with
 * zero or negative-zero direction components are exact. */
#ifndef LT_RAY_BOX_H
#define LT_RAY_BOX_H

#include "traversal/intersect_triangle.h"

/* Returns 1 and the entry distance when the ray meets [lo, hi] within [tmin, tmax]. */
LT_DEVICE int lt_ray_box(const lt_ray_setup *r, const float lo[3], const float hi[3], float tmax,
                         float *t_entry) {
  float t_near = r->tmin, t_far = tmax;
  for (int k = 0; k < 3; k++) {
    /* Parallel to this slab: inside it everywhere or nowhere. */
    if (r->dir[k] == 0.0f) {
      if (r->org[k] < lo[k] || r->org[k] > hi[k]) return 0;
      continue;
    }
    float t0 = (lo[k] - r->org[k]) * r->inv_dir[k];
    float t1 = (hi[k] - r->org[k]) * r->inv_dir[k];
    float t_lo = t0 < t1 ? t0 : t1, t_hi = t0 < t1 ? t1 : t0;
    t_hi += fabs(t_hi) * LT_SLAB_ROUNDING_EPS;
    t_near = t_lo > t_near ? t_lo : t_near;
    t_far = t_hi < t_far ? t_hi : t_far;
  }
  *t_entry = t_near;
  return t_near <= t_far;
}

#endif
