/* The QBVH's native path on CPUs with AVX2: the 8-wide tree of device/bvh8_node.h traced eight
 * boxes at a time, as Embree traces its BVH8. Native backend only (x86 with GCC or clang): the
 * functions carry their own target attribute, so the library still builds for baseline x86-64
 * and lt_bvh8_supported() decides at run time; OpenCL and other CPUs keep the 4-wide QBVH.
 *
 * Numerics are the 4-wide test's, lane by lane (traversal/qbvh_box4.h): the same floats in the
 * same order as lt_ray_slabs and lt_ray_box, no fused multiply-adds (the build turns
 * contraction off), the far end widened by LT_SLAB_ROUNDING_EPS, the interval met with
 * [tmin, best]. So a box is culled exactly when the binary BVH culls it, and the triangles are
 * the scalar watertight (or fast) test itself: hits are bit for bit those of every other
 * structure. A ray with a zero direction component takes the plain per-lane form.
 *
 * Leaves, with the watertight test: each block of four triangles (device/bvh8_node.h, lt_tri4)
 * goes through that test's steps up to the scaled distance as one SSE vector each, in the same
 * operations and order as the one-triangle test, so every lane holds the very floats that test
 * computes. A lane whose three edge functions are non-zero and of mixed signs is one the test
 * rejects at that point; a lane with an edge function of exactly 0 (which the test recomputes
 * in double) takes the one-triangle test itself; the others, the test's candidates, go through
 * its last steps (lt_watertight_finish: the area check, the distance in double, the clamp)
 * with their lane's floats. So hits stay bit for bit. Moller-Trumbore (the fast option) tests
 * triangle by triangle. An any-hit query stops at the first hit, in index order.
 *
 * Traversal: at an inner child the ray meets its children's eight boxes; one entered goes on
 * at once, several go on the stack with their entry distances sorted so that the nearest is
 * on top and taken next. An any-hit query compares no distances (any hit ends it): the first
 * lane entered goes on, the others wait as one entry (the node and its lanes still to enter),
 * read from the node only when their turn comes. Leaves wait on the stack like inner
 * children, so triangles are tested near to far too. A popped child whose entry distance lies
 * behind the best hit is dropped. */
#ifndef LT_BVH8_TRAVERSE_H
#define LT_BVH8_TRAVERSE_H

#if defined(__OPENCL_VERSION__) || !(defined(__x86_64__) || defined(__i386__))
#error "traversal/bvh8_traverse.h is the native backend's x86 path"
#endif

#include <immintrin.h>
#include <stddef.h>

#include "device/bvh8_node.h"
#include "traversal/ray_box.h"
#include "traversal/watertight4.h"

#define LT_BVH8_TARGET __attribute__((target("avx2")))

/* The traversal's forms (its `vector` argument): the plain per-lane box test and triangles one
 * by one, which the tests compare with the others; the vector tests for any ray; and, chosen
 * per ray inside lt_bvh8_traverse_from, the vector tests for the common ray (no zero direction
 * component, widened slabs, the watertight test) with none of the others' checks in its loop. */
#define LT_BVH8_PLAIN  0
#define LT_BVH8_VECTOR 1
#define LT_BVH8_COMMON 2

/* Which loop a query's flags give a common ray (valid, no zero direction component): the
 * any-hit or the closest-hit one, or, for flags that leave the common path (plain slabs, the
 * fast test), neither. Every caller that compiles a loop per kind dispatches by this. */
enum { LT_BVH8_QUERY_CLOSEST = 0, LT_BVH8_QUERY_ANY = 1, LT_BVH8_QUERY_OTHER = 2 };
static inline int lt_bvh8_query_form(int flags) {
  if (flags & (LT_QUERY_FLAG_PLAIN_SLABS | LT_QUERY_FLAG_FAST_TRIANGLES)) return LT_BVH8_QUERY_OTHER;
  return flags & LT_QUERY_FLAG_ANY ? LT_BVH8_QUERY_ANY : LT_BVH8_QUERY_CLOSEST;
}

/* A pending child: what its link says, and where the ray enters its box. Each visit pushes at
 * most seven (the eighth goes on at once) and the tree has at most LT_BVH_MAX_DEPTH (64)
 * levels, so 7 * 64 entries never overflow; the check stays and reports. */
#define LT_BVH8_STACK_SIZE 512
typedef struct lt_bvh8_item {
  lt_i32 first, count;
  float t;
} lt_bvh8_item;

