/* Closest-hit and any-hit traversal of the irregular grid (Perard-Gayot, Kalojanov and
 * Slusallek 2017, section 4), on demand: a ray that reaches a top cell not built yet asks for
 * its task and suspends, keeping its walk and best hit.
 *
 * The walk is the uniform grid's conservative 3D-DDA (traversal/grid_traverse.h) run over the
 * fine virtual grid, with one change that makes it an irregular grid's walk: after testing the
 * cells of the voxels around the ray, it jumps to T, the earliest exit from those cells' boxes
 * (the far planes, crossed with the fine grid's own arithmetic), instead of stepping voxel by
 * voxel through them. Every voxel boundary before T is skipped; those at T and later are taken
 * as the uniform walk takes them. So the paper's "leave through the cell's far planes, look up
 * the next voxel" is done with the uniform walk's exactness, and a step never goes back.
 *
 * Why skipping loses no hit. The uniform walk is exact (grid_traverse.h): the reference's hit W
 * lies in some voxel of the walk's product of per-axis ranges at or before the walk stops, and
 * the cell of every voxel references every triangle that meets the voxel. At each step this walk
 * tests the cells of every voxel of Q, the product of the current ranges (not only the slab the
 * last boundary added), and takes T = the least, over the voxels u of Q and the axes k on which
 * u_k is the last of Q's range, of where the ray crosses the far face on k of u's cell's (grown)
 * box. Let v be a voxel of a product the uniform walk would visit before T. On every axis, v_k is
 * at least the first of Q's range (ranges only drop voxels at their low end); let u_k be v_k or
 * the last of Q's range, whichever is lower: u is in Q. On an axis where v_k is within the range,
 * u_k = v_k, and u's cell's box, which holds u, holds v_k. On an axis where v_k is beyond it,
 * u_k is the range's last, so T is at most the crossing of the box's far face on k; the plane
 * that enters v_k was crossed before T, and crossings never decrease with the plane number, so
 * v_k lies below that far face (and above u_k, within the box). So u's cell's box holds v.
 * Every triangle that meets v then meets that box and, by the builder's expansion rule, meets
 * the cell's box before expansion: the cell references it, and it has been tested. A hit found
 * before T makes the walk stop at the next boundary after T with nothing between untested, as
 * the uniform walk would. Voxels of Q short of the range's last on an axis do not bound T on
 * it: just after a boundary the voxel left behind (kept in range by the widening) would
 * otherwise hold T at the boundary and the jump would gain nothing.
 *
 * Two refinements make a round cheaper, and the argument above holds with each.
 *  - A voxel u of Q may stand in any tested box that holds it instead of its own cell's: the
 *    argument used only that u's box holds u, that its triangles were tested, and that T is at
 *    most its far-face crossings. So after a boundary on axis b, the voxels of Q before the last
 *    on b use the cover, a cell of the round before whose box held every voxel of the ranges
 *    then (an integer test of the box against the ranges); these voxels lie in those ranges, so
 *    they need no lookup and no test.
 *  - A voxel u that is not the last of its range on some axis j leaves the ranges by W_u, the
 *    least such widened exit: a voxel v with v_j = u_j is in a product of the walk only up to
 *    W_u. If W_u is before B_u, the least of u's far-face crossings on the axes where it is last,
 *    u bounds nothing: for v reached through u on an axis k beyond its range, v_k is entered at
 *    or before W_u < B_u, below the far face on k, as above. The voxel left behind at a boundary
 *    (kept in the ranges only by the widening) therefore no longer holds T near the boundary.
 *
 * The stopping rule and the ranges are the uniform walk's; the cells of Q are tested once each
 * (a few recent ones are remembered, so a cell the walk meets again is not retested: retesting
 * would change nothing but the counts). */
#ifndef LT_IRGRID_TRAVERSE_H
#define LT_IRGRID_TRAVERSE_H

#include "device/irgrid_cells.h"
#include "device/pool.h"
#include "traversal/grid_traverse.h"

/* A native kernel that includes traversal/watertight4.h first and defines this to 1 tests a
 * cell's triangles four at a time (x86 with SSE2); OpenCL tests them one by one. */
#ifndef LT_IRG_WATERTIGHT4
#define LT_IRG_WATERTIGHT4 0
#endif

/* Cells a ray remembers having tested (a power of two). */
#define LT_IRG_RECENT 4

