/* A ray prepared once for every test it meets: validity, reciprocal direction, the axis
 * permutation and shear of the watertight triangle test (Woop, Benthin and Wald 2013), the
 * query flags that pick the numerics, and the conservative slab interval of a box (Ize,
 * "Robust BVH Ray Traversal", JCGT 2(2), 2013) that boxes and triangles share. */
#ifndef LT_RAY_H
#define LT_RAY_H

#include "device/types.h"

/* The relative error of a slab distance is at most 2 * gamma(3), with gamma(n) =
 * n * eps / (1 - n * eps) and eps = 2^-24 (Ize 2013; pbrt 3, section 3.9.2). */
#define LT_SLAB_ROUNDING_EPS 3.5762793e-7f

/* The slab test runs its three axes as one vector on the native backend; PoCL vectorises the
 * scalar form across work-items itself and was 35% slower tracing with the vector form. */
#ifdef __OPENCL_VERSION__
#define LT_VECTOR_SLABS 0
#else
#define LT_VECTOR_SLABS 1
#endif

/* Query flags. They travel in the kernels' any-hit argument, so that every entry point and
 * both backends get them without another parameter. */
#define LT_QUERY_FLAG_ANY 1            /* any hit instead of the closest */
#define LT_QUERY_FLAG_FAST_TRIANGLES 2 /* Moller-Trumbore instead of the watertight test */
#define LT_QUERY_FLAG_PLAIN_SLABS 4    /* box tests without conservative rounding (measurements only) */

/* The largest finite float: the reciprocal of a direction component so small that 1/d
 * overflows, so that slab distances keep their signs and 0 * (1/d) stays 0 instead of NaN. */
#define LT_FLOAT_MAX 3.40282347e+38f

typedef struct lt_ray_setup {
#if LT_VECTOR_SLABS
  lt_v4 org4, inv4; /* org and inv_dir as vectors (w = 0), for lt_ray_slabs */
#endif
  float org[3];
  float dir[3];
  float inv_dir[3]; /* 1/dir, at most LT_FLOAT_MAX in magnitude; unused where dir is 0 */
  float tmin, tmax;
  int kx, ky, kz;   /* axes permuted so that kz has the largest |dir| */
  float sx, sy, sz; /* shear constants */
  int valid;        /* 0 for NaN or infinite components, a zero direction or tmin > tmax */
#if LT_VECTOR_SLABS
  int parallel; /* some direction component is 0 (or -0): lt_ray_slabs takes the per-axis loop */
#endif
  int flags;        /* LT_QUERY_FLAG_* */
} lt_ray_setup;

LT_DEVICE lt_ray_setup lt_ray_prepare(float ox, float oy, float oz, float tmin, float dx, float dy, float dz,
                                      float tmax) {
  lt_ray_setup r;
  r.org[0] = ox, r.org[1] = oy, r.org[2] = oz;
  r.dir[0] = dx, r.dir[1] = dy, r.dir[2] = dz;
  r.tmin = tmin, r.tmax = tmax;
  r.flags = 0;

  /* Reject what has no defined answer; tmax may be +infinity, nothing else may be non-finite. */
  r.valid = lt_isfinite(ox) && lt_isfinite(oy) && lt_isfinite(oz) && lt_isfinite(dx) && lt_isfinite(dy) &&
            lt_isfinite(dz) && lt_isfinite(tmin) && !isnan(tmax) && tmin <= tmax &&
            (dx != 0.0f || dy != 0.0f || dz != 0.0f);
  for (int k = 0; k < 3; k++) {
    float inv = r.dir[k] != 0.0f ? 1.0f / r.dir[k] : 0.0f;
    r.inv_dir[k] = inv > LT_FLOAT_MAX ? LT_FLOAT_MAX : inv < -LT_FLOAT_MAX ? -LT_FLOAT_MAX : inv;
  }
#if LT_VECTOR_SLABS
  r.org4 = lt_v4_make(ox, oy, oz, 0.0f);
  r.inv4 = lt_v4_make(r.inv_dir[0], r.inv_dir[1], r.inv_dir[2], 0.0f);
  r.parallel = dx == 0.0f || dy == 0.0f || dz == 0.0f;
#endif

  /* kz is the dimension where |dir| is largest; swapping kx and ky keeps the winding. */
  float ax = lt_fabsf(dx), ay = lt_fabsf(dy), az = lt_fabsf(dz);
  r.kz = ax > ay ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2);
  r.kx = r.kz == 2 ? 0 : r.kz + 1;
  r.ky = r.kx == 2 ? 0 : r.kx + 1;
  if (r.dir[r.kz] < 0.0f) {
    int swap = r.kx;
    r.kx = r.ky;
    r.ky = swap;
  }
  float dkz = r.valid ? r.dir[r.kz] : 1.0f;
  r.sx = r.dir[r.kx] / dkz;
  r.sy = r.dir[r.ky] / dkz;
  r.sz = 1.0f / dkz;
  return r;
}