/* An any-hit query's pending children: a node and the lanes of it still to enter (bit i: lane
 * i), the highest taken first. One entry a visit that enters two or more, and at most one a
 * level of the path from the root (a lower entry is emptied before a higher one is read), so
 * LT_BVH_MAX_DEPTH (64) levels never overflow 128; the check stays and reports. A child is read
 * from its node only when its turn comes: a query that ends on a hit pays nothing for the rest. */
#define LT_BVH8_PENDING_SIZE 128
typedef struct lt_bvh8_pending {
  lt_i32 node;
  lt_u32 lanes;
} lt_bvh8_pending;

/* Whether this CPU runs the 8-wide path. */
static inline int lt_bvh8_supported(void) {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2");
}

/* The ray's origin, negated reciprocal direction and tmin, one lane per box, made once per ray. */
typedef struct lt_bvh8_ray {
  __m256 org[3], neg_inv[3], tmin;
  lt_watertight4_ray tri; /* for the leaves' four-triangle test */
  int parallel;           /* some direction component is 0 (or -0): the plain form decides */
  int widen;              /* conservative rounding (all but the accuracy report's plain slabs) */
  int unusual;            /* parallel or not widen: one test a visit sends both off the common path */
  int filter;             /* the watertight test: leaves are tested four triangles at a time */
} lt_bvh8_ray;

LT_BVH8_TARGET static inline lt_bvh8_ray lt_bvh8_ray_make(const lt_ray_setup *r) {
  lt_bvh8_ray q;
  for (int k = 0; k < 3; k++) q.org[k] = _mm256_set1_ps(r->org[k]), q.neg_inv[k] = _mm256_set1_ps(-r->inv_dir[k]);
  q.tmin = _mm256_set1_ps(r->tmin);
  q.tri = lt_watertight4_prepare(r);
  q.filter = !(r->flags & LT_QUERY_FLAG_FAST_TRIANGLES);
  q.parallel = r->parallel;
  q.widen = !(r->flags & LT_QUERY_FLAG_PLAIN_SLABS);
  q.unusual = q.parallel || !q.widen;
  return q;
}

_Static_assert(offsetof(lt_ray_setup, dir) == offsetof(lt_ray_setup, org) + 12 &&
                   offsetof(lt_ray_setup, inv_dir) == offsetof(lt_ray_setup, org) + 24 &&
                   offsetof(lt_ray_setup, tmin) == offsetof(lt_ray_setup, org) + 36,
               "lt_ray_setup: org, dir, inv_dir and tmin follow each other");
_Static_assert(offsetof(lt_ray_setup, sy) == offsetof(lt_ray_setup, sx) + 4 &&
                   offsetof(lt_ray_setup, sz) == offsetof(lt_ray_setup, sx) + 8 &&
                   offsetof(lt_ray_setup, valid) == offsetof(lt_ray_setup, sx) + 12,
               "lt_ray_setup: sx, sy, sz and valid follow each other");

/* lt_ray_prepare for the 8-wide kernel, from a ray in the ray file's layout (origin, tmin,
 * direction, tmax): the same lt_ray_setup field for field, bit for bit (the tests compare
 * both on valid and invalid rays), with its finiteness checks, zero tests and reciprocals as
 * SSE lanes instead of a branch each and written in place instead of returned: an AO ray's
 * setup was a fifth of its instructions. */
