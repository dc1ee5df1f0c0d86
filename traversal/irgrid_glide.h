/* The irregular grid's fast walk: cell to cell through the far faces, as the paper walks it,
 * with each step certified exact by a few comparisons; where a certificate fails, the ray goes
 * on with the conservative walk of traversal/irgrid_traverse.h from where it stands.
 *
 * The conservative walk finds, at every step, the exact ranges of voxels the ray is in on each
 * axis (guesses checked against plane crossings, the widened exits of the voxels left behind)
 * and looks them up. Most of that is not needed: a ray deep inside a large cell moves through
 * many voxel planes that are not cell faces. This walk looks up one guessed voxel a step and
 * checks the cell it finds, in cell terms only.
 *
 * Terms. On axis k, voxel u is active at distance s when the ray has entered it (its near
 * plane's crossing is at or before s) and its widened exit is not before s, as in the uniform
 * walk (traversal/grid_traverse.h); R(s) is the product over the axes of the active voxels (on
 * an axis the ray runs parallel to, the one voxel whose closed slab holds the origin, fixed for
 * the whole ray). The uniform walk's argument shows that the reference's hit W, at distance t,
 * is referenced by the cell of some voxel of R(t), t lies in [t_start, t_far], and a cell
 * references every triangle that meets a voxel of its (grown) box. So the walk is exact if,
 * whenever it stops with its best hit at distance b, every voxel of R(s) for s in [t_start, b]
 * lies in the box of a cell it has tested, and it stops only with b before every distance it
 * has not covered (or past t_far).
 *
 * For a cell M, with n_k and f_k the crossings of its near and far faces on axis k (in travel
 * order) and L = the greatest widened n_k over the axes whose near face is not the grid's own,
 * H = the least f_k: for s in (L, H), R(s) lies in M's box, because on every axis the voxels
 * before M have left (widened exits never decrease along the axis) and the voxel past M's far
 * face is not yet entered. Call (L, H) M's clean interval.
 *
 * The walk. The first cell M is the one of a voxel guessed at t_start; it is certified when
 * L < t_start < H. Then [t_start, H) is covered. A cell X covering up to E = H_X is left
 * through its far face on axis a (the least f); the next cell M is the one of the voxel just
 * past that face, the others guessed from the position at E and clamped to X's box, so that
 * M's near face on a is at or before X's far face. M is certified when, on every axis k other
 * than a, its widened n_k is before E and X's f_k is after L, and every f_k of M is after L
 * and H > E. Then for s in [E, L], R(s) lies in the box of X or of M: on the axes k other
 * than a the active voxels lie in both boxes' ranges (the nearer faces left before E, the
 * farther not entered by L), and on a they run from X's near face (left before E, by X's own
 * certificate) to M's far face (not entered by L), split between X and M at X's far face. With
 * M's clean interval, [E, H) is covered. A wrong guess only fails a certificate.
 *
 * Stopping. After testing M, the walk stops when its best hit (tmax if none) is before H, or
 * when H is past t_far. When M's far face is the grid's own, it stops if no other far face of M
 * is crossed by t_far (no voxel is entered before t_far, and the last ones stay in M's box);
 * otherwise, and at every failed certificate or a voxel whose top cell is not built, the
 * conservative walk starts at E (every voxel of R(s) for s before E has been tested) and
 * finishes the ray. */
#ifndef LT_IRGRID_GLIDE_H
#define LT_IRGRID_GLIDE_H

#include "traversal/irgrid_traverse.h"

/* A native build for x86 with SSE4.1 that defines this to 1 runs each step's certificate on
 * the three axes at once (traversal/irgrid_glide_sse41.h: the same floats, the same hits). */
#ifndef LT_IRG_GLIDE_SSE41
#define LT_IRG_GLIDE_SSE41 0
#endif

/* Where the ray crosses fine plane j (0 <= j <= n) of axis k, in voxel order (not travel
 * order): lt_grid_crossing's arithmetic. */
LT_DEVICE float lt_irg_glide_crossing(const lt_grid_walk *w, int j) {
  return (lt_grid_plane(&w->axis, j) - w->org) * w->inv;
}

/* Hands the ray to the conservative walk at distance E (its ranges there, no cover); returns 0
 * for lt_irg_advance to go on with. */
LT_DEVICE int lt_irg_glide_stop(const lt_irg_view *v, lt_irg_ray *q, float E, int widen) {
  for (int k = 0; k < 3; k++) lt_grid_walk_start(&q->w[k], &q->r, v->header, k, E, widen);
  q->cover = -1;
  q->state = LT_IRG_RAY_VISIT;
  return 0;
}

/* Enters the grid: 1 when the ray misses it (answered), else 0 with t_start, q->t_far, the
 * axes (the conservative walk's fields, which it sets again if it takes over) and the first
 * voxel, guessed. */
