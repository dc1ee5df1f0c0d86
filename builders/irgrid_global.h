/* The irregular grid's MERGE tasks: the paper's merge passes across top cells, one task a
 * pass, over the whole grid once every top cell is built (full builds only: on demand a
 * neighbour may never be built, and a built cell must not change under a ray). They run in a
 * launch of their own after the one that built the top cells (kernels/irgrid_ondemand.h says
 * why), whose set-up inserts the first pass; each pass hands its slot on to the next, or to the
 * first EXPAND pass over every cell (builders/irgrid_expand.h) once a pass merges too few.
 *
 * A pass along axis a has two phases over chunks of cells. Candidates: each live cell finds
 * the cell beyond its upper face (through the voxel map) and, when the two have the same
 * extent on the other axes and merging lowers (Ci * |T| + Ct) * SA(B), counts their union by
 * one walk over both ascending lists. The phase end pairs the candidates along each chain from
 * its lower end (one work-item, one walk over the cells). Merge: each pair writes the union's
 * list to new room in the reference heap (the old lists stay: the heap never frees), grows the
 * lower cell over the upper one, kills the upper one and points its voxels at the lower one.
 * Pairs are disjoint, so chunks never write the same cell or voxel. Passes go round the axes
 * until one merges fewer than 1 - alpha of the live cells. */
#ifndef LT_IRGRID_GLOBAL_H
#define LT_IRGRID_GLOBAL_H

#include "builders/irgrid_expand.h"

/* Scratch per cell: the candidate (then the partner of a pair's lower cell), the union's size,
 * and whether a candidate points at it. */
#define LT_IRG_CAND(b, j) ((b)->cell_scratch[3 * (long)(j)])
#define LT_IRG_UNION(b, j) ((b)->cell_scratch[3 * (long)(j) + 1])
#define LT_IRG_POINTED(b, j) ((b)->cell_scratch[3 * (long)(j) + 2])

/* The size of the union of two ascending lists. */
LT_DEVICE lt_i32 lt_irg_union_size(LT_GLOBAL const lt_i32 *a, lt_i32 na, LT_GLOBAL const lt_i32 *b, lt_i32 nb) {
  lt_i32 i = 0, j = 0, n = 0;
  while (i < na && j < nb) {
    lt_i32 x = a[i], y = b[j];
    i += x <= y, j += y <= x, n++;
  }
  return n + (na - i) + (nb - j);
}

/* The merge cost of a fine box holding n triangles (Ct, Ci of the build; the common factor 2
 * of surface areas left out). */
LT_DEVICE float lt_irg_fine_cost(const lt_irg_build *b, const lt_i32 lo[3], const lt_i32 hi[3], lt_i32 n) {
  float e[3];
  for (int k = 0; k < 3; k++) e[k] = (float)(hi[k] - lo[k]) * lt_grid_axis_of(b->header, k).size;
  return (b->intersection_cost * (float)n + b->traversal_cost) * (e[0] * e[1] + e[1] * e[2] + e[2] * e[0]);
}

