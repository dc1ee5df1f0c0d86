/* The watertight test (traversal/intersect_triangle.h) of up to four triangles at once, each
 * found through a reference (a triangle number into the scene's vertex array, 9 floats a
 * triangle): the native backend's x86 path for structures whose cells list triangles by number
 * (the irregular grid). SSE2 only, which every x86-64 CPU has, so no run-time check.
 *
 * Numerics are the one-triangle test's, lane by lane, as in the QBVH's 8-wide leaves
 * (traversal/bvh8_traverse.h): the steps up to the scaled distance as one SSE vector each, with
 * the same operations in the same order (the build turns contraction off), so that every lane
 * holds the very floats the one-triangle test computes. A lane whose three edge functions are
 * non-zero and of mixed signs is rejected, as that test rejects it; a lane with an edge
 * function of exactly 0 (which that test recomputes in double) takes the one-triangle test
 * itself; the others go through its last steps (lt_watertight_finish) with their lane's floats.
 * Lanes are finished in reference order, so an any-hit query stops where the one-by-one loop
 * would. */
#ifndef LT_WATERTIGHT4_H
#define LT_WATERTIGHT4_H

#if defined(__OPENCL_VERSION__) || !defined(__SSE2__)
#error "traversal/watertight4.h is the native backend's SSE2 path"
#endif

#include <emmintrin.h>

#include "traversal/intersect_triangle.h"

/* The ray's origin and shear, one copy a lane, made once a ray. */
typedef struct lt_watertight4_ray {
  __m128 org[3], sx, sy, sz;
} lt_watertight4_ray;

static inline lt_watertight4_ray lt_watertight4_prepare(const lt_ray_setup *r) {
  lt_watertight4_ray q;
  for (int k = 0; k < 3; k++) q.org[k] = _mm_set1_ps(r->org[k]);
  q.sx = _mm_set1_ps(r->sx), q.sy = _mm_set1_ps(r->sy), q.sz = _mm_set1_ps(r->sz);
  return q;
}

/* Tests triangles prims[0 .. count) (1 <= count <= 4) in that order; returns 1 when an any-hit
 * query found its hit (the rest is then not tested). */
