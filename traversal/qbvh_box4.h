/* The conservative ray/box test of traversal/ray_box.h on a QBVH node's four boxes at once:
 * SoA lanes as one float4 in OpenCL and one SSE register on the native backend. Lane by lane
 * it computes the same floats in the same order as lt_ray_slabs and lt_ray_box (the min/max
 * forms `a < b ? a : b` and `a > b ? a : b`, the far end widened by LT_SLAB_ROUNDING_EPS, the
 * interval met with [tmin, best]), so it culls exactly the boxes the binary BVH's test culls:
 * never one the ray touches. lt_qbvh_box4_scalar is the plain C form, lane after lane through
 * lt_ray_box itself; tests check that both give the same masks and distances. A ray with a
 * zero direction component takes the plain form, where such an axis is decided exactly. */
#ifndef LT_QBVH_BOX4_H
#define LT_QBVH_BOX4_H

#include "device/qbvh_node.h"
#include "traversal/ray_box.h"

/* The ray's origin, reciprocal direction and tmin, one lane per box, made once per ray. */
typedef struct lt_qbvh_ray4 {
  lt_v4 org[3], inv[3], tmin;
  int parallel; /* some direction component is 0 (or -0): the plain form decides */
  int widen;    /* conservative rounding (all but the accuracy report's plain slabs) */
} lt_qbvh_ray4;

LT_DEVICE lt_qbvh_ray4 lt_qbvh_ray4_make(const lt_ray_setup *r) {
  lt_qbvh_ray4 q;
  for (int k = 0; k < 3; k++) q.org[k] = lt_v4_splat(r->org[k]), q.inv[k] = lt_v4_splat(r->inv_dir[k]);
  q.tmin = lt_v4_splat(r->tmin);
  q.parallel = r->dir[0] == 0.0f || r->dir[1] == 0.0f || r->dir[2] == 0.0f;
  q.widen = !(r->flags & LT_QUERY_FLAG_PLAIN_SLABS);
  return q;
}

#ifdef __OPENCL_VERSION__
#define lt_qbvh_load4(p) (*(p))
#define lt_qbvh_abs4(v) fabs(v)
/* One bit per lane where a <= b. */
LT_DEVICE int lt_qbvh_le_mask(float4 a, float4 b) {
  int4 m = a <= b;
  return (m.x & 1) | (m.y & 2) | (m.z & 4) | (m.w & 8);
}
LT_DEVICE void lt_qbvh_store4(float4 v, float out[4]) { vstore4(v, 0, out); }
#else
LT_DEVICE lt_v4 lt_qbvh_load4(const lt_float4 *p) {
  lt_v4 v;
  memcpy(&v, p, sizeof v);
  return v;
}
LT_DEVICE lt_v4 lt_qbvh_abs4(lt_v4 v) { return (lt_v4)((lt_vi4)v & (lt_vi4){0x7fffffff, 0x7fffffff, 0x7fffffff, 0x7fffffff}); }
#if defined(__SSE__)
LT_DEVICE int lt_qbvh_le_mask(lt_v4 a, lt_v4 b) { return _mm_movemask_ps(_mm_cmple_ps((__m128)a, (__m128)b)); }
#else
LT_DEVICE int lt_qbvh_le_mask(lt_v4 a, lt_v4 b) {
  lt_vi4 m = a <= b;
  return (m[0] & 1) | (m[1] & 2) | (m[2] & 4) | (m[3] & 8);
}
#endif
LT_DEVICE void lt_qbvh_store4(lt_v4 v, float out[4]) { memcpy(out, &v, sizeof v); }
#endif

/* One bit per lane that holds a child (count != 0): empty lanes have empty boxes, which the
 * slab arithmetic does not reject by itself. */
#ifdef __OPENCL_VERSION__
LT_DEVICE int lt_qbvh_child_lanes(LT_GLOBAL const lt_qbvh_node *n) {
  int4 m = vload4(0, n->count) != (int4)(0);
  return (m.x & 1) | (m.y & 2) | (m.z & 4) | (m.w & 8);
}
#else
LT_DEVICE int lt_qbvh_child_lanes(const lt_qbvh_node *n) {
  lt_vi4 count;
  memcpy(&count, n->count, sizeof count);
  lt_vi4 empty = count == (lt_vi4){0, 0, 0, 0};
#if defined(__SSE__)
  return ~_mm_movemask_ps((__m128)empty) & 15;
#else
  return ~((empty[0] & 1) | (empty[1] & 2) | (empty[2] & 4) | (empty[3] & 8)) & 15;
#endif
}
#endif

/* The plain form: each lane through lt_ray_box. Returns one bit per lane whose box the ray
 * meets within [tmin, tmax] (pass the best hit so far as tmax) and those lanes' entry
 * distances in t_entry. */
LT_DEVICE int lt_qbvh_box4_scalar(const lt_ray_setup *r, LT_GLOBAL const lt_qbvh_node *n, float tmax, float t_entry[4]) {
  int mask = 0;
  for (int lane = 0; lane < 4; lane++) {
    float lo[3], hi[3];
    lt_qbvh_child_box(n, lane, lo, hi);
    if (lt_ray_box(r, lo, hi, tmax, &t_entry[lane])) mask |= 1 << lane;
  }
  return mask;
}

/* The same four tests as one vector per slab. */
LT_DEVICE int lt_qbvh_box4(const lt_ray_setup *r, const lt_qbvh_ray4 *q, LT_GLOBAL const lt_qbvh_node *n, float tmax,
                           float t_entry[4]) {
  if (q->parallel) return lt_qbvh_box4_scalar(r, n, tmax, t_entry);
  LT_GLOBAL const lt_float4 *planes = &n->lo_x;
  lt_v4 near_t = lt_v4_splat(-INFINITY), far_t = lt_v4_splat(INFINITY);
  for (int k = 0; k < 3; k++) {
    /* Axis k of all four boxes, met in the order lt_ray_slabs meets them. */
    lt_v4 t0 = (lt_qbvh_load4(planes + 2 * k) - q->org[k]) * q->inv[k];
    lt_v4 t1 = (lt_qbvh_load4(planes + 2 * k + 1) - q->org[k]) * q->inv[k];
    near_t = lt_v4_max(lt_v4_min(t0, t1), near_t);
    far_t = lt_v4_min(lt_v4_max(t1, t0), far_t);
  }
  if (q->widen) far_t = far_t + lt_qbvh_abs4(far_t) * lt_v4_splat(LT_SLAB_ROUNDING_EPS);

  /* Within [tmin, tmax], as lt_ray_box clamps. */
  near_t = lt_v4_max(near_t, q->tmin);
  far_t = lt_v4_min(far_t, lt_v4_splat(tmax));
  lt_qbvh_store4(near_t, t_entry);
  return lt_qbvh_le_mask(near_t, far_t);
}

#endif
