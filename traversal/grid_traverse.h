/* Closest-hit and any-hit traversal of the uniform grid (Thrane and Simonsen 2005, section 7.2):
 * the 3D-DDA of Amanatides and Woo ("A Fast Voxel Traversal Algorithm for Ray Tracing", 1987),
 * made conservative so that its hits are the brute-force reference's, bit for bit.
 *
 * Why the textbook walk is not enough: it accumulates tMax += tDelta, which drifts, and where
 * two axes' next boundaries nearly tie, rounding may step the wrong axis first and skip a
 * cell the ray crosses for a tiny stretch. Worse, the triangle test keeps t inside the
 * triangle box's slab interval widened by its rounding bound (lt_clamp_to_box), so a hit may
 * lie a rounding error outside every cell the exact ray crosses. Either way a hit is lost.
 *
 * What this walk does instead:
 *  - Every crossing distance is computed afresh from the plane's float with lt_ray_slabs's own
 *    arithmetic, (plane - org) * inv_dir, never accumulated. Rounding is monotone, so along one
 *    axis the crossings never decrease in the order the ray meets the planes, and a cell's
 *    interval is bit for bit what lt_ray_slabs gives for the cell's box.
 *  - Each axis keeps a range of cells rather than one: those entered at or before the current
 *    distance whose exit, widened as lt_ray_slabs widens a far end, is not before it. The cells
 *    visited are the products of the three ranges: first the product at the grid's entry, then
 *    at each boundary the slab of cells that the newly entered cell on one axis adds. Away from
 *    edges and corners every range holds one cell and this is the textbook walk; within a
 *    rounding error of them, the two to eight cells around are all visited, each once.
 *  - On an axis the ray runs parallel to (a direction component of +0 or -0) one cell serves
 *    the whole ray: one whose closed slab holds the origin. A triangle can only be hit if its
 *    box's slab holds the origin (lt_ray_slabs decides that exactly), and then its box meets
 *    every such cell, where the builder has referenced it.
 *  - The walk stops when the best hit is strictly before the next boundary (a hit exactly there
 *    may still tie with a lower-numbered triangle beyond it), when the next boundary is past the
 *    grid's widened exit, or when no boundary is left.
 *
 * Why that is exact. Let the reference's hit be triangle W at t. After lt_clamp_to_box, t lies
 * in the slab interval of W's box: on every axis, at or after the box's entry crossing and at or
 * before its widened exit crossing. The builder referenced W from every cell whose closed slab
 * meets its box, decided against the same plane floats. On each axis the ray is not parallel
 * to, take the last such cell entered at or before t: its widened exit is at or after t,
 * because either the next plane's crossing is after t or its exit plane lies at or beyond the
 * box's (and widening never decreases). So that cell is in every axis's range at t, t is at or
 * after where the walk starts, and the walk cannot stop before it (a stop needs a best hit
 * before the next boundary, and the best is never after t). W is therefore tested, and every
 * other triangle tested can only lose or tie to it under lt_hit_better, as in the reference.
 * A triangle met again in a later cell changes nothing. */
#ifndef LT_GRID_TRAVERSE_H
#define LT_GRID_TRAVERSE_H

#include "device/grid_cells.h"
#include "traversal/ray_box.h"

/* One axis of the walk. Its cells are counted in travel order u: u is the cell for a positive
 * direction and n - 1 - cell for a negative one, so that u grows with t on every axis. */
typedef struct lt_grid_walk {
  lt_grid_axis axis;
  float org, inv;
  int sign;         /* 1 or -1; 0 for a direction component of +0 or -0 */
  int first, last;  /* the range of travel indices (of cells, where sign is 0) */
  float next_entry; /* where cell last + 1 is entered, if last + 1 < n */
  float first_exit; /* where cell first is left, widened */
} lt_grid_walk;

