/* The irregular grid's fast walk (traversal/irgrid_glide.h) with each step's certificate and
 * next voxel computed on the three axes at once, in SSE4.1 lanes x, y, z (w idle, treated as an
 * axis the ray runs parallel to), and written as steps, so that a native kernel can keep a few
 * rays in flight and one ray's loads overlap another's arithmetic. Included by irgrid_glide.h
 * for native x86 builds that define LT_IRG_GLIDE_SSE41; the scalar walk there is the reference
 * for every line.
 *
 * The floats are the scalar walk's: a plane is lo + j * size (no fused multiply-add: the build
 * turns contraction off), `p < hi ? p : hi` (minps), exactly lo at j = 0 and hi at j = n; a
 * crossing (plane - org) * inv; a widened distance t + |t| * eps. Where the scalar walk would
 * read a NaN as "before" the certificate fails here too (a NaN widened near crossing fails it
 * on every axis, which only sends the ray to the conservative walk sooner). The maximum and
 * minimum over the lanes are of floats that are not NaN, so their order does not matter (a
 * zero's sign can differ, which no comparison sees). Which axis is left first, when two far
 * faces tie, may differ from the scalar walk's choice; either is certified the same way. */
#ifndef LT_IRGRID_GLIDE_SSE41_H
#define LT_IRGRID_GLIDE_SSE41_H

#include <smmintrin.h>

/* What every ray of a launch shares: the fine grid's axes as lanes. */
typedef struct lt_irg_glide_grid {
  __m128 lo, hi, size, rcp;
  __m128i n, n_minus_1;
} lt_irg_glide_grid;

static inline lt_irg_glide_grid lt_irg_glide_grid_of(LT_GLOBAL const lt_grid_header *h) {
  lt_irg_glide_grid g;
  g.lo = _mm_setr_ps(h->lo.x, h->lo.y, h->lo.z, 0.0f);
  g.hi = _mm_setr_ps(h->hi.x, h->hi.y, h->hi.z, 0.0f);
  g.size = _mm_setr_ps(h->size.x, h->size.y, h->size.z, 0.0f);
  /* For guesses only: any voxel within the cell's box is certified or refused the same way. */
  g.rcp = _mm_div_ps(_mm_set1_ps(1.0f), g.size);
  g.n = _mm_setr_epi32(h->dims.x, h->dims.y, h->dims.z, 1);
  g.n_minus_1 = _mm_sub_epi32(g.n, _mm_set1_epi32(1));
  return g;
}

/* A ray on the fast walk, between steps. */
typedef struct lt_irg_glider {
  __m128 org, inv, dir;
  __m128 parallel;  /* lanes where the ray runs parallel to the axis (and w) */
  __m128i neg;      /* lanes where it runs towards lower planes */
  __m128i boundary; /* the grid's first plane in travel order */
  __m128i vox;      /* the voxel whose cell is `cell` */
  __m128 fx, on_a;  /* the last cell's far crossings, and lane a, the axis it was left by */
  float E;          /* every voxel active before E is in a tested cell's box */
  lt_i32 cell;      /* the cell to certify and test next (< 0: its top cell is not built) */
  lt_i32 steps_left;
  lt_irg_ray q;
} lt_irg_glider;

/* Where the ray crosses planes j (voxel order, 0 <= j <= n a lane). */
static inline __m128 lt_irg_glide4_crossing(const lt_irg_glide_grid *g, const lt_irg_glider *s, __m128i j) {
  __m128 p = _mm_add_ps(g->lo, _mm_mul_ps(_mm_cvtepi32_ps(j), g->size));
  p = _mm_min_ps(p, g->hi);
  p = _mm_blendv_ps(p, g->hi, _mm_castsi128_ps(_mm_cmpgt_epi32(j, g->n_minus_1)));
  p = _mm_blendv_ps(p, g->lo, _mm_castsi128_ps(_mm_cmplt_epi32(j, _mm_set1_epi32(1))));
  return _mm_mul_ps(_mm_sub_ps(p, s->org), s->inv);
}

