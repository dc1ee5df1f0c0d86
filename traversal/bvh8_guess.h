/* Any-hit queries' guesses on the native 8-wide trees: recent answers tried before a traversal. */
#ifndef LT_BVH8_GUESS_H
#define LT_BVH8_GUESS_H

#include "traversal/bvh8_traverse.h"

/* Guesses: an any-hit query is answered by any triangle of the scene hit within [tmin, tmax],
 * so a work-item first tries copies of the triangles that answered its last eight any-hit
 * queries, the wide trees' four-triangle test run on both blocks at once (lt_bvh8_guess_steps),
 * and traverses only when none is hit. The test is the traversal's
 * own, on the scene's own floats, so a hit there is one the traversal would accept: occlusion
 * is the same as without guesses, only which triangle answers may differ (as between any two
 * any-hit traversals). Coherent queries (a point's ambient-occlusion rays, neighbouring points'
 * shadow rays) are often answered so, with no node visited. Where that does not pay (the share
 * of tries answered, times the node visits a traversal made after a failed try, below one node
 * visit, about a block test's cost) only every 32nd query tries, to learn whether it would
 * again. The on-demand BVH's wide tree (kernels/native_bvh_wide.c; LT_BVH_GUESSES=0 in the
 * environment turns them off there) and the full QBVH's native trace kernel (kernels/bvh8_trace.h)
 * use them; the state is lt_bvh8_occluders (device/bvh8_node.h), one per work-item or thread. */
/* worth, from odds and work: whether a try saves more on average than it costs. */
static inline void lt_bvh8_guess_weigh(lt_bvh8_occluders *o) { o->worth = (long long)o->odds * o->work >= 4096 * 16; }

/* The watertight test's vector steps (lt_watertight4_steps) for the eight guesses at once, the
 * two blocks side by side in the halves of AVX registers: the same operations on the same floats
 * in every lane, so each lane holds what the four-triangle test (and the one-triangle test)
 * computes for its triangle; one pass instead of two when the first block holds no answer, as
 * it mostly does not. Returns zeros | open over the lanes in `lanes` (0: all rejected). */
LT_BVH8_TARGET static inline int lt_bvh8_guess_steps(const lt_ray_setup *r, const lt_bvh8_occluders *o, int lanes,
                                                     int *zeros, float u_out[8], float v_out[8], float w_out[8],
                                                     float t_out[8]) {
  int kx = r->kx, ky = r->ky, kz = r->kz;
  const float(*lo)[4] = o->recent[0].v, (*hi)[4] = o->recent[1].v;
#define LT_GUESS_ROW(k) _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(lo[k])), _mm_loadu_ps(hi[k]), 1)
  __m256 org_kx = _mm256_set1_ps(r->org[kx]), org_ky = _mm256_set1_ps(r->org[ky]), org_kz = _mm256_set1_ps(r->org[kz]);
  __m256 sx = _mm256_set1_ps(r->sx), sy = _mm256_set1_ps(r->sy), sz = _mm256_set1_ps(r->sz);
  __m256 az = _mm256_sub_ps(LT_GUESS_ROW(kz), org_kz), bz = _mm256_sub_ps(LT_GUESS_ROW(3 + kz), org_kz);
  __m256 cz = _mm256_sub_ps(LT_GUESS_ROW(6 + kz), org_kz);
  __m256 ax = _mm256_sub_ps(_mm256_sub_ps(LT_GUESS_ROW(kx), org_kx), _mm256_mul_ps(sx, az));
  __m256 ay = _mm256_sub_ps(_mm256_sub_ps(LT_GUESS_ROW(ky), org_ky), _mm256_mul_ps(sy, az));
  __m256 bx = _mm256_sub_ps(_mm256_sub_ps(LT_GUESS_ROW(3 + kx), org_kx), _mm256_mul_ps(sx, bz));
  __m256 by = _mm256_sub_ps(_mm256_sub_ps(LT_GUESS_ROW(3 + ky), org_ky), _mm256_mul_ps(sy, bz));
  __m256 cx = _mm256_sub_ps(_mm256_sub_ps(LT_GUESS_ROW(6 + kx), org_kx), _mm256_mul_ps(sx, cz));
  __m256 cy = _mm256_sub_ps(_mm256_sub_ps(LT_GUESS_ROW(6 + ky), org_ky), _mm256_mul_ps(sy, cz));
#undef LT_GUESS_ROW
  __m256 u = _mm256_sub_ps(_mm256_mul_ps(cx, by), _mm256_mul_ps(cy, bx));
  __m256 v = _mm256_sub_ps(_mm256_mul_ps(ax, cy), _mm256_mul_ps(ay, cx));
  __m256 w = _mm256_sub_ps(_mm256_mul_ps(bx, ay), _mm256_mul_ps(by, ax));
  __m256 zero = _mm256_setzero_ps();
  __m256 any_zero = _mm256_or_ps(_mm256_or_ps(_mm256_cmp_ps(u, zero, _CMP_EQ_OQ), _mm256_cmp_ps(v, zero, _CMP_EQ_OQ)),
                                 _mm256_cmp_ps(w, zero, _CMP_EQ_OQ));
  __m256 any_neg = _mm256_or_ps(_mm256_or_ps(_mm256_cmp_ps(u, zero, _CMP_LT_OQ), _mm256_cmp_ps(v, zero, _CMP_LT_OQ)),
                                _mm256_cmp_ps(w, zero, _CMP_LT_OQ));
  __m256 any_pos = _mm256_or_ps(_mm256_or_ps(_mm256_cmp_ps(u, zero, _CMP_GT_OQ), _mm256_cmp_ps(v, zero, _CMP_GT_OQ)),
                                _mm256_cmp_ps(w, zero, _CMP_GT_OQ));
  *zeros = _mm256_movemask_ps(any_zero) & lanes;
  int open = ~_mm256_movemask_ps(_mm256_or_ps(any_zero, _mm256_and_ps(any_neg, any_pos))) & lanes;
  if (!(*zeros | open)) return 0;
  __m256 t = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(u, _mm256_mul_ps(sz, az)), _mm256_mul_ps(v, _mm256_mul_ps(sz, bz))),
                           _mm256_mul_ps(w, _mm256_mul_ps(sz, cz)));
  _mm256_storeu_ps(u_out, u), _mm256_storeu_ps(v_out, v), _mm256_storeu_ps(w_out, w), _mm256_storeu_ps(t_out, t);
  return *zeros | open;
}

