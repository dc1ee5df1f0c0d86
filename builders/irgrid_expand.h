/* The irregular grid's expansion (Perard-Gayot, Kalojanov and Slusallek 2017, section 3.3) as
 * EXPAND tasks of the pool: one task a pass, over one top cell's cells as it is built, or over
 * every cell of a full build once the MERGE passes across the grid are done.
 *
 * A pass tries each face of each cell: it grows by one layer of the cell's own sub-voxels when
 * every triangle that meets the layer is one the cell references already (meets its box
 * before expansion), in this top cell or in a neighbouring one. A pass needs no box from before
 * the first: a triangle meets the box as grown so far exactly when it meets the box before
 * expansion, since the grown box is that box and the layers added to it, all boxes, and every
 * triangle that meets a layer met the box before expansion when the layer was added. So the
 * box at the start of the pass stands for it.
 *
 * Only triangles are read, through the top cells' lists or through cells' lists, never a
 * neighbour's boxes, so a cell may grow into top cells not built yet, cells grow independently
 * of each other (the chunks of a pass may run in any order), and the result does not depend on
 * the order top cells are built in. A ray then leaves the grown box later and skips voxels
 * whose triangles it has just tested (traversal/irgrid_traverse.h shows why no hit is lost). */
#ifndef LT_IRGRID_EXPAND_H
#define LT_IRGRID_EXPAND_H

#include "builders/irgrid_task.h"

/* A fine box [lo, hi) as the plane floats of its faces, which is how a triangle's box is
 * tested against it: the box meets the triangle's exactly when lt_irg_fine_range's voxels
 * meet it (first_cell(a) <= hi - 1 iff a <= plane(hi); last_cell(b) >= lo iff b >= plane(lo)). */
typedef struct lt_irg_planes {
  float lo[3], hi[3];
} lt_irg_planes;

LT_DEVICE lt_irg_planes lt_irg_planes_of(const lt_irg_build *b, const int lo[3], const int hi[3]) {
  lt_irg_planes p;
  for (int k = 0; k < 3; k++) {
    lt_grid_axis a = lt_grid_axis_of(b->header, k);
    p.lo[k] = lt_grid_plane(&a, lo[k]), p.hi[k] = lt_grid_plane(&a, hi[k]);
  }
  return p;
}

LT_DEVICE int lt_irg_prim_meets(const lt_irg_build *b, lt_i32 prim, const lt_irg_planes *p) {
  LT_GLOBAL const lt_v4 *box = b->prim_boxes + 2 * (long)prim;
  int meets = 1;
  for (int k = 0; k < 3; k++) meets &= lt_v4_lane(box[0], k) <= p->hi[k] && lt_v4_lane(box[1], k) >= p->lo[k];
  return meets;
}

/* Whether a triangle that meets the layer misses the cell's box before expansion. */
LT_DEVICE int lt_irg_escapes(const lt_irg_build *b, lt_i32 prim, const lt_irg_planes *layer, const lt_irg_planes *own) {
  return lt_irg_prim_meets(b, prim, layer) && !lt_irg_prim_meets(b, prim, own);
}

/* Looks at the triangles of one cell for lt_irg_covered; 0 when one escapes. */
LT_DEVICE int lt_irg_cell_covered(const lt_irg_build *b, lt_i32 cell, const lt_irg_planes *layer,
                                  const lt_irg_planes *own) {
  LT_GLOBAL const lt_irg_cell *p = &b->cells[cell];
  for (lt_i32 i = p->begin; i < p->end; i++)
    if (lt_irg_escapes(b, b->refs[i], layer, own)) return 0;
  return 1;
}

/* Whether every triangle that meets fine box [lo, hi) (a layer beside a cell) meets the cell's
 * box before expansion (planes `own`) too. Each top cell the layer meets is read one way: a
 * built one (or top cell self_t, whose entry self_entry its own tasks know before it is
 * published) through its cells, as a cell's triangles include those of every voxel it holds,
 * one not built through its list. */
LT_DEVICE int lt_irg_covered(const lt_irg_build *b, lt_i32 self_t, lt_i32 self_entry, const int lo[3], const int hi[3],
                             const lt_irg_planes *own) {
  int tx = b->fine_dims.x >> b->shift, ty = b->fine_dims.y >> b->shift, span = 1 << b->shift;
  lt_irg_planes layer = lt_irg_planes_of(b, lo, hi);
  for (int z = lo[2] >> b->shift; z <= (hi[2] - 1) >> b->shift; z++)
    for (int y = lo[1] >> b->shift; y <= (hi[1] - 1) >> b->shift; y++)
      for (int x = lo[0] >> b->shift; x <= (hi[0] - 1) >> b->shift; x++) {
        lt_i32 t = lt_grid_cell_index(tx, ty, x, y, z);
        lt_i32 entry = t == self_t ? self_entry : lt_atomic_load_acquire_i32(&b->top_map[t]);
        if (entry < 0) {
          for (lt_i32 i = b->top_begin[t]; i < b->top_begin[t + 1]; i++)
            if (lt_irg_escapes(b, b->refs[i], &layer, own)) return 0;
          continue;
        }
        /* The layer's sub-voxels in this top cell, and their cells. */
        int level = LT_IRG_ENTRY_LEVEL(entry), down = b->shift - level, side = 1 << level;
        int origin[3] = {x << b->shift, y << b->shift, z << b->shift}, slo[3], shi[3];
        for (int k = 0; k < 3; k++) {
          int l = lo[k] - origin[k], h = hi[k] - 1 - origin[k];
          slo[k] = (l < 0 ? 0 : l) >> down, shi[k] = (h > span - 1 ? span - 1 : h) >> down;
        }
        lt_i32 last = -1;
        for (int sz = slo[2]; sz <= shi[2]; sz++)
          for (int sy = slo[1]; sy <= shi[1]; sy++)
            for (int sx = slo[0]; sx <= shi[0]; sx++) {
              lt_i32 cell = b->sub_maps[LT_IRG_ENTRY_BASE(entry) + sx + side * (sy + side * sz)];
              if (cell == last) continue;
              last = cell;
              if (!lt_irg_cell_covered(b, cell, &layer, own)) return 0;
            }
      }
  return 1;
}