/* What traversal reads. */
typedef struct lt_irg_view {
  LT_GLOBAL const lt_grid_header *header; /* the fine grid */
  LT_GLOBAL const lt_i32 *top_map, *sub_maps, *refs;
  LT_GLOBAL const lt_irg_cell *cells;     /* the cells as built */
  LT_GLOBAL const lt_irg_cell16 *cells16; /* or, when not NULL, a compacted grid's 16-byte cells (lists, maps packed) */
  LT_GLOBAL const float *verts;
  const lt_pool *pool; /* on demand: where unbuilt top cells are requested; NULL when all are built */
  lt_int4 fine_dims;
  int shift;
} lt_irg_view;

enum { LT_IRG_RAY_START = 0, LT_IRG_RAY_VISIT, LT_IRG_RAY_DONE };

/* A ray in flight. */
typedef struct lt_irg_ray {
  lt_ray_setup r;
  lt_hit_record hit;
  lt_grid_walk w[3];
  float t_far;      /* the grid's widened exit */
  lt_i32 state;
  lt_i32 recent[LT_IRG_RECENT];
  lt_i32 recent_next;
  lt_i32 wait;          /* the top cell it waits for, or -1 */
  lt_i32 cover;         /* a tested cell whose box holds every voxel before the last on cover_axis, or -1 */
  lt_i32 cover_axis;    /* the axis of the boundary taken since cover was found */
  float cover_exit[3];  /* where the ray crosses cover's far face on each axis (infinity if parallel) */
#if LT_IRG_WATERTIGHT4
  lt_watertight4_ray r4; /* the four-triangle test's copy of the ray, made once */
#endif
} lt_irg_ray;

LT_DEVICE void lt_irg_ray_start(lt_irg_ray *q, LT_GLOBAL const float *ray, int flags) {
  q->r = lt_ray_prepare(ray[0], ray[1], ray[2], ray[3], ray[4], ray[5], ray[6], ray[7]);
  q->r.flags = flags;
  q->hit.t = q->r.tmax, q->hit.u = q->hit.v = 0.0f, q->hit.prim = -1;
  q->state = LT_IRG_RAY_START, q->wait = -1, q->recent_next = 0, q->cover = -1, q->cover_axis = 0;
  for (int i = 0; i < LT_IRG_RECENT; i++) q->recent[i] = -1;
#if LT_IRG_WATERTIGHT4
  q->r4 = lt_watertight4_prepare(&q->r);
#endif
}

LT_DEVICE lt_hit_record lt_irg_ray_answer(const lt_irg_ray *q) {
  lt_hit_record hit = q->hit;
  if (hit.prim < 0) hit.t = INFINITY, hit.u = hit.v = 0.0f;
  return hit;
}

/* Whether the grid is a compacted one with 16-byte cells, packed lists and 3-byte sub-map
 * entries (a constant in the native builds for that layout only). */
LT_DEVICE int lt_irg_view_packed(const lt_irg_view *v) { return LT_IRG_CELL16_ONLY || v->cells16; }

/* The fine voxel at travel indices (ux, uy, uz). */
LT_DEVICE void lt_irg_voxel_at(const lt_irg_ray *q, int ux, int uy, int uz, int v[3]) {
  v[0] = lt_grid_cell_of(&q->w[0], ux), v[1] = lt_grid_cell_of(&q->w[1], uy), v[2] = lt_grid_cell_of(&q->w[2], uz);
}

/* The cell of the voxel at travel indices u, or the top map's entry (< 0) if not built. */
LT_DEVICE lt_i32 lt_irg_cell_at(const lt_irg_view *v, const lt_irg_ray *q, int ux, int uy, int uz) {
  int x[3];
  lt_irg_voxel_at(q, ux, uy, uz, x);
  return lt_irg_lookup(v->top_map, v->sub_maps, lt_irg_view_packed(v), v->fine_dims, v->shift, x[0], x[1], x[2]);
}

/* Where the ray crosses a cell box's far face on axis k (infinity where it runs parallel). */
LT_DEVICE float lt_irg_far_crossing(const lt_irg_ray *q, const lt_irg_cell *cell, int k) {
  const lt_grid_walk *w = &q->w[k];
  if (w->sign == 0) return INFINITY;
  return lt_grid_crossing(w, w->sign > 0 ? cell->hi[k] : w->axis.n - cell->lo[k]);
}

/* 1 when a cell's box holds every voxel of the ranges' product. */
LT_DEVICE int lt_irg_box_holds_ranges(const lt_irg_ray *q, const lt_irg_cell *cell) {
  for (int k = 0; k < 3; k++) {
    const lt_grid_walk *w = &q->w[k];
    int lo = lt_grid_cell_of(w, w->first), hi = lt_grid_cell_of(w, w->last);
    if (w->sign < 0) lo = hi, hi = lt_grid_cell_of(w, w->first);
    if (lo < cell->lo[k] || hi >= cell->hi[k]) return 0;
  }
  return 1;
}