/* The greatest and least lanes (none NaN). */
static inline float lt_irg_glide4_max(__m128 x) {
  x = _mm_max_ps(x, _mm_shuffle_ps(x, x, _MM_SHUFFLE(1, 0, 3, 2)));
  return _mm_cvtss_f32(_mm_max_ps(x, _mm_shuffle_ps(x, x, _MM_SHUFFLE(2, 3, 0, 1))));
}
static inline float lt_irg_glide4_min(__m128 x) {
  x = _mm_min_ps(x, _mm_shuffle_ps(x, x, _MM_SHUFFLE(1, 0, 3, 2)));
  return _mm_cvtss_f32(_mm_min_ps(x, _mm_shuffle_ps(x, x, _MM_SHUFFLE(2, 3, 0, 1))));
}

/* Starts a ray whose s->q was just started (lt_irg_ray_start): 1 when it is answered (it misses
 * the grid), else 0 with its first cell looked up. */
static inline int lt_irg_glide_begin(const lt_irg_view *v, const lt_irg_glide_grid *g, lt_irg_glider *s, int flags) {
  lt_irg_ray *q = &s->q;
  float t_start;
  int vox[3];
  if (lt_irg_glide_enter(v, q, !(flags & LT_QUERY_FLAG_PLAIN_SLABS), &t_start, vox)) return 1;
  __m128 zero = _mm_setzero_ps();
  s->org = _mm_setr_ps(q->r.org[0], q->r.org[1], q->r.org[2], 0.0f);
  s->inv = _mm_setr_ps(q->r.inv_dir[0], q->r.inv_dir[1], q->r.inv_dir[2], 0.0f);
  s->dir = _mm_setr_ps(q->r.dir[0], q->r.dir[1], q->r.dir[2], 0.0f);
  s->neg = _mm_castps_si128(_mm_cmplt_ps(s->dir, zero));
  s->parallel = _mm_cmpeq_ps(s->dir, zero);
  s->boundary = _mm_blendv_epi8(_mm_setzero_si128(), g->n, s->neg);
  s->vox = _mm_setr_epi32(vox[0], vox[1], vox[2], 0);
  s->fx = _mm_set1_ps(INFINITY), s->on_a = zero, s->E = t_start;
  s->steps_left = 3 * (q->w[0].axis.n + q->w[1].axis.n + q->w[2].axis.n + 3);
  s->cell = lt_irg_lookup(v->top_map, v->sub_maps, lt_irg_view_packed(v), v->fine_dims, v->shift, vox[0], vox[1], vox[2]);
  return 0;
}

/* One step: certifies and tests s->cell and looks up the next. 1 when the ray is answered, 0
 * to go on, -1 when the conservative walk is to finish it (lt_irg_advance; it is set up). */