LT_BVH8_TARGET static inline void lt_bvh8_ray_prepare(const float *ray, int flags, lt_ray_setup *r) {
  __m128 o = _mm_loadu_ps(ray), d = _mm_loadu_ps(ray + 4); /* ox oy oz tmin, dx dy dz tmax */
  __m128 magnitude = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff)), zero = _mm_setzero_ps();
  __m128 xyz = _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0)), inf = _mm_set1_ps(INFINITY);
  __m128 d_abs = _mm_and_ps(d, magnitude);

  /* Valid: origin and tmin finite, direction finite, tmin <= tmax (false for a NaN tmax; lane
   * 3 of o is tmin, of d tmax), some direction component not 0. A component is either == 0 or
   * != 0 (a NaN is != 0), so the zero ones are the complement of the others. */
  __m128 ok = _mm_and_ps(_mm_cmplt_ps(_mm_and_ps(o, magnitude), inf),
                         _mm_blend_ps(_mm_cmplt_ps(d_abs, inf), _mm_cmple_ps(o, d), 8));
  __m128 nonzero = _mm_cmpneq_ps(d, zero);
  int nonzero_d = _mm_movemask_ps(nonzero) & 7;
  r->valid = _mm_movemask_ps(ok) == 15 && nonzero_d;
  r->flags = flags;

  /* 1/d, 0 where d is 0 (either sign), clamped to the largest float; a NaN stays NaN. */
  __m128 inv = _mm_div_ps(_mm_set1_ps(1.0f), d);
  inv = _mm_min_ps(_mm_set1_ps(LT_FLOAT_MAX), _mm_max_ps(_mm_set1_ps(-LT_FLOAT_MAX), inv));
  inv = _mm_and_ps(inv, _mm_and_ps(nonzero, xyz));
  r->org4 = (lt_v4)_mm_and_ps(o, xyz), r->inv4 = (lt_v4)inv;
  /* org, dir and inv_dir (nine floats in a row, then tmin and tmax) as three four-float
   * stores, each one's fourth float overwritten by the next store, the last's by tmin. */
  _mm_storeu_ps(r->org, o), _mm_storeu_ps(r->org + 3, d), _mm_storeu_ps(r->org + 6, inv);
  r->tmin = ray[3], r->tmax = ray[7];
  r->parallel = nonzero_d != 7;

  /* The watertight test's axes and shear, as lt_ray_prepare makes them: kz = ax > ay ? (ax > az
   * ? 0 : 2) : (ay > az ? 1 : 2) from the three comparisons' bits (ax > ay, ax > az, ay > az)
   * as a table of eight two-bit entries; kx and ky follow it, swapped where dir[kz] < 0. */
  __m128 a = _mm_shuffle_ps(d_abs, d_abs, _MM_SHUFFLE(3, 1, 0, 0)), b = _mm_shuffle_ps(d_abs, d_abs, _MM_SHUFFLE(3, 2, 2, 1));
  int bits = _mm_movemask_ps(_mm_cmpgt_ps(a, b)) & 7;
  int kz = 0x192a >> (2 * bits) & 3, kx = kz == 2 ? 0 : kz + 1, ky = kx == 2 ? 0 : kx + 1;
  int negative = _mm_movemask_ps(_mm_cmplt_ps(d, zero)) >> kz & 1;
  int sx_axis = negative ? ky : kx, sy_axis = negative ? kx : ky;
  r->kz = kz, r->kx = sx_axis, r->ky = sy_axis;
  /* sx = dir[kx] / dkz, sy = dir[ky] / dkz, sz = 1 / dkz as one vector division (each lane
   * rounded as the scalar one), stored over sx, sy, sz and valid, which is written again. */
  int valid = r->valid;
  __m128 dkz = valid ? _mm_permutevar_ps(d, _mm_set1_epi32(kz)) : _mm_set1_ps(1.0f);
  __m128 num = _mm_blend_ps(_mm_permutevar_ps(d, _mm_setr_epi32(sx_axis, sy_axis, 0, 0)), _mm_set1_ps(1.0f), 12);
  _mm_storeu_ps(&r->sx, _mm_div_ps(num, dkz));
  r->valid = valid;
}

/* One bit per lane that holds a child (count != 0). The vector test does without it: an empty
 * lane's box (LT_BVH8_EMPTY_LANE_BOX) is rejected by the slab arithmetic itself. */
LT_BVH8_TARGET static inline int lt_bvh8_child_lanes(const lt_bvh8_node *n) {
  __m256i count = _mm256_loadu_si256((const __m256i *)n->count);
  __m256i empty = _mm256_cmpeq_epi32(count, _mm256_setzero_si256());
  return ~_mm256_movemask_ps(_mm256_castsi256_ps(empty)) & 0xff;
}

/* The plain form: each lane through lt_ray_box. One bit per lane whose box the ray meets
 * within [tmin, tmax], those lanes' entry distances in t_entry. */
static inline int lt_bvh8_box8_scalar(const lt_ray_setup *r, const lt_bvh8_node *n, float tmax, float t_entry[8]) {
  int mask = 0;
  for (int lane = 0; lane < LT_BVH8_WIDTH; lane++) {
    float lo[3], hi[3];
    lt_bvh8_child_box(n, lane, lo, hi);
    if (lt_ray_box(r, lo, hi, tmax, &t_entry[lane])) mask |= 1 << lane;
  }
  return mask;
}

/* The same eight tests as one AVX register per slab. Empty lanes are dropped by their box (a
 * far point, device/bvh8_node.h), not by a mask of the lanes in use: one entered all the same
 * (a ray through that very point) is a leaf of no triangles. */