/* Cell j's candidate along axis a, or -1; its union size in LT_IRG_UNION. */
LT_DEVICE void lt_irg_global_candidate(const lt_irg_build *b, lt_i32 j, int a) {
  LT_IRG_CAND(b, j) = -1;
  LT_IRG_POINTED(b, j) = 0;
  LT_GLOBAL const lt_irg_cell *c = &b->cells[j];
  int n_a = a == 0 ? b->fine_dims.x : a == 1 ? b->fine_dims.y : b->fine_dims.z;
  if (lt_irg_dead(c) || c->hi[a] >= n_a) return;
  int at[3] = {c->lo[0], c->lo[1], c->lo[2]};
  at[a] = c->hi[a];
  lt_i32 n = lt_irg_lookup(b->top_map, b->sub_maps, 0, b->fine_dims, b->shift, at[0], at[1], at[2]);
  if (n < 0) return;
  LT_GLOBAL const lt_irg_cell *d = &b->cells[n];
  for (int k = 0; k < 3; k++)
    if (k == a ? d->lo[k] != c->hi[k] : d->lo[k] != c->lo[k] || d->hi[k] != c->hi[k]) return;
  lt_i32 clo[3] = {c->lo[0], c->lo[1], c->lo[2]}, chi[3] = {c->hi[0], c->hi[1], c->hi[2]};
  lt_i32 dlo[3] = {d->lo[0], d->lo[1], d->lo[2]}, dhi[3] = {d->hi[0], d->hi[1], d->hi[2]};
  lt_i32 uhi[3] = {chi[0], chi[1], chi[2]}, nc = c->end - c->begin, nd = d->end - d->begin;
  uhi[a] = dhi[a];
  float apart = lt_irg_fine_cost(b, clo, chi, nc) + lt_irg_fine_cost(b, dlo, dhi, nd);
  /* The union holds at least the larger list: when even that does not pay, skip counting it. */
  if (!(lt_irg_fine_cost(b, clo, uhi, nc > nd ? nc : nd) < apart)) return;
  lt_i32 both = lt_irg_union_size(b->refs + c->begin, nc, b->refs + d->begin, nd);
  if (!(lt_irg_fine_cost(b, clo, uhi, both) < apart)) return;
  LT_IRG_CAND(b, j) = n;
  LT_IRG_UNION(b, j) = both;
}

/* Points every voxel of fine box [lo, hi) at cell j (all its top cells are built). */
LT_DEVICE void lt_irg_point_voxels(const lt_irg_build *b, const lt_i32 lo[3], const lt_i32 hi[3], lt_i32 j) {
  int tx = b->fine_dims.x >> b->shift, ty = b->fine_dims.y >> b->shift, span = 1 << b->shift;
  for (int z = lo[2] >> b->shift; z <= (hi[2] - 1) >> b->shift; z++)
    for (int y = lo[1] >> b->shift; y <= (hi[1] - 1) >> b->shift; y++)
      for (int x = lo[0] >> b->shift; x <= (hi[0] - 1) >> b->shift; x++) {
        lt_i32 entry = b->top_map[lt_grid_cell_index(tx, ty, x, y, z)];
        int level = LT_IRG_ENTRY_LEVEL(entry), down = b->shift - level, side = 1 << level;
        int origin[3] = {x << b->shift, y << b->shift, z << b->shift}, slo[3], shi[3];
        for (int k = 0; k < 3; k++) {
          int l = lo[k] - origin[k], h = hi[k] - 1 - origin[k];
          slo[k] = (l < 0 ? 0 : l) >> down, shi[k] = (h > span - 1 ? span - 1 : h) >> down;
        }
        for (int sz = slo[2]; sz <= shi[2]; sz++)
          for (int sy = slo[1]; sy <= shi[1]; sy++)
            for (int sx = slo[0]; sx <= shi[0]; sx++)
              b->sub_maps[LT_IRG_ENTRY_BASE(entry) + sx + side * (sy + side * sz)] = j;
      }
}

/* Merges cell j with its partner along axis a. */
LT_DEVICE void lt_irg_global_merge(const lt_irg_build *b, lt_i32 j, int a) {
  lt_i32 n = LT_IRG_CAND(b, j), both = LT_IRG_UNION(b, j);
  LT_GLOBAL lt_irg_cell *c = &b->cells[j];
  LT_GLOBAL lt_irg_cell *d = &b->cells[n];
  lt_i32 at = both > 0 ? lt_heap_alloc(&b->ref_heap, both) : 0;
  if (at < 0) {
    lt_pool_fail(&b->pool, LT_POOL_ERROR_HEAP);
    return;
  }
  /* The union of the two ascending lists, ascending. */
  lt_i32 i = c->begin, k = d->begin, out = at;
  while (i < c->end || k < d->end) {
    lt_i32 x = i < c->end ? b->refs[i] : 0x7fffffff, y = k < d->end ? b->refs[k] : 0x7fffffff;
    b->refs[out++] = x < y ? x : y;
    i += x <= y, k += y <= x;
  }
  lt_irg_count(b, LT_IRG_STAT_REFS_SAVED, (lt_u32)((c->end - c->begin) + (d->end - d->begin) - both));
  lt_irg_count(b, LT_IRG_STAT_SORT_OPS, (lt_u32)both);
  lt_i32 dlo[3] = {d->lo[0], d->lo[1], d->lo[2]}, dhi[3] = {d->hi[0], d->hi[1], d->hi[2]};
  c->begin = at, c->end = at + both, c->hi[a] = dhi[a];
  d->lo[0] = -1;
  lt_irg_point_voxels(b, dlo, dhi, j);
}