/* Tests the triangles of cell number `cell` (read into p) unless it was tested lately; 1 when
 * an any-hit query is answered. */
LT_DEVICE int lt_irg_test_cell(const lt_irg_view *v, lt_irg_ray *q, lt_i32 cell, const lt_irg_cell *p, int any_hit,
                               lt_trace_counters *c) {
  for (int i = 0; i < LT_IRG_RECENT; i++)
    if (q->recent[i] == cell) return 0;
  q->recent[q->recent_next] = cell;
  q->recent_next = (q->recent_next + 1) & (LT_IRG_RECENT - 1);
  c->traversal_steps++;
  int packed = lt_irg_view_packed(v);
  lt_irg_list list = lt_irg_list_open(v->refs, packed, p);
#if LT_IRG_WATERTIGHT4
  /* Natively, a cell of two or more triangles takes them four at a time (the same hits). */
  if (list.left >= 2 && !(q->r.flags & LT_QUERY_FLAG_FAST_TRIANGLES)) {
    while (list.left > 0) {
      lt_i32 prims[4];
      int n = list.left < 4 ? list.left : 4;
      for (int i = 0; i < n; i++) prims[i] = lt_irg_list_next(v->refs, packed, &list);
      c->intersections += n;
      if (lt_watertight4(&q->r, &q->r4, v->verts, prims, n, any_hit, &q->hit)) return 1;
    }
    return 0;
  }
#endif
  while (list.left > 0) {
    lt_i32 prim = lt_irg_list_next(v->refs, packed, &list);
    LT_GLOBAL const float *t = v->verts + 9 * (long)prim;
    float v0[3] = {t[0], t[1], t[2]}, v1[3] = {t[3], t[4], t[5]}, v2[3] = {t[6], t[7], t[8]};
    c->intersections++;
    if (lt_intersect_triangle(&q->r, v0, v1, v2, prim, &q->hit) && any_hit) return 1;
  }
  return 0;
}

/* Moves axis k's range to where the walk is just before T: the last voxel entered before T,
 * and back to the first whose widened exit is not before T. Each crossing is computed once:
 * c1 is where voxel u + 1 is entered, c0 where u is, exit where f is left. */
LT_DEVICE void lt_irg_skip_axis(lt_grid_walk *w, const lt_ray_setup *r, int k, float T, int widen) {
  if (w->sign == 0) return;
  int n = w->axis.n, u = w->last;
  float c0;
  if (u + 1 < n && w->next_entry < T) {
    float x = r->org[k] + T * r->dir[k];
    if (x == x && x > -INFINITY && x < INFINITY) {
      int g = lt_grid_cell_guess(&w->axis, x);
      g = w->sign > 0 ? g : n - 1 - g;
      u = g > u ? g : u;
    }
    float c1 = u + 1 < n ? lt_grid_crossing(w, u + 1) : INFINITY;
    while (c1 < T) {
      u++;
      c1 = u + 1 < n ? lt_grid_crossing(w, u + 1) : INFINITY;
    }
    c0 = lt_grid_crossing(w, u);
    while (u > w->last && c0 >= T) {
      u--;
      c1 = c0;
      c0 = lt_grid_crossing(w, u);
    }
    w->last = u;
    if (u + 1 < n) w->next_entry = c1;
  } else {
    /* Not moving: at most the voxels left whose widened exit is before T drop out. With two
     * in the range, the first's widened exit is kept already. */
    if (u == w->first) return;
    if (w->first + 1 == u) {
      if (!(w->first_exit >= T)) w->first = u, w->first_exit = lt_grid_widen(u + 1 < n ? w->next_entry : lt_grid_crossing(w, u + 1), widen);
      return;
    }
    c0 = lt_grid_crossing(w, u);
  }
  int f = w->last;
  float exit = f + 1 < n ? w->next_entry : lt_grid_crossing(w, f + 1);
  while (f > w->first && lt_grid_widen(c0, widen) >= T) {
    f--;
    exit = c0;
    c0 = lt_grid_crossing(w, f);
  }
  if (f > w->first) {
    w->first = f;
    w->first_exit = lt_grid_widen(exit, widen);
  }
}

/* A voxel to visit whose top cell is not built (entry `cell` < 0): asks the pool for it (unless
 * the top grid is still being counted, or there is no pool) and returns 0, the ray waiting. */