LT_BVH8_TARGET __attribute__((always_inline)) static inline int lt_bvh8_box8_slabs(const lt_bvh8_ray *q,
                                                                                   const lt_bvh8_node *n, float tmax,
                                                                                   float t_entry[8], int widen) {
  const float *planes = n->lo_x;
  __m256 near_t, far_t;
  for (int k = 0; k < 3; k++) {
    /* Axis k of all eight boxes, met in the order lt_ray_slabs meets them. lt_ray_slabs starts
     * from [-inf, +inf]; here the first axis' interval is taken as it is, the same floats: the
     * distances are never NaN (finite planes and origin, a finite non-zero 1/d: this form is not
     * run for a ray with a zero direction component). lt_ray_slabs' (plane - org) * (1/d) is
     * computed as (org - plane) * -(1/d), the same float (rounding is symmetric in sign) but
     * where the two meet exactly, +0 and -0 swapped, which no comparison tells apart: so the
     * plane is the subtraction's memory operand, no load of its own (six fewer a visit). */
    __m256 t0 = _mm256_mul_ps(_mm256_sub_ps(q->org[k], _mm256_loadu_ps(planes + 16 * k)), q->neg_inv[k]);
    __m256 t1 = _mm256_mul_ps(_mm256_sub_ps(q->org[k], _mm256_loadu_ps(planes + 16 * k + 8)), q->neg_inv[k]);
    near_t = k ? _mm256_max_ps(_mm256_min_ps(t0, t1), near_t) : _mm256_min_ps(t0, t1);
    far_t = k ? _mm256_min_ps(_mm256_max_ps(t1, t0), far_t) : _mm256_max_ps(t1, t0);
  }
  if (widen) {
    __m256 magnitude = _mm256_and_ps(far_t, _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff)));
    far_t = _mm256_add_ps(far_t, _mm256_mul_ps(magnitude, _mm256_set1_ps(LT_SLAB_ROUNDING_EPS)));
  }

  /* Within [tmin, tmax], as lt_ray_box clamps. */
  near_t = _mm256_max_ps(near_t, q->tmin);
  far_t = _mm256_min_ps(far_t, _mm256_set1_ps(tmax));
  _mm256_storeu_ps(t_entry, near_t);
  return _mm256_movemask_ps(_mm256_cmp_ps(near_t, far_t, _CMP_LE_OS));
}

/* lt_bvh8_box8_slabs for the ray's kind: the common one (widened, no zero direction component)
 * tested once a visit; a parallel ray takes the plain form, empty lanes masked. */
LT_BVH8_TARGET static inline int lt_bvh8_box8(const lt_ray_setup *r, const lt_bvh8_ray *q, const lt_bvh8_node *n,
                                              float tmax, float t_entry[8]) {
  if (__builtin_expect(!q->unusual, 1)) return lt_bvh8_box8_slabs(q, n, tmax, t_entry, 1);
  if (q->parallel) return lt_bvh8_box8_scalar(r, n, tmax, t_entry) & lt_bvh8_child_lanes(n);
  return lt_bvh8_box8_slabs(q, n, tmax, t_entry, 0);
}

/* Lane `lane` of a block: its triangle's three vertices. */
static inline void lt_bvh8_block_vertices(const lt_tri4 *b, int lane, float v0[3], float v1[3], float v2[3]) {
  for (int k = 0; k < 3; k++) v0[k] = b->v[k][lane], v1[k] = b->v[3 + k][lane], v2[k] = b->v[6 + k][lane];
}

/* The one-triangle test of the ray's kind on lane `lane` of a block. */
LT_BVH8_TARGET static inline void lt_bvh8_triangle(const lt_ray_setup *r, const lt_tri4 *b, int lane,
                                                  lt_hit_record *hit) {
  float v0[3], v1[3], v2[3];
  lt_bvh8_block_vertices(b, lane, v0, v1, v2);
  lt_intersect_triangle(r, v0, v1, v2, b->prim[lane], hit);
}

#ifndef LT_HAVE_DOUBLE
#error "the 8-wide path's finish computes the hit distance in double, as lt_hit_distance_checked does"
#endif

/* lt_watertight_finish for a ray with no zero direction component, on the triangle's vertices
 * as vectors: the distance from the triangle's plane as four doubles at once, the clamp to the
 * triangle's box as four floats at once. The same operations on the same values in the same
 * order as lt_hit_distance_checked, lt_clamp_to_box and lt_ray_slabs' vector form (minps and
 * maxps are their ternaries, the sums run in their order from 0), so the hit is theirs bit for
 * bit; test_qbvh8 compares the two on every lane. In scalar form these steps were about a
 * sixth of an AO ray's instructions (nearly every AO ray ends on a hit).
 *
 * An any-hit query asks only whether the hit is recorded, and the distance that decides it
 * always ends inside the stretch [near, far] of the ray within the triangle's box (the clamp;
 * NaN only when that stretch is empty, or when both the distance in double and the scaled one
 * are unusable). So when near <= far lies within [tmin, tmax], no best hit is held yet and the
 * scaled distance is a number, the hit is recorded whatever the double steps would give: they
 * are skipped, and the hit keeps the scaled distance, clamped. The decision is the one-triangle
 * test's bit for bit; only the distance an any-hit query reports may differ in its last bits. */