/* Phase 0 finds the chunk's candidates, phase 1 merges its pairs. */
LT_DEVICE void lt_irg_merge_chunk(const lt_irg_build *b, lt_i32 slot, lt_i32 chunk, int lid, int lsize) {
  LT_GLOBAL const lt_task *task = &b->pool.tasks[slot];
  int a = task->work[LT_IRG_W_PASS] % 3;
  lt_i32 first, end;
  lt_irg_chunk_cells(task, chunk, &first, &end);
  for (lt_i32 j = first + lid; j < end; j += lsize) {
    if (task->phase == 0) lt_irg_global_candidate(b, j, a);
    else if (LT_IRG_CAND(b, j) >= 0) lt_irg_global_merge(b, j, a);
  }
}

/* Pairs the candidates along each chain from its lower end; returns the pairs. */
LT_DEVICE lt_i32 lt_irg_global_pair(const lt_irg_build *b, lt_i32 cells) {
  for (lt_i32 j = 0; j < cells; j++)
    if (LT_IRG_CAND(b, j) >= 0) LT_IRG_POINTED(b, LT_IRG_CAND(b, j)) = 1;
  lt_i32 pairs = 0;
  for (lt_i32 h = 0; h < cells; h++) {
    if (LT_IRG_CAND(b, h) < 0 || LT_IRG_POINTED(b, h)) continue;
    for (lt_i32 j = h; j >= 0;) {
      lt_i32 n = LT_IRG_CAND(b, j);
      if (n < 0) break;
      lt_i32 next = LT_IRG_CAND(b, n);
      LT_IRG_CAND(b, n) = -1; /* the upper cell of a pair is no lower cell this pass */
      pairs++;
      j = next;
    }
  }
  return pairs;
}

/* After the candidates: pair them, and merge. After the merges: the next pass, or the first
 * EXPAND pass over every cell, once this one merged fewer than 1 - alpha of the live cells. */
LT_DEVICE void lt_irg_merge_end(const lt_irg_build *b, lt_i32 slot) {
  LT_GLOBAL lt_task *task = &b->pool.tasks[slot];
  if (task->phase == 0) {
    task->work[LT_IRG_W_PAIRS] = lt_irg_global_pair(b, task->end);
    lt_fence();
    lt_pool_next_phase(&b->pool, slot, 1, task->chunks);
    return;
  }
  lt_i32 pairs = task->work[LT_IRG_W_PAIRS], live = task->work[LT_IRG_W_LIVE], pass = task->work[LT_IRG_W_PASS];
  lt_irg_count(b, LT_IRG_STAT_GLOBAL_MERGES, (lt_u32)pairs);
  int again = pairs > 0 && !((float)pairs < (1.0f - b->merge_alpha) * (float)live);
  if (again || b->expansion_passes > 0)
    lt_irg_hand_on(b, slot, again ? LT_IRG_KIND_MERGE : LT_IRG_KIND_EXPAND, -1, 0, again ? pass + 1 : 0, live - pairs,
                   task->begin, task->end);
  else
    lt_pool_retire(&b->pool, slot);
}

/* The merge launch's start, once, by one work-item: the first MERGE pass over every cell
 * (all top cells are built). */
LT_DEVICE void lt_irg_merge_setup(const lt_irg_build *b) {
  lt_i32 cells = lt_heap_used(&b->cell_heap);
  lt_i32 chunks = lt_irg_cell_chunks(-1, 0, cells);
  lt_i32 slot = lt_pool_insert(&b->pool, LT_IRG_KIND_MERGE, b->top_count + 1, 0, cells, 0, chunks);
  if (slot < 0) return;
  lt_irg_set_work(&b->pool.tasks[slot], -1, 0, 0, cells);
  lt_pool_publish(&b->pool, slot);
}

#endif