/* Tries the guesses, in slot order (each lane's last steps as the wide trees' leaves take
 * them: lt_bvh8_triangle for a lane with an edge function of 0, else lt_bvh8_finish), up to
 * the first hit. Common rays only (the caller sends the others past the guesses). */
LT_BVH8_TARGET __attribute__((noinline, unused)) static int lt_bvh8_guess(const lt_ray_setup *r, lt_bvh8_occluders *o,
                                                                      lt_hit_record *hit, lt_trace_counters *c) {
  c->intersections += (lt_u32)o->filled;
  int zeros, answered = 0;
  float u[8], v[8], w[8], t[8];
  for (int todo = lt_bvh8_guess_steps(r, o, (1 << o->filled) - 1, &zeros, u, v, w, t); todo; todo &= todo - 1) {
    int lane = __builtin_ctz((unsigned)todo);
    const lt_tri4 *b = &o->recent[lane >> 2];
    if (zeros >> lane & 1) lt_bvh8_triangle(r, b, lane & 3, hit);
    else lt_bvh8_finish(r, b, lane & 3, u[lane], v[lane], w[lane], t[lane], 1, hit);
    if (hit->prim >= 0) {
      answered = 1;
      break;
    }
  }
  o->odds += ((answered ? 4096 : 0) - o->odds) >> 4;
  lt_bvh8_guess_weigh(o);
  return answered;
}

/* Whether this query tries the guesses: when they pay, and every 32nd query anyway. */
static inline int lt_bvh8_guess_tries(lt_bvh8_occluders *o) {
  return o->filled > 0 && ((o->rays++ & 31) == 0 || o->worth);
}

/* After a traversal: its node visits go into the average (when a guess was tried first), its
 * answer becomes a guess in place of the oldest. */
static inline void lt_bvh8_guess_learn(const float *verts, lt_bvh8_occluders *o, lt_i32 prim, int tried,
                                       lt_u32 steps) {
  if (tried) {
    lt_i32 visits = steps < (1u << 20) ? (lt_i32)steps : 1 << 20;
    o->work += (visits * 16 - o->work) >> 4;
    lt_bvh8_guess_weigh(o);
  }
  if (prim < 0) return;
  const float *v = verts + 9 * (size_t)prim;
  int slot = o->next;
  lt_tri4 *b = &o->recent[slot >> 2];
  for (int k = 0; k < 9; k++) b->v[k][slot & 3] = v[k];
  b->prim[slot & 3] = prim;
  o->next = (slot + 1) & 7;
  o->filled += o->filled < 8;
}

#endif