LT_BVH8_TARGET static inline int lt_bvh8_finish(const lt_ray_setup *r, const lt_tri4 *block, int lane, float u,
                                                float v, float w, float t_scaled, int any_hit,
                                                lt_hit_record *hit) {
  float det = u + v + w;
  if (det == 0.0f) return 0;
  float inv_det = 1.0f / det, t = t_scaled * inv_det;
  /* The lane's vertices from the block the test has just read (no other line is touched),
   * their fourth lanes 0. */
  const float(*rows)[4] = block->v;
  __m128 a = _mm_setr_ps(rows[0][lane], rows[1][lane], rows[2][lane], 0.0f);
  __m128 b = _mm_setr_ps(rows[3][lane], rows[4][lane], rows[5][lane], 0.0f);
  __m128 c = _mm_setr_ps(rows[6][lane], rows[7][lane], rows[8][lane], 0.0f);

  /* The stretch of the ray inside the triangle's box (lt_clamp_to_box). */
  __m128 lo = _mm_min_ps(c, _mm_min_ps(a, b)), hi = _mm_max_ps(c, _mm_max_ps(a, b));
  __m128 org = (__m128)r->org4, inv = (__m128)r->inv4;
  __m128 t0 = _mm_mul_ps(_mm_sub_ps(lo, org), inv), t1 = _mm_mul_ps(_mm_sub_ps(hi, org), inv);
  __m128 t_lo = _mm_min_ps(t0, t1), t_hi = _mm_max_ps(t1, t0);
  /* lt_ray_slabs' per-axis steps in lane 0: near = l > near ? l : near is maxss(l, near), and
   * far = h < far ? h : far is minss(h, far), axis by axis. lt_ray_slabs starts from [-inf,
   * +inf], which the first axis' distances replace as they are: they are never NaN (finite
   * planes and origin, a finite non-zero 1/d on this path). */
  __m128 near_v = t_lo, far_v = t_hi;
  near_v = _mm_max_ss(_mm_shuffle_ps(t_lo, t_lo, 1), near_v), far_v = _mm_min_ss(_mm_shuffle_ps(t_hi, t_hi, 1), far_v);
  near_v = _mm_max_ss(_mm_shuffle_ps(t_lo, t_lo, 2), near_v), far_v = _mm_min_ss(_mm_shuffle_ps(t_hi, t_hi, 2), far_v);
  float near_t = _mm_cvtss_f32(near_v), far_t = _mm_cvtss_f32(far_v);
  far_t += lt_fabsf(far_t) * LT_SLAB_ROUNDING_EPS;
  /* The clamped distance lies in [near, far] (or is NaN): a stretch wholly before tmin or after
   * tmax, or behind a best hit, is no hit, whatever the distance. An AO ray's own triangle, in
   * a flat box behind its origin, ends here, before the double steps. */
  if (far_t < r->tmin || near_t > r->tmax || (hit->prim >= 0 && near_t > hit->t)) return 0;

  /* The plane's normal, the edges' cross product (none: no area, never hit). */
  __m256d a_d = _mm256_cvtps_pd(a), e1 = _mm256_sub_pd(_mm256_cvtps_pd(b), a_d),
          e2 = _mm256_sub_pd(_mm256_cvtps_pd(c), a_d);
  __m256d n = _mm256_sub_pd(_mm256_mul_pd(_mm256_permute4x64_pd(e1, _MM_SHUFFLE(3, 0, 2, 1)),
                                          _mm256_permute4x64_pd(e2, _MM_SHUFFLE(3, 1, 0, 2))),
                            _mm256_mul_pd(_mm256_permute4x64_pd(e1, _MM_SHUFFLE(3, 1, 0, 2)),
                                          _mm256_permute4x64_pd(e2, _MM_SHUFFLE(3, 0, 2, 1))));
  if ((_mm256_movemask_pd(_mm256_cmp_pd(n, _mm256_setzero_pd(), _CMP_EQ_OQ)) & 7) == 7) return 0;

  /* The distance from the plane, in double, unless the stretch alone decides (above). */
  if (!(any_hit && hit->prim < 0 && near_t <= far_t && near_t >= r->tmin && far_t <= r->tmax && t == t)) {
    __m256d to_plane = _mm256_mul_pd(n, _mm256_sub_pd(a_d, _mm256_cvtps_pd((__m128)r->org4)));
    __m256d along = _mm256_mul_pd(n, _mm256_cvtps_pd(_mm_setr_ps(r->dir[0], r->dir[1], r->dir[2], 0.0f)));
    double p[4], d[4];
    _mm256_storeu_pd(p, to_plane), _mm256_storeu_pd(d, along);
    double num = 0.0 + p[0], den = 0.0 + d[0];
    num += p[1], den += d[1];
    num += p[2], den += d[2];
    double plane = num / den;
    if (den != 0.0 && plane == plane && plane < 3.0e38 && plane > -3.0e38) t = (float)plane;
  }
  t = !(near_t <= far_t) ? NAN : t < near_t ? near_t : t > far_t ? far_t : t;
  return lt_record_hit(r, t, v * inv_det, w * inv_det, block->prim[lane], hit);
}