/* Where the ray crosses travel plane u (0 <= u <= n), in lt_ray_slabs's arithmetic. */
LT_DEVICE float lt_grid_crossing(const lt_grid_walk *w, int u) {
  float p = lt_grid_plane(&w->axis, w->sign > 0 ? u : w->axis.n - u);
  return (p - w->org) * w->inv;
}

/* A far end widened by the very expression of lt_ray_slabs (or not, for a query that asks for
 * plain slabs). C evaluates it in double (fabs) and OpenCL in float; written the same, it
 * matches each backend's own slab test, which is what the argument above needs, and it never
 * decreases as t grows. A far end of -infinity becomes NaN there and here; every comparison
 * below is written so that NaN reads as "before". */
LT_DEVICE float lt_grid_widen(float t, int widen) {
  if (!widen) return t;
  t += lt_fabsf(t) * LT_SLAB_ROUNDING_EPS;
  return t;
}

LT_DEVICE int lt_grid_cell_of(const lt_grid_walk *w, int u) { return w->sign < 0 ? w->axis.n - 1 - u : u; }

/* Sets up axis k at t_start, where the walk begins (within the grid's slab interval). */
LT_DEVICE void lt_grid_walk_start(lt_grid_walk *w, const lt_ray_setup *r, LT_GLOBAL const lt_grid_header *g, int k,
                                  float t_start, int widen) {
  w->axis = lt_grid_axis_of(g, k);
  w->org = r->org[k];
  w->inv = r->inv_dir[k];
  w->sign = r->dir[k] > 0.0f ? 1 : r->dir[k] < 0.0f ? -1 : 0;
  w->next_entry = w->first_exit = 0.0f;
  int n = w->axis.n;

  /* Parallel to the axis: one cell for the whole ray, any whose closed slab holds the origin
   * (the slab test of the grid's box has found the origin inside the grid's slab). */
  if (w->sign == 0) {
    w->first = w->last = lt_grid_last_cell(&w->axis, w->org);
    return;
  }

  /* The last cell entered by t_start, walking from a guess at where the ray is then. */
  int u = lt_grid_cell_guess(&w->axis, w->org + t_start * r->dir[k]);
  u = w->sign > 0 ? u : n - 1 - u;
  while (u + 1 < n && lt_grid_crossing(w, u + 1) <= t_start) u++;
  while (u > 0 && lt_grid_crossing(w, u) > t_start) u--;
  w->last = u;
  if (u + 1 < n) w->next_entry = lt_grid_crossing(w, u + 1);

  /* Back to the first cell whose widened exit is not before t_start. */
  while (u > 0 && lt_grid_widen(lt_grid_crossing(w, u), widen) >= t_start) u--;
  w->first = u;
  w->first_exit = lt_grid_widen(lt_grid_crossing(w, u + 1), widen);
}

/* Tests the triangles of every cell whose travel indices lie in lo[k] .. hi[k]; returns 1 when
 * an any-hit query has its answer. */
LT_DEVICE int lt_grid_visit(const lt_ray_setup *r, const lt_grid_walk *w, const int *lo, const int *hi,
                            LT_GLOBAL const lt_i32 *cells, LT_GLOBAL const lt_i32 *refs, LT_GLOBAL const float *verts,
                            int any_hit, lt_hit_record *hit, lt_trace_counters *counters) {
  for (int uz = lo[2]; uz <= hi[2]; uz++)
    for (int uy = lo[1]; uy <= hi[1]; uy++)
      for (int ux = lo[0]; ux <= hi[0]; ux++) {
        int x = lt_grid_cell_of(&w[0], ux), y = lt_grid_cell_of(&w[1], uy), z = lt_grid_cell_of(&w[2], uz);
        lt_i32 begin, end;
        lt_grid_cell_range(cells, lt_grid_cell_index(w[0].axis.n, w[1].axis.n, x, y, z), &begin, &end);
        counters->traversal_steps++;
        for (lt_i32 i = begin; i < end; i++) {
          lt_i32 prim = refs[i];
          LT_GLOBAL const float *t = verts + 9 * (long)prim;
          float v0[3] = {t[0], t[1], t[2]}, v1[3] = {t[3], t[4], t[5]}, v2[3] = {t[6], t[7], t[8]};
          counters->intersections++;
          if (lt_intersect_triangle(r, v0, v1, v2, prim, hit) && any_hit) return 1;
        }
      }
  return 0;
}