static inline int lt_irg_glide_step(const lt_irg_view *v, const lt_irg_glide_grid *g, lt_irg_glider *s, int flags,
                                    lt_trace_counters *c) {
  int any_hit = flags & LT_QUERY_FLAG_ANY, widen = !(flags & LT_QUERY_FLAG_PLAIN_SLABS);
  lt_irg_ray *q = &s->q;
  float E = s->E;
  if (s->cell < 0 || --s->steps_left < 0) {
    lt_irg_glide_stop(v, q, E, widen);
    return -1;
  }
  __m128 inf = _mm_set1_ps(INFINITY);
  __m128i one = _mm_set1_epi32(1);
  lt_irg_cell p = lt_irg_cell_get(v->cells, v->cells16, s->cell);
  __m128i lo = _mm_setr_epi32(p.lo[0], p.lo[1], p.lo[2], 0), hi = _mm_setr_epi32(p.hi[0], p.hi[1], p.hi[2], 1);
  __m128i near = _mm_blendv_epi8(lo, hi, s->neg), far = _mm_blendv_epi8(hi, lo, s->neg);

  /* The certificate: far crossings f, widened near crossings nw (minus infinity where the near
   * face is the grid's own or the ray runs parallel), L and H. */
  __m128 f = _mm_blendv_ps(lt_irg_glide4_crossing(g, s, far), inf, s->parallel);
  __m128 nc = lt_irg_glide4_crossing(g, s, near);
  __m128 eps = _mm_set1_ps(widen ? LT_SLAB_ROUNDING_EPS : 0.0f);
  __m128 nw = _mm_add_ps(nc, _mm_mul_ps(_mm_andnot_ps(_mm_set1_ps(-0.0f), nc), eps));
  nw = _mm_blendv_ps(nw, _mm_set1_ps(-INFINITY),
                     _mm_or_ps(s->parallel, _mm_castsi128_ps(_mm_cmpeq_epi32(near, s->boundary))));
  float L = lt_irg_glide4_max(nw), H = lt_irg_glide4_min(f);
  __m128 Lv = _mm_set1_ps(L), Ev = _mm_set1_ps(E);
  __m128 ok = _mm_and_ps(_mm_cmpord_ps(nw, nw), _mm_or_ps(_mm_cmplt_ps(nw, Ev), s->on_a));
  ok = _mm_and_ps(ok, _mm_cmpgt_ps(f, Lv));
  ok = _mm_and_ps(ok, _mm_or_ps(_mm_cmpgt_ps(s->fx, Lv), s->on_a));
  if (_mm_movemask_ps(ok) != 15 || !(H > E) || !(H < INFINITY)) {
    lt_irg_glide_stop(v, q, E, widen);
    return -1;
  }
  int b = __builtin_ctz((unsigned)_mm_movemask_ps(_mm_cmpeq_ps(f, _mm_set1_ps(H))));
  __m128 on_b = _mm_castsi128_ps(_mm_cmpeq_epi32(_mm_setr_epi32(0, 1, 2, 3), _mm_set1_epi32(b)));

  /* The next voxel, past the far face on b and guessed on the others within M's box, and its
   * cell, looked up before M's triangles are tested so that the loads overlap the tests. */
  __m128i past = _mm_blendv_epi8(hi, _mm_sub_epi32(lo, one), s->neg);
  int next = b == 0 ? _mm_extract_epi32(past, 0) : b == 1 ? _mm_extract_epi32(past, 1) : _mm_extract_epi32(past, 2);
  int n_b = b == 0 ? _mm_extract_epi32(g->n, 0) : b == 1 ? _mm_extract_epi32(g->n, 1) : _mm_extract_epi32(g->n, 2);
  int leaving = next < 0 || next >= n_b;
  lt_i32 cell = s->cell;
  if (!leaving) {
    __m128 x = _mm_add_ps(s->org, _mm_mul_ps(_mm_set1_ps(H), s->dir));
    __m128i guess = _mm_cvttps_epi32(_mm_mul_ps(_mm_sub_ps(x, g->lo), g->rcp));
    guess = _mm_min_epi32(_mm_max_epi32(guess, lo), _mm_sub_epi32(hi, one));
    guess = _mm_blendv_epi8(guess, s->vox, _mm_castps_si128(s->parallel));
    s->vox = _mm_blendv_epi8(guess, _mm_set1_epi32(next), _mm_castps_si128(on_b));
    s->cell = lt_irg_lookup(v->top_map, v->sub_maps, lt_irg_view_packed(v), v->fine_dims, v->shift,
                            _mm_extract_epi32(s->vox, 0), _mm_extract_epi32(s->vox, 1), _mm_extract_epi32(s->vox, 2));
  }

  if (lt_irg_test_cell(v, q, cell, &p, any_hit, c)) return 1;
  if (q->hit.t < H || !(H <= q->t_far)) return 1;

  /* Leaving the grid: done unless a voxel is still entered on another axis by t_far. */
  if (leaving) {
    if (!(_mm_movemask_ps(_mm_andnot_ps(on_b, _mm_cmple_ps(f, _mm_set1_ps(q->t_far)))) & 7)) return 1;
    lt_irg_glide_stop(v, q, H, widen);
    return -1;
  }
  s->fx = f, s->on_a = on_b, s->E = H;
  return 0;
}

#endif