/* The watertight test of a block's four triangles (the lanes in `lanes`), in index order:
 * lt_intersect_watertight's steps up to the scaled distance as one SSE vector each, with the
 * same operations in the same order, so that every lane holds the very floats that test
 * computes for its triangle (see the top of this file). A lane whose edge functions are
 * non-zero and of mixed signs is rejected here, as that test rejects it; a lane with one of
 * them exactly 0 (which that test recomputes in double) takes the one-triangle test; the
 * others are the test's candidates and go through its last steps (lt_watertight_finish) with
 * the lane's floats. Returns 1 when an any-hit query found its hit (the rest is not tested). */
LT_BVH8_TARGET __attribute__((always_inline)) static inline int lt_bvh8_tri4_watertight(
    const lt_ray_setup *r, const lt_bvh8_ray *q, const lt_tri4 *b, int lanes, int any_hit, int common,
    lt_hit_record *hit) {
  lt_watertight4_lanes l;
  int todo = lt_watertight4_steps(r, &q->tri, (const __m128 *)b->v, lanes, &l);
  for (; todo; todo &= todo - 1) {
    int lane = __builtin_ctz((unsigned)todo);
    if (l.zeros >> lane & 1) {
      lt_bvh8_triangle(r, b, lane, hit);
    } else if (common || !r->parallel) {
      lt_bvh8_finish(r, b, lane, l.u[lane], l.v[lane], l.w[lane], l.t_scaled[lane], any_hit, hit);
    } else {
      float v0[3], v1[3], v2[3];
      lt_bvh8_block_vertices(b, lane, v0, v1, v2);
      lt_watertight_finish(r, v0, v1, v2, l.u[lane], l.v[lane], l.w[lane], l.t_scaled[lane], b->prim[lane], hit);
    }
    if (any_hit && hit->prim >= 0) return 1;
  }
  return 0;
}

/* A leaf's `count` triangles from position `first`, in index order: blocks of four through
 * the vector test (a vector form and the watertight test), else one by one. Returns 1 when an
 * any-hit query found its hit; the rest of the leaf is then not tested, either way. */
LT_BVH8_TARGET __attribute__((always_inline)) static inline int lt_bvh8_leaf(const lt_ray_setup *r,
                                                                             const lt_bvh8_ray *q,
                                                                             const lt_tri4 *blocks, lt_i32 first,
                                                                             lt_i32 count, int vector, int any_hit,
                                                                             lt_hit_record *hit) {
  if (vector != LT_BVH8_COMMON && (vector == LT_BVH8_PLAIN || !q->filter)) {
    for (lt_i32 k = first; k < first + count; k++) {
      lt_bvh8_triangle(r, &blocks[k >> 2], k & 3, hit);
      if (any_hit && hit->prim >= 0) return 1;
    }
    return 0;
  }
  /* A leaf of up to four triangles lies in one block, from lane first & 3 (a longer one
   * starts a block): the first block's lanes are the leaf's ones shifted there. */
  const lt_tri4 *b = &blocks[first >> 2];
  int shift = first & 3;
  for (lt_i32 left = count; left > 0; left -= 4, b++, shift = 0)
    if (lt_bvh8_tri4_watertight(r, q, b, (left < 4 ? (1 << left) - 1 : 15) << shift, any_hit,
                                vector == LT_BVH8_COMMON, hit))
      return 1;
  return 0;
}

/* One bit per lane that is an exit (device/bvh8_node.h: count < 0 and first < 0). */
LT_BVH8_TARGET static inline int lt_bvh8_exit_lanes(const lt_bvh8_node *n) {
  __m256 first = _mm256_loadu_ps((const float *)n->first), count = _mm256_loadu_ps((const float *)n->count);
  return _mm256_movemask_ps(_mm256_and_ps(first, count)) & 0xff;
}