LT_DEVICE int lt_irg_wait(const lt_irg_view *v, lt_irg_ray *q, int ux, int uy, int uz, lt_i32 cell) {
  if (cell != LT_IRG_COUNTING && v->pool) {
    int x[3];
    lt_irg_voxel_at(q, ux, uy, uz, x);
    lt_i32 top = lt_irg_top_of(v->fine_dims, v->shift, x[0], x[1], x[2]);
    lt_pool_request(v->pool, LT_IRG_UNBUILT_SLOT(cell), top + 1);
    if (q->wait != top) lt_pool_count(v->pool, LT_POOL_STAT_STALLS, 1);
    q->wait = top;
  }
  return 0;
}

/* Tests the cells of the voxels at travel indices lo .. hi (one tested lately is not tested
 * again) and lowers T to the earliest exit of their boxes, each through the far faces of the
 * axes on which its voxel is the last of the walk's range (the header says why that is
 * enough). The cell of the voxel last on every axis goes to newest, its crossings to ex.
 * Returns -1 to go on, 1 when an any-hit query is answered, 0 when a voxel is in a top cell
 * not built (asked for; the ray waits, and what was tested stays). */
LT_DEVICE int lt_irg_visit(const lt_irg_view *v, lt_irg_ray *q, const int *lo, const int *hi, int any_hit, int widen,
                           lt_trace_counters *c, float *T, lt_i32 *newest, float *ex) {
  for (int uz = lo[2]; uz <= hi[2]; uz++)
    for (int uy = lo[1]; uy <= hi[1]; uy++)
      for (int ux = lo[0]; ux <= hi[0]; ux++) {
        lt_i32 cell = lt_irg_cell_at(v, q, ux, uy, uz);
        if (cell < 0) return lt_irg_wait(v, q, ux, uy, uz, cell);
        q->wait = -1;
        lt_irg_cell p = lt_irg_cell_get(v->cells, v->cells16, cell);
        if (lt_irg_test_cell(v, q, cell, &p, any_hit, c)) {
          q->state = LT_IRG_RAY_DONE;
          return 1;
        }
        int u[3] = {ux, uy, uz}, last[3] = {ux == q->w[0].last, uy == q->w[1].last, uz == q->w[2].last};
        float e[3], B = INFINITY, W = INFINITY;
        for (int k = 0; k < 3; k++) {
          e[k] = last[k] ? lt_irg_far_crossing(q, &p, k) : INFINITY;
          B = e[k] < B ? e[k] : B;
          if (!last[k]) {
            const lt_grid_walk *w = &q->w[k];
            float x = u[k] == w->first ? w->first_exit : lt_grid_widen(lt_grid_crossing(w, u[k] + 1), widen);
            W = x < W ? x : W;
          }
        }
        if (!(W < B)) *T = B < *T ? B : *T;
        if (last[0] && last[1] && last[2]) {
          *newest = cell;
          for (int k = 0; k < 3; k++) ex[k] = e[k];
        }
      }
  return -1;
}

/* A ray entering the grid (the conservative slab test of its box, whose widened far end bounds
 * every cell's): 1 when it misses (answered, state DONE), else 0 with t_start, where the walk
 * begins, and q->t_far set (state still DONE until the caller sets up a walk). */
LT_DEVICE int lt_irg_enter(const lt_irg_view *v, lt_irg_ray *q, int widen, float *t_start) {
  float lo[3] = {v->header->lo.x, v->header->lo.y, v->header->lo.z};
  float hi[3] = {v->header->hi.x, v->header->hi.y, v->header->hi.z};
  float t_near, t_far;
  q->state = LT_IRG_RAY_DONE;
  if (!q->r.valid || !lt_ray_slabs(&q->r, lo, hi, widen, &t_near, &t_far)) return 1;
  float t = t_near > q->r.tmin ? t_near : q->r.tmin;
  if (!(t <= t_far && t <= q->r.tmax)) return 1;
  q->t_far = t_far, *t_start = t;
  return 0;
}

/* Advances a ray; 1 when it is answered, 0 while it waits for a top cell (requested from the
 * pool). flags are the query flags. */
