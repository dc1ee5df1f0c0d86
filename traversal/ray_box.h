/* Conservative ray/box test: a box the ray touches is never culled. Slab distances are widened
 * by their rounding bound (Ize, "Robust BVH Ray Traversal", JCGT 2013) and an axis the ray
 * runs parallel to is decided by the origin alone, so rays with zero or negative-zero
 * direction components are exact (see lt_ray_slabs). The plain variant, without the widening,
 * exists only so that the accuracy report can measure what the widening buys. */
#ifndef LT_RAY_BOX_H
#define LT_RAY_BOX_H

#include "traversal/intersect_triangle.h"

/* Returns 1 and the entry distance when the ray meets [lo, hi] within [tmin, tmax]; pass the
 * best hit so far as tmax. A triangle inside the box that could still win or tie has its
 * clamped hit distance inside the interval accepted here (lt_clamp_to_box). */
LT_DEVICE int lt_ray_box(const lt_ray_setup *r, const float lo[3], const float hi[3], float tmax, float *t_entry) {
  float t_near, t_far;
  if (!lt_ray_slabs(r, lo, hi, !(r->flags & LT_QUERY_FLAG_PLAIN_SLABS), &t_near, &t_far)) return 0;
  t_near = t_near > r->tmin ? t_near : r->tmin;
  t_far = t_far < tmax ? t_far : tmax;
  *t_entry = t_near;
  return t_near <= t_far;
}

#endif
