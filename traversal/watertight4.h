/* The watertight test (traversal/intersect_triangle.h) of up to four triangles at once, the
 * native backend's x86 path: its vector steps (lt_watertight4_steps) are shared by the QBVH's
 * 8-wide leaves (traversal/bvh8_traverse.h: blocks of four triangles stored as rows) and by
 * structures whose cells list triangles by number (lt_watertight4: the irregular grid, each
 * triangle found through a reference into the scene's vertex array, 9 floats a triangle). SSE2
 * only, which every x86-64 CPU has, so no run-time check.
 *
 * Numerics are the one-triangle test's, lane by lane: the steps up to the scaled distance as
 * one SSE vector each, with the same operations in the same order (the build turns contraction
 * off), so that every lane holds the very floats the one-triangle test computes. A lane whose
 * three edge functions are non-zero and of mixed signs is rejected, as that test rejects it; a
 * lane with an edge function of exactly 0 (which that test recomputes in double) takes the
 * one-triangle test itself; the others go through its last steps (lt_watertight_finish, or the
 * 8-wide path's vector form of it) with their lane's floats. Lanes are finished in order, so an
 * any-hit query stops where the one-by-one loop would. */
#ifndef LT_WATERTIGHT4_H
#define LT_WATERTIGHT4_H

#if defined(__OPENCL_VERSION__) || !defined(__SSE2__)
#error "traversal/watertight4.h is the native backend's SSE2 path"
#endif

#include <emmintrin.h>

#include "traversal/intersect_triangle.h"

/* The ray's origin on the test's axes (kx, ky, kz) and its shear, one copy a lane, made once a ray. */
typedef struct lt_watertight4_ray {
  __m128 org_kx, org_ky, org_kz, sx, sy, sz;
} lt_watertight4_ray;

static inline lt_watertight4_ray lt_watertight4_prepare(const lt_ray_setup *r) {
  lt_watertight4_ray q;
  q.org_kx = _mm_set1_ps(r->org[r->kx]), q.org_ky = _mm_set1_ps(r->org[r->ky]), q.org_kz = _mm_set1_ps(r->org[r->kz]);
  q.sx = _mm_set1_ps(r->sx), q.sy = _mm_set1_ps(r->sy), q.sz = _mm_set1_ps(r->sz);
  return q;
}

/* What the vector steps leave for the lanes' last steps: the lanes with an edge function of
 * exactly 0 (the one-triangle test recomputes those in double), the candidates, and each lane's
 * edge functions and scaled distance. */
typedef struct lt_watertight4_lanes {
  int zeros, open;
  float u[4], v[4], w[4], t_scaled[4];
} lt_watertight4_lanes;

/* The watertight test's steps up to the scaled distance for four triangles at once, their
 * vertices as rows (v[3 * j + k]: coordinate k of vertex j, one triangle a lane) and only the
 * lanes in `lanes`. Returns zeros | open (0: every lane rejected, nothing else written). Shared
 * by the irregular grid's cells (below) and the QBVH's 8-wide leaves. */
__attribute__((always_inline)) static inline int lt_watertight4_steps(const lt_ray_setup *r,
                                                                      const lt_watertight4_ray *q, const __m128 v[9],
                                                                      int lanes, lt_watertight4_lanes *out) {
  /* Vertices relative to the origin, sheared and scaled into ray space, as the one-triangle
   * test computes them: a[k] = v0[k] - org[k], then ax = a[kx] - sx * a[kz], and so on. */
  int kx = r->kx, ky = r->ky, kz = r->kz;
  __m128 az = _mm_sub_ps(v[kz], q->org_kz), bz = _mm_sub_ps(v[3 + kz], q->org_kz);
  __m128 cz = _mm_sub_ps(v[6 + kz], q->org_kz);
  __m128 ax = _mm_sub_ps(_mm_sub_ps(v[kx], q->org_kx), _mm_mul_ps(q->sx, az));
  __m128 ay = _mm_sub_ps(_mm_sub_ps(v[ky], q->org_ky), _mm_mul_ps(q->sy, az));
  __m128 bx = _mm_sub_ps(_mm_sub_ps(v[3 + kx], q->org_kx), _mm_mul_ps(q->sx, bz));
  __m128 by = _mm_sub_ps(_mm_sub_ps(v[3 + ky], q->org_ky), _mm_mul_ps(q->sy, bz));
  __m128 cx = _mm_sub_ps(_mm_sub_ps(v[6 + kx], q->org_kx), _mm_mul_ps(q->sx, cz));
  __m128 cy = _mm_sub_ps(_mm_sub_ps(v[6 + ky], q->org_ky), _mm_mul_ps(q->sy, cz));

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
   * w * cz). */
  __m128 t_scaled = _mm_add_ps(_mm_add_ps(_mm_mul_ps(u, _mm_mul_ps(q->sz, az)), _mm_mul_ps(vv, _mm_mul_ps(q->sz, bz))),
                               _mm_mul_ps(w, _mm_mul_ps(q->sz, cz)));
  out->zeros = zeros, out->open = open;
  _mm_storeu_ps(out->u, u), _mm_storeu_ps(out->v, vv), _mm_storeu_ps(out->w, w), _mm_storeu_ps(out->t_scaled, t_scaled);
  return zeros | open;
}

/* Tests triangles prims[0 .. count) (1 <= count <= 4) in that order; returns 1 when an any-hit
 * query found its hit (the rest is then not tested). Always inlined: the irregular grid's trace,
 * whose walk is one large function, otherwise calls it (1% more instructions there). */
__attribute__((always_inline)) static inline int lt_watertight4(const lt_ray_setup *r, const lt_watertight4_ray *q,
                                                                const float *verts, const lt_i32 *prims, int count,
                                                                int any_hit, lt_hit_record *hit) {
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
  lt_watertight4_lanes l;
  int todo = lt_watertight4_steps(r, q, v, (1 << count) - 1, &l);

  /* Each candidate and zero lane in reference order. */
  for (; todo; todo &= todo - 1) {
    int lane = __builtin_ctz((unsigned)todo);
    const float *p = t[lane];
    float v0[3] = {p[0], p[1], p[2]}, v1[3] = {p[3], p[4], p[5]}, v2[3] = {p[6], p[7], p[8]};
    if (l.zeros >> lane & 1)
      lt_intersect_watertight(r, v0, v1, v2, prims[lane], hit);
    else
      lt_watertight_finish(r, v0, v1, v2, l.u[lane], l.v[lane], l.w[lane], l.t_scaled[lane], prims[lane], hit);
    if (any_hit && hit->prim >= 0) return 1;
  }
  return 0;
}

#endif