LT_DEVICE int lt_irg_advance(const lt_irg_view *v, lt_irg_ray *q, int flags, lt_trace_counters *c) {
  int any_hit = flags & LT_QUERY_FLAG_ANY, widen = !(flags & LT_QUERY_FLAG_PLAIN_SLABS);
  if (q->state == LT_IRG_RAY_DONE) return 1;
  if (q->state == LT_IRG_RAY_START) {
    float t_start;
    if (lt_irg_enter(v, q, widen, &t_start)) return 1;
    for (int k = 0; k < 3; k++) lt_grid_walk_start(&q->w[k], &q->r, v->header, k, t_start, widen);
    q->state = LT_IRG_RAY_VISIT;
  }

  int cap = 3 * (q->w[0].axis.n + q->w[1].axis.n + q->w[2].axis.n + 3);
  for (int step = 0; step < cap; step++) {
    /* The voxels before the last on the axis of the boundary just taken lie in the box of the
     * cover, a cell tested in the round before (when there is one): they need no lookup and no
     * test, and bound T through the cover's far faces on the other axes, on each of which some
     * of them is the last of its range. The header's argument holds with the cover's box in
     * place of their own cells' boxes: it needs only a tested box that holds the voxel. */
    int lo[3] = {q->w[0].first, q->w[1].first, q->w[2].first};
    int hi[3] = {q->w[0].last, q->w[1].last, q->w[2].last};
    float T_cover = INFINITY, W = INFINITY;
    int covered = 0;
    if (q->cover >= 0) {
      /* (Each axis by a constant index rather than through cover_axis: measured a little
       * cheaper.) */
      for (int k = 0; k < 3; k++) {
        const lt_grid_walk *w = &q->w[k];
        if (k != q->cover_axis) {
          T_cover = q->cover_exit[k] < T_cover ? q->cover_exit[k] : T_cover;
        } else if (lo[k] < hi[k]) {
          W = w->first + 1 == w->last ? w->first_exit : lt_grid_widen(lt_grid_crossing(w, w->last), widen);
          lo[k] = hi[k];
          covered = 1;
        }
      }
      /* Covered voxels leave the ranges (at W at the latest) before the cover's box ends on
       * the other axes: then they bound nothing (the header says why). */
      if (!covered || W < T_cover) T_cover = INFINITY;
    }
    /* Test the cells of the other voxels, and find T, the earliest exit of their boxes (the
     * last voxel's cell and crossings are kept for the next cover). */
    float T = INFINITY, ex[3] = {INFINITY, INFINITY, INFINITY};
    lt_i32 newest = -1;
    int r = lt_irg_visit(v, q, lo, hi, any_hit, widen, c, &T, &newest, ex);
    if (r >= 0) return r;
    T = T_cover < T ? T_cover : T;
    /* A hit before T ends the walk: every boundary left is at or after T (the uniform walk's
     * rule, taken before the skip that would only confirm it). */
    if (q->hit.prim >= 0 && q->hit.t < T) {
      q->state = LT_IRG_RAY_DONE;
      return 1;
    }
    /* Skip every boundary before T. If the last voxel's cell holds all the ranges now, it
     * covers the voxels left behind by the next boundary. */
    for (int k = 0; k < 3; k++) lt_irg_skip_axis(&q->w[k], &q->r, k, T, widen);
    lt_irg_cell box = lt_irg_cell_get(v->cells, v->cells16, newest);
    q->cover = lt_irg_box_holds_ranges(q, &box) ? newest : -1;
    for (int k = 0; k < 3; k++) q->cover_exit[k] = ex[k];

    /* The next boundary, and the uniform walk's rules for it. */
    int a = -1;
    float entry = 0.0f;
    for (int k = 0; k < 3; k++)
      if (q->w[k].sign != 0 && q->w[k].last + 1 < q->w[k].axis.n && (a < 0 || q->w[k].next_entry < entry))
        a = k, entry = q->w[k].next_entry;
    float best = q->hit.prim >= 0 ? q->hit.t : q->r.tmax;
    if (a < 0 || entry > best || !(entry <= q->t_far)) {
      q->state = LT_IRG_RAY_DONE;
      return 1;
    }
    q->cover_axis = a;
    for (int k = 0; k < 3; k++) {
      lt_grid_walk *w = &q->w[k];
      if (k == a) {
        w->last++;
        if (w->last + 1 < w->axis.n) w->next_entry = lt_grid_crossing(w, w->last + 1);
      }
      while (w->sign != 0 && w->first < w->last && !(w->first_exit >= entry)) {
        w->first++;
        int e = w->first + 1;
        w->first_exit = lt_grid_widen(e == w->last + 1 && e < w->axis.n ? w->next_entry : lt_grid_crossing(w, e), widen);
      }
    }
  }
  /* More boundaries than the grid has planes: impossible, each enters a new voxel. */
  q->state = LT_IRG_RAY_DONE;
  return 1;
}

#endif