/* lt_bvh8_traverse_from for one kind of query and one form, both constants where it is inlined. */
LT_BVH8_TARGET __attribute__((always_inline)) static inline int lt_bvh8_traverse_query(
    const lt_bvh8_node *nodes, const lt_tri4 *blocks, const lt_ray_setup *r, lt_i32 root, lt_hit_record *io, lt_trace_counters *c, int vector, lt_bvh8_item *exits, int max_exits, int *exit_count,
    int any_hit) {
  /* Field by field: callers write the record a field or two at a time, and one 16-byte load
   * of it would wait for those stores to reach the cache (no store forwards to a load that
   * spans several): a tenth of the AO trace's samples sat there. */
  lt_hit_record hit;
  hit.t = io->t, hit.u = io->u, hit.v = io->v, hit.prim = io->prim;
  int status = 0;
  lt_bvh8_ray q = lt_bvh8_ray_make(r);
  lt_bvh8_item stack[LT_BVH8_STACK_SIZE];        /* closest hits */
  lt_bvh8_pending pending[LT_BVH8_PENDING_SIZE]; /* any hit */
  int sp = 0;
  lt_u32 steps = 0, tests = 0;     /* counted here, added once: c may alias the stack for the compiler */
  lt_i32 first = root, count = -1; /* the root's children */
  while (r->valid) {
    if (count < 0) {
      /* An inner child: its children's boxes against the ray, up to the best hit so far. */
      steps++;
      const lt_bvh8_node *n = &nodes[first];
      float t[8];
      int mask = vector == LT_BVH8_COMMON ? lt_bvh8_box8_slabs(&q, n, hit.t, t, 1)
                 : vector                 ? lt_bvh8_box8(r, &q, n, hit.t, t)
                                          : lt_bvh8_box8_scalar(r, n, hit.t, t) & lt_bvh8_child_lanes(n);
      /* Exits entered are the binary traversal's to take (trees still being built only). */
      int out = exits ? mask & lt_bvh8_exit_lanes(n) : 0;
      if (out) {
        if (*exit_count + __builtin_popcount((unsigned)out) > max_exits) {
          status = 1;
          break;
        }
        mask &= ~out;
        do {
          int lane = __builtin_ctz((unsigned)out);
          out &= out - 1;
          lt_bvh8_item item = {n->first[lane], n->count[lane], t[lane]};
          exits[(*exit_count)++] = item;
        } while (out);
      }
      if (mask) {
        int lane = __builtin_ctz((unsigned)mask);
        mask &= mask - 1;

        /* One entered, the common case of coherent rays: on with it. */
        if (!mask) {
          first = n->first[lane], count = n->count[lane];
          continue;
        }

        /* Any hit: no order to keep, as Embree's occlusion traversal: the first entered on at
         * once, the others pending (highest lane first), without their entry distances (read only
         * to order and cull, which an any-hit query does not do). */
        if (any_hit) {
          if (sp == LT_BVH8_PENDING_SIZE) {
            status = -1;
            break;
          }
          pending[sp].node = first, pending[sp].lanes = (lt_u32)mask, sp++;
          first = n->first[lane], count = n->count[lane];
          continue;
        }

        /* Two: the nearer on, the farther on the stack. */
        if (!(mask & (mask - 1))) {
          if (sp == LT_BVH8_STACK_SIZE) {
            status = -1;
            break;
          }
          int other = __builtin_ctz((unsigned)mask);
          int near = t[other] < t[lane] ? other : lane, far = near == lane ? other : lane;
          stack[sp].first = n->first[far], stack[sp].count = n->count[far], stack[sp].t = t[far], sp++;
          first = n->first[near], count = n->count[near];
          continue;
        }

        /* More: all on the stack, sorted far to near (insertion sort, at most eight). */
        if (sp + LT_BVH8_WIDTH > LT_BVH8_STACK_SIZE) {
          status = -1;
          break;
        }
        int base = sp;
        stack[sp].first = n->first[lane], stack[sp].count = n->count[lane], stack[sp].t = t[lane], sp++;
        do {
          lane = __builtin_ctz((unsigned)mask);
          mask &= mask - 1;
          lt_bvh8_item item = {n->first[lane], n->count[lane], t[lane]};
          int j = sp++;
          while (j > base && stack[j - 1].t < item.t) stack[j] = stack[j - 1], j--;
          stack[j] = item;
        } while (mask);
        sp--;
        first = stack[sp].first, count = stack[sp].count;
        continue;
      }
    } else {
      /* A leaf: four triangles at a time. */
      tests += (lt_u32)count;
      if (lt_bvh8_leaf(r, &q, blocks, first, count, vector, any_hit, &hit)) break;
    }

    /* The nearest pending child the best hit does not rule out (ties are kept: a triangle at
     * the same distance with a lower number still wins). An any-hit query has none yet. */
    if (any_hit) {
      if (sp == 0) break;
      lt_bvh8_pending *p = &pending[sp - 1];
      int lane = 31 - __builtin_clz(p->lanes);
      const lt_bvh8_node *from = &nodes[p->node];
      p->lanes &= ~(1u << lane);
      sp -= p->lanes == 0;
      first = from->first[lane], count = from->count[lane];
      continue;
    }
    while (sp > 0 && stack[sp - 1].t > hit.t) sp--;
    if (sp == 0) break;
    sp--;
    first = stack[sp].first, count = stack[sp].count;
  }
  c->traversal_steps += steps, c->intersections += tests;
  *io = hit;
  return status;
}