/* One expansion pass over one cell: fine box [lo, hi), grown in place by layers `step` fine
 * voxels thick, each face at most once. Returns the layers grown. */
LT_DEVICE lt_i32 lt_irg_expand_pass(const lt_irg_build *b, lt_i32 self_t, lt_i32 self_entry, int step, int lo[3],
                                    int hi[3], const lt_irg_planes *own) {
  int n[3] = {b->fine_dims.x, b->fine_dims.y, b->fine_dims.z};
  lt_i32 grown = 0;
  for (int face = 0; face < 6; face++) {
    int k = face >> 1, up = face & 1;
    int llo[3] = {lo[0], lo[1], lo[2]}, lhi[3] = {hi[0], hi[1], hi[2]};
    if (up)
      llo[k] = hi[k], lhi[k] = hi[k] + step < n[k] ? hi[k] + step : n[k];
    else
      lhi[k] = lo[k], llo[k] = lo[k] - step > 0 ? lo[k] - step : 0;
    if (llo[k] >= lhi[k] || !lt_irg_covered(b, self_t, self_entry, llo, lhi, own)) continue;
    if (up)
      hi[k] = lhi[k];
    else
      lo[k] = llo[k];
    grown++;
  }
  return grown;
}

/* One pass over the chunk's cells. Layers are one sub-voxel of the top cell the cell started
 * in thick (the cell's finest unit): over the whole grid, where a cell's box may have grown
 * into another top cell, the first pass keeps that thickness in the cell scratch, whose merge
 * words are free by then. */
LT_DEVICE void lt_irg_expand_chunk(const lt_irg_build *b, lt_i32 slot, lt_i32 chunk, int lid, int lsize) {
  LT_GLOBAL const lt_task *task = &b->pool.tasks[slot];
  lt_i32 t = task->work[LT_IRG_W_TOP], entry = task->work[LT_IRG_W_ENTRY], pass = task->work[LT_IRG_W_PASS];
  lt_i32 first, end;
  lt_irg_chunk_cells(task, chunk, &first, &end);
  for (lt_i32 j = first + lid; j < end; j += lsize) {
    LT_GLOBAL lt_irg_cell *cell = &b->cells[j];
    if (lt_irg_dead(cell)) continue;
    int lo[3] = {cell->lo[0], cell->lo[1], cell->lo[2]}, hi[3] = {cell->hi[0], cell->hi[1], cell->hi[2]};
    lt_irg_planes planes = lt_irg_planes_of(b, lo, hi);
    lt_i32 step;
    if (t >= 0) {
      step = 1 << (b->shift - LT_IRG_ENTRY_LEVEL(entry));
    } else if (pass == 0) {
      lt_i32 start = b->top_map[lt_irg_top_of(b->fine_dims, b->shift, lo[0], lo[1], lo[2])];
      step = b->cell_scratch[3 * (long)j] = 1 << (b->shift - LT_IRG_ENTRY_LEVEL(start));
    } else {
      step = b->cell_scratch[3 * (long)j];
    }
    lt_i32 grown = lt_irg_expand_pass(b, t, entry, step, lo, hi, &planes);
    for (int k = 0; k < 3; k++) cell->lo[k] = lo[k], cell->hi[k] = hi[k];
    lt_irg_count(b, LT_IRG_STAT_EXPANSIONS, (lt_u32)grown);
  }
}

/* After a pass: the next one, or, after the last over a top cell, its publication. */
LT_DEVICE void lt_irg_expand_end(const lt_irg_build *b, lt_i32 slot) {
  LT_GLOBAL const lt_task *task = &b->pool.tasks[slot];
  lt_i32 t = task->work[LT_IRG_W_TOP], entry = task->work[LT_IRG_W_ENTRY], pass = task->work[LT_IRG_W_PASS];
  if (pass + 1 < b->expansion_passes)
    lt_irg_hand_on(b, slot, LT_IRG_KIND_EXPAND, t, entry, pass + 1, task->work[LT_IRG_W_LIVE], task->begin, task->end);
  else if (t >= 0)
    lt_irg_publish_top(b, slot, t, entry);
  else
    lt_pool_retire(&b->pool, slot);
}

#endif