static inline int lt_watertight4(const lt_ray_setup *r, const lt_watertight4_ray *q, const float *verts,
                                 const lt_i32 *prims, int count, int any_hit, lt_hit_record *hit) {
  /* The four triangles' 9 floats as rows of four lanes: three loads a triangle (the third
   * overlaps the second, so that nothing past the triangle is read), then transposed. A lane
   * past count repeats the last triangle and is masked off. */
  const float *t[4];
  for (int i = 0; i < 4; i++) t[i] = verts + 9 * (long)prims[i < count ? i : count - 1];
  __m128 v[9];
  {
    __m128 r0 = _mm_loadu_ps(t[0]), r1 = _mm_loadu_ps(t[1]), r2 = _mm_loadu_ps(t[2]), r3 = _mm_loadu_ps(t[3]);
    _MM_TRANSPOSE4_PS(r0, r1, r2, r3);
    v[0] = r0, v[1] = r1, v[2] = r2, v[3] = r3;
    r0 = _mm_loadu_ps(t[0] + 4), r1 = _mm_loadu_ps(t[1] + 4), r2 = _mm_loadu_ps(t[2] + 4), r3 = _mm_loadu_ps(t[3] + 4);
    _MM_TRANSPOSE4_PS(r0, r1, r2, r3);
    v[4] = r0, v[5] = r1, v[6] = r2, v[7] = r3;
    /* The last float of each: lane 3 of the loads at t + 5. */
    __m128 a = _mm_loadu_ps(t[0] + 5), b = _mm_loadu_ps(t[1] + 5), c = _mm_loadu_ps(t[2] + 5),
           d = _mm_loadu_ps(t[3] + 5);
    __m128 ab = _mm_unpackhi_ps(a, b), cd = _mm_unpackhi_ps(c, d); /* (a2 b2 a3 b3), (c2 d2 c3 d3) */
    v[8] = _mm_movehl_ps(cd, ab);                                  /* (a3 b3 c3 d3) */
  }
  int lanes = (1 << count) - 1;

  /* Vertices relative to the origin, sheared and scaled into ray space, as the one-triangle
   * test computes them: a[k] = v0[k] - org[k], then ax = a[kx] - sx * a[kz], and so on. */
  int kx = r->kx, ky = r->ky, kz = r->kz;
  __m128 az = _mm_sub_ps(v[kz], q->org[kz]), bz = _mm_sub_ps(v[3 + kz], q->org[kz]);
  __m128 cz = _mm_sub_ps(v[6 + kz], q->org[kz]);
  __m128 ax = _mm_sub_ps(_mm_sub_ps(v[kx], q->org[kx]), _mm_mul_ps(q->sx, az));
  __m128 ay = _mm_sub_ps(_mm_sub_ps(v[ky], q->org[ky]), _mm_mul_ps(q->sy, az));
  __m128 bx = _mm_sub_ps(_mm_sub_ps(v[3 + kx], q->org[kx]), _mm_mul_ps(q->sx, bz));
  __m128 by = _mm_sub_ps(_mm_sub_ps(v[3 + ky], q->org[ky]), _mm_mul_ps(q->sy, bz));
  __m128 cx = _mm_sub_ps(_mm_sub_ps(v[6 + kx], q->org[kx]), _mm_mul_ps(q->sx, cz));
  __m128 cy = _mm_sub_ps(_mm_sub_ps(v[6 + ky], q->org[ky]), _mm_mul_ps(q->sy, cz));

  /* The edge functions; the lanes the test rejects (none zero, signs mixed) and those it
   * recomputes in double (one zero). */
  __m128 u = _mm_sub_ps(_mm_mul_ps(cx, by), _mm_mul_ps(cy, bx));
  __m128 vv = _mm_sub_ps(_mm_mul_ps(ax, cy), _mm_mul_ps(ay, cx));
  __m128 w = _mm_sub_ps(_mm_mul_ps(bx, ay), _mm_mul_ps(by, ax));
  __m128 zero = _mm_setzero_ps();
  __m128 any_zero = _mm_or_ps(_mm_or_ps(_mm_cmpeq_ps(u, zero), _mm_cmpeq_ps(vv, zero)), _mm_cmpeq_ps(w, zero));
  __m128 any_neg = _mm_or_ps(_mm_or_ps(_mm_cmplt_ps(u, zero), _mm_cmplt_ps(vv, zero)), _mm_cmplt_ps(w, zero));
  __m128 any_pos = _mm_or_ps(_mm_or_ps(_mm_cmpgt_ps(u, zero), _mm_cmpgt_ps(vv, zero)), _mm_cmpgt_ps(w, zero));
  int zeros = _mm_movemask_ps(any_zero) & lanes;
  int open = ~_mm_movemask_ps(_mm_or_ps(any_zero, _mm_and_ps(any_neg, any_pos))) & lanes;
  if (!(zeros | open)) return 0;

  /* The scaled distance of the candidates (az = sz * a[kz], and so on, then u * az + v * bz +
   * w * cz), then each lane in reference order. */
  __m128 t_scaled = _mm_add_ps(_mm_add_ps(_mm_mul_ps(u, _mm_mul_ps(q->sz, az)), _mm_mul_ps(vv, _mm_mul_ps(q->sz, bz))),
                               _mm_mul_ps(w, _mm_mul_ps(q->sz, cz)));
  float uu[4], vl[4], ww[4], ts[4];
  _mm_storeu_ps(uu, u), _mm_storeu_ps(vl, vv), _mm_storeu_ps(ww, w), _mm_storeu_ps(ts, t_scaled);
  for (int todo = zeros | open; todo; todo &= todo - 1) {
    int lane = __builtin_ctz((unsigned)todo);
    const float *p = t[lane];
    float v0[3] = {p[0], p[1], p[2]}, v1[3] = {p[3], p[4], p[5]}, v2[3] = {p[6], p[7], p[8]};
    if (zeros >> lane & 1)
      lt_intersect_watertight(r, v0, v1, v2, prims[lane], hit);
    else
      lt_watertight_finish(r, v0, v1, v2, uu[lane], vl[lane], ww[lane], ts[lane], prims[lane], hit);
    if (any_hit && hit->prim >= 0) return 1;
  }
  return 0;
}

#endif