/* Traces one ray prepared with lt_ray_prepare (its flags set) through the 8-wide subtree whose
 * root's children are the lanes of node `root`, from the best hit so far in *io (prim -1 and
 * t = tmax when none), which it updates. Returns 0, or -1 when the stack would overflow (never
 * on a tree of LT_BVH_MAX_DEPTH levels). `vector` is LT_BVH8_VECTOR, or LT_BVH8_PLAIN for
 * the plain box test and every triangle one by one (the tests compare both). The on-demand traversal enters the wide
 * tree of its tree's built part here (kernels/native_bvh_wide.c): exit lanes the ray enters
 * go to exits[] (at most max_exits, *exit_count of them; 1 is returned when more would), with
 * their entry distances, for the binary traversal; exits NULL: the tree has none. The
 * common ray's traversal is made twice, once for any-hit queries and once for closest hits, so
 * that neither tests the kind of query or of ray in its loop; the other rays share one out of
 * line. */
#define LT_BVH8_TRAVERSE_PARAMS                                                                             \
  const lt_bvh8_node *nodes, const lt_tri4 *blocks, const lt_ray_setup *r, lt_i32 root, lt_hit_record *io, \
      lt_trace_counters *c, int vector, lt_bvh8_item *exits, int max_exits, int *exit_count
#define LT_BVH8_TRAVERSE_ARGS nodes, blocks, r, root, io, c, vector, exits, max_exits, exit_count

/* Three functions, each compiled (and its registers allocated) for one loop. */
LT_BVH8_TARGET __attribute__((noinline, unused)) static int lt_bvh8_traverse_rare(LT_BVH8_TRAVERSE_PARAMS) {
  return lt_bvh8_traverse_query(LT_BVH8_TRAVERSE_ARGS, (r->flags & LT_QUERY_FLAG_ANY) != 0);
}
LT_BVH8_TARGET __attribute__((noinline, unused)) static int lt_bvh8_traverse_any(LT_BVH8_TRAVERSE_PARAMS) {
  (void)vector;
  return lt_bvh8_traverse_query(nodes, blocks, r, root, io, c, LT_BVH8_COMMON, exits, max_exits, exit_count, 1);
}
LT_BVH8_TARGET __attribute__((noinline, unused)) static int lt_bvh8_traverse_closest(LT_BVH8_TRAVERSE_PARAMS) {
  (void)vector;
  return lt_bvh8_traverse_query(nodes, blocks, r, root, io, c, LT_BVH8_COMMON, exits, max_exits, exit_count, 0);
}

LT_BVH8_TARGET static inline int lt_bvh8_traverse_from(LT_BVH8_TRAVERSE_PARAMS) {
  int form = lt_bvh8_query_form(r->flags);
  if (vector == LT_BVH8_PLAIN || r->parallel || form == LT_BVH8_QUERY_OTHER)
    return lt_bvh8_traverse_rare(LT_BVH8_TRAVERSE_ARGS);
  if (form == LT_BVH8_QUERY_ANY) return lt_bvh8_traverse_any(LT_BVH8_TRAVERSE_ARGS);
  return lt_bvh8_traverse_closest(LT_BVH8_TRAVERSE_ARGS);
}

/* Traces one ray through a whole finished 8-wide tree (node 0 holds the root's children);
 * writes the hit (prim -1 on a miss) and returns as lt_bvh8_traverse_from. */
LT_BVH8_TARGET static inline int lt_bvh8_traverse_with(const lt_bvh8_node *nodes, const lt_tri4 *blocks,
                                                       const lt_ray_setup *r, lt_hit_record *out,
                                                       lt_trace_counters *c, int vector) {
  out->t = r->tmax, out->u = out->v = 0.0f, out->prim = -1;
  return lt_bvh8_traverse_from(nodes, blocks, r, 0, out, c, vector, NULL, 0, NULL);
}

#endif