/* The interval of the ray's line (all t, not only [tmin, tmax]) inside the box [lo, hi]:
 * returns 0 when an axis the ray runs parallel to already puts the origin outside. The far
 * end is widened by the slab arithmetic's rounding bound unless `widen` is 0.
 *
 * Every slab distance is fl(fl(plane - org) * inv_dir): rounding is monotone, so a box that
 * holds another (a node and a triangle's own box) always gets a wider interval, bit for bit.
 * Each distance is within gamma(3) of exact, relative (Ize 2013); widening the far end by
 * 2 * gamma(3) of its magnitude keeps every box the exact line touches. */
LT_DEVICE int lt_ray_slabs(const lt_ray_setup *r, const float lo[3], const float hi[3], int widen, float *t_near,
                           float *t_far) {
  float near_t = -INFINITY, far_t = INFINITY;
#if LT_VECTOR_SLABS
  if (!r->parallel) {
    /* The loop below for a ray parallel to no slab, three axes at once: every lane computes
     * the same floats, and the intervals meet in the same order. */
    lt_v4 lo4 = lt_v4_make(lo[0], lo[1], lo[2], 0.0f), hi4 = lt_v4_make(hi[0], hi[1], hi[2], 0.0f);
    lt_v4 t0 = (lo4 - r->org4) * r->inv4, t1 = (hi4 - r->org4) * r->inv4;
    lt_v4 t_lo = lt_v4_min(t0, t1), t_hi = lt_v4_max(t1, t0);
    for (int k = 0; k < 3; k++) {
      float l = lt_v4_lane(t_lo, k), h = lt_v4_lane(t_hi, k);
      near_t = l > near_t ? l : near_t;
      far_t = h < far_t ? h : far_t;
    }
    if (widen) far_t += lt_fabsf(far_t) * LT_SLAB_ROUNDING_EPS;
    *t_near = near_t;
    *t_far = far_t;
    return 1;
  }
#endif
  for (int k = 0; k < 3; k++) {
    /* Parallel to this slab: inside it everywhere or nowhere, decided exactly. */
    if (r->dir[k] == 0.0f) {
      if (r->org[k] < lo[k] || r->org[k] > hi[k]) return 0;
      continue;
    }
    float t0 = (lo[k] - r->org[k]) * r->inv_dir[k];
    float t1 = (hi[k] - r->org[k]) * r->inv_dir[k];
    float t_lo = t0 < t1 ? t0 : t1, t_hi = t0 < t1 ? t1 : t0;
    near_t = t_lo > near_t ? t_lo : near_t;
    far_t = t_hi < far_t ? t_hi : far_t;
  }
  if (widen) far_t += lt_fabsf(far_t) * LT_SLAB_ROUNDING_EPS;
  *t_near = near_t;
  *t_far = far_t;
  return 1;
}

#endif