LT_DEVICE int lt_irg_glide_enter(const lt_irg_view *v, lt_irg_ray *q, int widen, float *t_start, int *vox) {
  if (lt_irg_enter(v, q, widen, t_start)) return 1;
  float t = *t_start;
  for (int k = 0; k < 3; k++) {
    lt_grid_walk *w = &q->w[k];
    w->axis = lt_grid_axis_of(v->header, k);
    w->org = q->r.org[k], w->inv = q->r.inv_dir[k];
    w->sign = q->r.dir[k] > 0.0f ? 1 : q->r.dir[k] < 0.0f ? -1 : 0;
    vox[k] = w->sign == 0 ? lt_grid_last_cell(&w->axis, w->org) : lt_grid_cell_guess(&w->axis, w->org + t * q->r.dir[k]);
  }
  return 0;
}

#if LT_IRG_GLIDE_SSE41
/* Steps instead (lt_irg_glide_begin, lt_irg_glide_step), for a kernel with rays in flight. */
#include "traversal/irgrid_glide_sse41.h"
#else
/* Runs a ray that has not started (state LT_IRG_RAY_START) by the fast walk; returns 1 when
 * it is answered, 0 when lt_irg_advance is to finish it (its walk is then set up). */
LT_DEVICE int lt_irg_glide(const lt_irg_view *v, lt_irg_ray *q, int flags, lt_trace_counters *c) {
  int any_hit = flags & LT_QUERY_FLAG_ANY, widen = !(flags & LT_QUERY_FLAG_PLAIN_SLABS);
  float t_start, t_far;
  int vox[3];
  if (lt_irg_glide_enter(v, q, widen, &t_start, vox)) return 1;
  t_far = q->t_far;

  float E = t_start, fx[3] = {INFINITY, INFINITY, INFINITY};
  int a = -1;
  int cap = 3 * (q->w[0].axis.n + q->w[1].axis.n + q->w[2].axis.n + 3);
  int packed = lt_irg_view_packed(v);
  lt_i32 cell = lt_irg_lookup(v->top_map, v->sub_maps, packed, v->fine_dims, v->shift, vox[0], vox[1], vox[2]);
  for (int step = 0; step < cap && cell >= 0; step++) {
    lt_irg_cell p = lt_irg_cell_get(v->cells, v->cells16, cell);

    /* The certificate (the header's conditions), the clean interval's ends L and H, and the
     * axis b of the far face crossed first. */
    float f[3], L = -INFINITY, H = INFINITY;
    int ok = 1, b = -1;
    for (int k = 0; k < 3; k++) {
      const lt_grid_walk *w = &q->w[k];
      f[k] = INFINITY;
      if (w->sign == 0) continue;
      int near = w->sign > 0 ? p.lo[k] : p.hi[k], far = w->sign > 0 ? p.hi[k] : p.lo[k];
      f[k] = lt_irg_glide_crossing(w, far);
      if (!(f[k] >= H)) H = f[k], b = k;
      if (near != (w->sign > 0 ? 0 : w->axis.n)) {
        float n = lt_grid_widen(lt_irg_glide_crossing(w, near), widen);
        L = n > L ? n : L;
        if (k != a && !(n < E)) ok = 0;
      }
    }
    for (int k = 0; k < 3; k++)
      if (q->w[k].sign != 0 && (!(f[k] > L) || (k != a && !(fx[k] > L)))) ok = 0;
    if (!ok || !(H > E) || b < 0) break;

    /* The next voxel, past the far face on b and guessed on the others within M's box, and its
     * cell, looked up before M's triangles are tested so that the loads overlap the tests. */
    const lt_grid_walk *w = &q->w[b];
    int next = w->sign > 0 ? p.hi[b] : p.lo[b] - 1, leaving = next < 0 || next >= w->axis.n;
    lt_i32 next_cell = -1;
    if (!leaving) {
      for (int k = 0; k < 3; k++) {
        const lt_grid_walk *x = &q->w[k];
        if (k == b) {
          vox[k] = next;
        } else if (x->sign != 0) {
          int g = lt_grid_cell_guess(&x->axis, x->org + H * q->r.dir[k]);
          vox[k] = g < p.lo[k] ? p.lo[k] : g >= p.hi[k] ? p.hi[k] - 1 : g;
        }
      }
      next_cell = lt_irg_lookup(v->top_map, v->sub_maps, packed, v->fine_dims, v->shift, vox[0], vox[1], vox[2]);
    }

    if (lt_irg_test_cell(v, q, cell, &p, any_hit, c)) return 1;
    if (q->hit.t < H || !(H <= t_far)) return 1;

    /* Leaving the grid: done unless a voxel is still entered on another axis by t_far. */
    if (leaving) {
      int more = 0;
      for (int k = 0; k < 3; k++) more |= k != b && f[k] <= t_far;
      if (!more) return 1;
      E = H;
      break;
    }
    for (int k = 0; k < 3; k++) fx[k] = f[k];
    E = H, a = b, cell = next_cell;
  }
  return lt_irg_glide_stop(v, q, E, widen);
}
#endif

#endif