/* Traces one ray through the grid (header g, cells = cell_begin, refs, and the scene's vertex
 * array, 9 floats per triangle); any_hit stops at the first hit found. A miss leaves prim = -1
 * and t = tmax. Returns 0, or -1 if the walk takes more boundary steps than the grid has
 * planes (impossible: every step enters a new cell on some axis). */
LT_DEVICE int lt_grid_traverse(const lt_ray_setup *r, LT_GLOBAL const lt_grid_header *g, LT_GLOBAL const lt_i32 *cells,
                               LT_GLOBAL const lt_i32 *refs, LT_GLOBAL const float *verts, int any_hit,
                               lt_hit_record *hit, lt_trace_counters *counters) {
  hit->t = r->tmax;
  hit->u = hit->v = 0.0f;
  hit->prim = -1;
  if (!r->valid) return 0;
  int widen = !(r->flags & LT_QUERY_FLAG_PLAIN_SLABS);

  /* Enter with the conservative slab test of the grid's box; its widened far end bounds the
   * widened exit of every cell, so nothing past it can hold a hit. */
  float lo[3] = {g->lo.x, g->lo.y, g->lo.z}, hi[3] = {g->hi.x, g->hi.y, g->hi.z};
  float t_near, t_far;
  if (!lt_ray_slabs(r, lo, hi, widen, &t_near, &t_far)) return 0;
  float t_start = t_near > r->tmin ? t_near : r->tmin;
  if (!(t_start <= t_far && t_start <= r->tmax)) return 0;

  /* Every axis's cells at t_start, and their product, visited first. */
  lt_grid_walk w[3];
  int first[3], last[3];
  for (int k = 0; k < 3; k++) {
    lt_grid_walk_start(&w[k], r, g, k, t_start, widen);
    first[k] = w[k].first, last[k] = w[k].last;
  }
  if (lt_grid_visit(r, w, first, last, cells, refs, verts, any_hit, hit, counters)) return 0;

  /* One boundary a step; each enters a new cell on some axis, so the planes bound the steps. */
  int cap = w[0].axis.n + w[1].axis.n + w[2].axis.n + 3;
  for (int step = 0; step < cap; step++) {
    /* The next boundary: the earliest entry of a cell not yet reached, over the axes. */
    int a = -1;
    float entry = 0.0f;
    for (int k = 0; k < 3; k++)
      if (w[k].sign != 0 && w[k].last + 1 < w[k].axis.n && (a < 0 || w[k].next_entry < entry))
        a = k, entry = w[k].next_entry;
    if (a < 0) return 0;

    /* Done when the best hit is strictly before it, or it is past the grid's widened exit. */
    float best = hit->prim >= 0 ? hit->t : r->tmax;
    if (entry > best || !(entry <= t_far)) return 0;

    /* Enter the cell on axis a; drop from every axis the cells left (widened) before entry. */
    w[a].last++;
    if (w[a].last + 1 < w[a].axis.n) w[a].next_entry = lt_grid_crossing(&w[a], w[a].last + 1);
    for (int k = 0; k < 3; k++) {
      while (w[k].sign != 0 && w[k].first < w[k].last && !(w[k].first_exit >= entry)) {
        w[k].first++;
        w[k].first_exit = lt_grid_widen(lt_grid_crossing(&w[k], w[k].first + 1), widen);
      }
      first[k] = w[k].first, last[k] = w[k].last;
    }

    /* The new cells: the one just entered on axis a, against the other axes' ranges. */
    first[a] = last[a];
    if (lt_grid_visit(r, w, first, last, cells, refs, verts, any_hit, hit, counters)) return 0;
  }
  return -1;
}

#endif
