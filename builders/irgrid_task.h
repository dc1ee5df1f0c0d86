/* The irregular grid's build as task-pool tasks (Perard-Gayot, Kalojanov and Slusallek 2017,
 * section 3), with its top cells materialised on demand (new here).
 *
 * The build's phases are tasks of their own kinds. The task that finishes a phase of a top
 * cell turns into the task of the next phase (lt_irg_hand_on, lt_pool_next_kind), whose first
 * chunk no work-group can take before the phase it needs is done:
 *
 *   COUNT      one task over all triangles, three phases whose chunks every work-group takes:
 *              0 counts the references of each top cell, 1 fills the top cells' lists, 2 sorts
 *              each list. Its phase ends take the lists' room from the reference heap and,
 *              last, insert one CELL task per top cell (waiting for a ray in a requested
 *              build). For a uniform grid (Thrane and Simonsen 2005) it is all there is: the
 *              top grid's lists are the uniform grid's cells (traversal/grid_traverse.h).
 *   CELL       one top cell, on one work-item: the initial subdivision into 8^level sub-voxels
 *              (level from the cell density lambda2 and the top cell's references), the SAH
 *              merge passes within it, and the cells that are left with their references.
 *   VOXEL_MAP  the top cell's sub-map, chunks of its cells spread over work-groups.
 *   EXPAND     one expansion pass over the top cell's cells (chunks over work-groups); the
 *              last pass publishes the top cell's map entry. In a full build with global
 *              merging the top cells are published without it, and the MERGE passes across
 *              the grid (builders/irgrid_global.h) hand on to EXPAND passes over every cell.
 *
 * A ray waiting for a top cell finds its slot in the top map, whichever phase runs there now,
 * and a request (its priority) carries over from phase to phase.
 *
 * Merging (section 3.2). A pass along axis a pairs each cell with the cell beyond its upper
 * face when the two have the same extent on the other axes and merging lowers the cost
 * (Ci * |T| + Ct) * SA(B); such pairs form chains along a, and each chain merges pairwise from
 * its lower end, so a pass never merges a cell twice. Passes go round the axes until one
 * merges fewer than (1 - alpha) of the cells it started with. Counts of merged cells come from one
 * sweep over the triangles per pass (the triangles a pair shares), never from lists.
 *
 * Merges stay inside a top cell: that is what lets a top cell be built alone, in any order,
 * and come out the same whether the build is full or on demand (the paper merges across top
 * cells too; docs/notes/irgrid.md says what that changes).
 *
 * Expansion (section 3.3): builders/irgrid_expand.h.
 *
 * References are conservative as in the uniform grid: a cell references every triangle whose
 * box meets its closed box, decided on the fine voxels that lt_grid_first_cell and
 * lt_grid_last_cell give for the box's ends. */
#ifndef LT_IRGRID_TASK_H
#define LT_IRGRID_TASK_H

#include "device/box.h"
#include "device/heap.h"
#include "device/irgrid_cells.h"
#include "device/pool.h"

/* Task kinds, as the irregular grid's workload numbers them (kernels/irgrid_ondemand.h). */
enum {
  LT_IRG_KIND_COUNT = 0,     /* the top grid's lists */
  LT_IRG_KIND_CELL = 1,      /* one top cell: subdivision, merge passes within it, references */
  LT_IRG_KIND_VOXEL_MAP = 2, /* one top cell's sub-map, from its cells */
  LT_IRG_KIND_EXPAND = 3,    /* one expansion pass over a top cell's cells, or the whole grid's */
  LT_IRG_KIND_MERGE = 4      /* one merge pass across top cells (full builds, builders/irgrid_global.h) */
};

/* Triangles per chunk of the counting phases, top cells per chunk of the sorting phase. */
#define LT_IRG_COUNT_CHUNK 1024
#define LT_IRG_SORT_CHUNK 64

/* A work-group's scratch, in ints: 12 arrays of one entry per sub-voxel of the deepest level,
 * then the packed sub-voxel ranges of up to LT_IRG_SCRATCH_RANGES triangles (more are
 * recomputed as needed). */
#define LT_IRG_MAX_SUBVOXELS (1 << (3 * LT_IRG_MAX_LEVEL))
#define LT_IRG_SCRATCH_RANGES (1 << 17)
#define LT_IRG_SCRATCH (12 * LT_IRG_MAX_SUBVOXELS + LT_IRG_SCRATCH_RANGES)

/* Per-work-group counters of the build and its traversal, one list: X(ID, STAT) with STAT the
 * statistic the host adds it to (LT_STAT_NONE: kept apart). */
#define LT_IRG_STAT_LIST(X)                                                         \
  X(LT_IRG_STAT_TOP_BUILT, LT_STAT_NONE) /* top cells materialised */               \
  X(LT_IRG_STAT_INITIAL, LT_STAT_NONE) /* cells of the initial subdivisions */      \
  X(LT_IRG_STAT_CELLS, LT_STAT_NONE) /* cells after merging */                      \
  X(LT_IRG_STAT_MERGES, LT_STAT_NONE) /* pairs merged within top cells */           \
  X(LT_IRG_STAT_GLOBAL_MERGES, LT_STAT_NONE) /* pairs merged by the global passes */ \
  X(LT_IRG_STAT_REFS_SAVED, LT_STAT_NONE) /* references the global merges saved */   \
  X(LT_IRG_STAT_EXPANSIONS, LT_STAT_NONE) /* layers grown */                        \
  X(LT_IRG_STAT_CELL_REFS, LT_STAT_NONE) /* references held by cells */             \
  X(LT_IRG_STAT_SORT_OPS, LT_STAT_SORT_OPS) /* references placed or compared */     \
  X(LT_IRG_STAT_STEPS, LT_STAT_TRAVERSAL_STEPS) /* cells visited */                 \
  X(LT_IRG_STAT_TESTS, LT_STAT_INTERSECTIONS) /* ray-triangle tests */

enum {
#define LT_IRG_STAT_ENUM(id, stat) id,
  LT_IRG_STAT_LIST(LT_IRG_STAT_ENUM)
#undef LT_IRG_STAT_ENUM
      LT_IRG_STAT_COUNT
};

typedef struct lt_irg_build {
  lt_pool pool;
  LT_GLOBAL const float *verts;       /* 9 per triangle, in scene order */
  LT_GLOBAL const lt_v4 *prim_boxes;  /* 2 per triangle: lo, hi */
  LT_GLOBAL const lt_grid_header *header; /* the fine grid */
  LT_GLOBAL lt_i32 *top_map;          /* per top cell (device/irgrid_cells.h) */
  LT_GLOBAL lt_i32 *top_begin;        /* top cells + 1: counts, then where each list begins in refs */
  LT_GLOBAL lt_i32 *top_fill;         /* per top cell: the fill cursor */
  LT_GLOBAL lt_i32 *sub_maps;         /* from map_heap */
  LT_GLOBAL lt_irg_cell *cells;       /* from cell_heap */
  LT_GLOBAL lt_i32 *refs;             /* from ref_heap: the top lists, then the cells' lists */
  LT_GLOBAL lt_i32 *scratch;          /* LT_IRG_SCRATCH per work-group */
  LT_GLOBAL lt_u32 *counters;         /* LT_IRG_STAT_COUNT per work-group */
  LT_GLOBAL lt_i32 *control;          /* LT_IRG_CONTROL_WORDS words (below) */
  LT_GLOBAL lt_i32 *cell_scratch;     /* 3 per unit of cell_heap: the global passes' scratch */
  lt_heap cell_heap, ref_heap, map_heap;
  lt_int4 fine_dims;                  /* the header's dims, for lookups */
  lt_i32 prim_count, top_count, shift;
  lt_i32 merge;                       /* whether to merge at all */
  lt_i32 global_merge;                /* whether a GLOBAL task merges across top cells once all are built */
  lt_i32 uniform;                     /* a uniform grid: the COUNT task alone, top cells never cut */
  lt_i32 expansion_passes;
  float cell_density;                 /* lambda2 */
  float merge_alpha;
  float traversal_cost, intersection_cost; /* Ct, Ci */
} lt_irg_build;

/* The build's kernel arguments (device/kernel_args.h); V is its path in the view. */
#define LT_IRG_BUILD_ARGS(X, V)                      \
  LT_POOL_ARGS(X, V.pool)                            \
  X(BUF, float, V.verts, verts)                      \
  X(BUF, lt_v4, V.prim_boxes, prim_boxes)            \
  X(BUF, lt_grid_header, V.header, header)           \
  X(BUF, lt_i32, V.top_map, top_map)                 \
  X(BUF, lt_i32, V.top_begin, top_begin)             \
  X(BUF, lt_i32, V.top_fill, top_fill)               \
  X(BUF, lt_i32, V.sub_maps, sub_maps)               \
  X(BUF, lt_irg_cell, V.cells, cells)                \
  X(BUF, lt_i32, V.refs, refs)                       \
  X(BUF, lt_i32, V.scratch, scratch)                 \
  X(BUF, lt_u32, V.counters, counters)               \
  X(BUF, lt_i32, V.control, control)                 \
  X(BUF, lt_i32, V.cell_scratch, cell_scratch)       \
  LT_HEAP_ARGS(X, V.cell_heap, cell_heap)            \
  LT_HEAP_ARGS(X, V.ref_heap, ref_heap)              \
  LT_HEAP_ARGS(X, V.map_heap, map_heap)              \
  X(VAL, lt_int4, V.fine_dims, fine_dims)            \
  X(VAL, lt_i32, V.prim_count, prim_count)           \
  X(VAL, lt_i32, V.top_count, top_count)             \
  X(VAL, lt_i32, V.shift, shift)                     \
  X(VAL, lt_i32, V.merge, merge)                     \
  X(VAL, lt_i32, V.global_merge, global_merge)       \
  X(VAL, lt_i32, V.uniform, uniform)                 \
  X(VAL, lt_i32, V.expansion_passes, expansion_passes) \
  X(VAL, float, V.cell_density, cell_density)        \
  X(VAL, float, V.merge_alpha, merge_alpha)          \
  X(VAL, float, V.traversal_cost, traversal_cost)    \
  X(VAL, float, V.intersection_cost, intersection_cost)

/* Words of the control buffer: top cells not built yet (set by the COUNT task). */
#define LT_IRG_CONTROL_TOPS_LEFT 0
#define LT_IRG_CONTROL_WORDS 4

LT_DEVICE void lt_irg_count(const lt_irg_build *b, int stat, lt_u32 n) {
  lt_atomic_add_u32(&b->counters[lt_group_id() * LT_IRG_STAT_COUNT + stat], n);
}

/* ---- Where a triangle is ---- */

/* The fine voxels a triangle's box meets: [lo[k], hi[k]] on each axis, inclusive. */
LT_DEVICE void lt_irg_fine_range(const lt_irg_build *b, lt_i32 prim, int lo[3], int hi[3]) {
  LT_GLOBAL const lt_v4 *box = b->prim_boxes + 2 * (long)prim;
  for (int k = 0; k < 3; k++) {
    lt_grid_axis a = lt_grid_axis_of(b->header, k);
    int first = lt_grid_first_cell(&a, lt_v4_lane(box[0], k)), last = lt_grid_last_cell(&a, lt_v4_lane(box[1], k));
    lo[k] = first < 0 ? 0 : first > a.n - 1 ? a.n - 1 : first;
    hi[k] = last < lo[k] ? lo[k] : last > a.n - 1 ? a.n - 1 : last;
  }
}

/* Whether inclusive range [lo, hi] meets box [blo, bhi) on every axis. */
LT_DEVICE int lt_irg_meets(const int lo[3], const int hi[3], const int blo[3], const int bhi[3]) {
  return lo[0] < bhi[0] && hi[0] >= blo[0] && lo[1] < bhi[1] && hi[1] >= blo[1] && lo[2] < bhi[2] && hi[2] >= blo[2];
}

/* The top cells a triangle meets (inclusive). */
LT_DEVICE void lt_irg_top_range(const lt_irg_build *b, lt_i32 prim, int lo[3], int hi[3]) {
  lt_irg_fine_range(b, prim, lo, hi);
  for (int k = 0; k < 3; k++) lo[k] >>= b->shift, hi[k] >>= b->shift;
}

/* ---- The COUNT task ---- */

/* Sorts a[0 .. n) ascending in place (heapsort: no recursion, no scratch). */
LT_DEVICE void lt_irg_sort(LT_GLOBAL lt_i32 *a, lt_i32 n) {
  for (lt_i32 start = n / 2 - 1, end = n; end > 1;) {
    lt_i32 root;
    if (start >= 0) {
      root = start--;
    } else {
      end--;
      lt_i32 t = a[0];
      a[0] = a[end], a[end] = t;
      root = 0;
    }
    for (lt_i32 child; (child = 2 * root + 1) < end; root = child) {
      if (child + 1 < end && a[child + 1] > a[child]) child++;
      if (a[root] >= a[child]) break;
      lt_i32 t = a[root];
      a[root] = a[child], a[child] = t;
    }
  }
}

/* One chunk of the COUNT task: phase 0 counts, 1 fills, 2 sorts. */
LT_DEVICE void lt_irg_count_chunk(const lt_irg_build *b, lt_i32 slot, lt_i32 chunk, int lid, int lsize) {
  lt_i32 phase = b->pool.tasks[slot].phase;
  int tx = b->fine_dims.x >> b->shift, ty = b->fine_dims.y >> b->shift;
  if (phase == 2) {
    lt_i32 first = chunk * LT_IRG_SORT_CHUNK, end = first + LT_IRG_SORT_CHUNK;
    for (lt_i32 t = first + lid; t < end && t < b->top_count; t += lsize) {
      lt_i32 begin = b->top_begin[t];
      lt_irg_sort(b->refs + begin, b->top_begin[t + 1] - begin);
    }
    return;
  }
  lt_i32 first = chunk * LT_IRG_COUNT_CHUNK, end = first + LT_IRG_COUNT_CHUNK;
  for (lt_i32 prim = first + lid; prim < end && prim < b->prim_count; prim += lsize) {
    int lo[3], hi[3];
    lt_irg_top_range(b, prim, lo, hi);
    for (int z = lo[2]; z <= hi[2]; z++)
      for (int y = lo[1]; y <= hi[1]; y++)
        for (int x = lo[0]; x <= hi[0]; x++) {
          lt_i32 t = lt_grid_cell_index(tx, ty, x, y, z);
          if (phase == 0) lt_atomic_add_i32(&b->top_begin[t], 1);
          else b->refs[lt_atomic_add_i32(&b->top_fill[t], 1)] = prim;
        }
  }
}

/* Inserts the CELL task of every top cell and points the top map at it. */
LT_DEVICE void lt_irg_spawn_cells(const lt_irg_build *b) {
  for (lt_i32 t = 0; t < b->top_count; t++) {
    lt_i32 slot = lt_pool_insert(&b->pool, LT_IRG_KIND_CELL, t + 1, b->top_begin[t], b->top_begin[t + 1], 0, 1);
    if (slot < 0) return;
    lt_atomic_store_i32(&b->top_map[t], LT_IRG_UNBUILT(slot));
    lt_pool_publish(&b->pool, slot);
  }
}

/* The end of a COUNT phase, on work-item 0 of the group that finished it. */
LT_DEVICE void lt_irg_count_end(const lt_irg_build *b, lt_i32 slot) {
  LT_GLOBAL lt_task *task = &b->pool.tasks[slot];
  lt_i32 phase = task->phase;
  if (phase == 0) {
    /* Room for every list at once, then where each begins. */
    lt_i32 total = 0;
    for (lt_i32 t = 0; t < b->top_count; t++) total += b->top_begin[t];
    lt_i32 base = lt_heap_alloc(&b->ref_heap, total);
    if (base < 0) {
      lt_pool_fail(&b->pool, LT_POOL_ERROR_HEAP);
      return;
    }
    for (lt_i32 t = 0, at = base; t <= b->top_count; t++) {
      lt_i32 n = t < b->top_count ? b->top_begin[t] : 0;
      b->top_begin[t] = at;
      if (t < b->top_count) b->top_fill[t] = at;
      at += n;
    }
    lt_irg_count(b, LT_IRG_STAT_SORT_OPS, (lt_u32)total);
    lt_fence();
    lt_pool_next_phase(&b->pool, slot, 1, task->end / LT_IRG_COUNT_CHUNK + (task->end % LT_IRG_COUNT_CHUNK != 0));
  } else if (phase == 1) {
    lt_fence();
    lt_pool_next_phase(&b->pool, slot, 2, (b->top_count + LT_IRG_SORT_CHUNK - 1) / LT_IRG_SORT_CHUNK);
  } else {
    lt_atomic_store_i32(&b->control[LT_IRG_CONTROL_TOPS_LEFT], b->top_count);
    lt_fence();
    if (!b->uniform) lt_irg_spawn_cells(b);
    lt_pool_retire(&b->pool, slot);
  }
}

/* ---- The CELL task: one top cell's subdivision and merges ---- */

/* A top cell being materialised: where it is and its scratch arrays. */
typedef struct lt_irg_top {
  lt_i32 t, begin, m;   /* top cell, its list refs[begin .. begin + m) */
  int origin[3];        /* its lowest fine voxel */
  int level, side, step; /* 2^level sub-voxels per axis, each step fine voxels wide */
  lt_i32 voxels;        /* side^3 */
  float width[3];       /* a sub-voxel's size in the scene's units */
  LT_GLOBAL lt_i32 *smap, *box, *count, *stamp, *shared, *cand, *ranges;
  lt_i32 cached;        /* triangles whose packed range is in `ranges` */
} lt_irg_top;

/* The level of a top cell with m references: the least with 8^level >= lambda2 * m. */
LT_DEVICE int lt_irg_level(float density, lt_i32 m) {
  float want = density * (float)m;
  int level = 0;
  while (level < LT_IRG_MAX_LEVEL && (float)(1 << (3 * level)) < want) level++;
  return level;
}

/* Triangle i of the top cell's list: its sub-voxel range [lo, hi] (inclusive, clamped to the
 * top cell), packed 5 bits a number. */
LT_DEVICE lt_i32 lt_irg_pack_range(const lt_irg_build *b, const lt_irg_top *c, lt_i32 prim) {
  int lo[3], hi[3];
  lt_irg_fine_range(b, prim, lo, hi);
  lt_i32 packed = 0;
  int down = b->shift - c->level;
  for (int k = 0; k < 3; k++) {
    int l = lo[k] - c->origin[k], h = hi[k] - c->origin[k], top = (1 << b->shift) - 1;
    l = l < 0 ? 0 : l > top ? top : l;
    h = h < 0 ? 0 : h > top ? top : h;
    packed |= ((l >> down) << (5 * k)) | ((h >> down) << (15 + 5 * k));
  }
  return packed;
}

LT_DEVICE lt_i32 lt_irg_range_of(const lt_irg_build *b, const lt_irg_top *c, lt_i32 i) {
  return i < c->cached ? c->ranges[i] : lt_irg_pack_range(b, c, b->refs[c->begin + i]);
}

LT_DEVICE void lt_irg_unpack(lt_i32 packed, int lo[3], int hi[3]) {
  for (int k = 0; k < 3; k++) lo[k] = (packed >> (5 * k)) & 31, hi[k] = (packed >> (15 + 5 * k)) & 31;
}

LT_DEVICE lt_i32 lt_irg_voxel(const lt_irg_top *c, int x, int y, int z) { return x + c->side * (y + c->side * z); }

/* Cell j's box in sub-voxels: lo at box[6j .. 6j + 3), hi (exclusive) at box[6j + 3 .. 6j + 6). */
LT_DEVICE float lt_irg_cost(const lt_irg_build *b, const lt_irg_top *c, const int lo[3], const int hi[3], lt_i32 n) {
  float e0 = (float)(hi[0] - lo[0]) * c->width[0], e1 = (float)(hi[1] - lo[1]) * c->width[1];
  float e2 = (float)(hi[2] - lo[2]) * c->width[2];
  return (b->intersection_cost * (float)n + b->traversal_cost) * (e0 * e1 + e1 * e2 + e2 * e0);
}

LT_DEVICE void lt_irg_box_of(const lt_irg_top *c, lt_i32 j, int lo[3], int hi[3]) {
  for (int k = 0; k < 3; k++) lo[k] = c->box[6 * j + k], hi[k] = c->box[6 * j + 3 + k];
}

/* One merge pass along axis a; returns the pairs merged. */
LT_DEVICE lt_i32 lt_irg_merge_pass(const lt_irg_build *b, lt_irg_top *c, int a) {
  int o1 = (a + 1) % 3, o2 = (a + 2) % 3;
  /* The candidate beyond each live cell's upper face: same extent on the other axes. */
  for (lt_i32 j = 0; j < c->voxels; j++) {
    c->cand[j] = -1, c->shared[j] = 0, c->stamp[j] = -1;
    if (c->count[j] < 0) continue;
    int lo[3], hi[3];
    lt_irg_box_of(c, j, lo, hi);
    if (hi[a] >= c->side) continue;
    int at[3] = {lo[0], lo[1], lo[2]};
    at[a] = hi[a];
    lt_i32 n = c->smap[lt_irg_voxel(c, at[0], at[1], at[2])];
    int nlo[3], nhi[3];
    lt_irg_box_of(c, n, nlo, nhi);
    if (nlo[a] == hi[a] && nlo[o1] == lo[o1] && nhi[o1] == hi[o1] && nlo[o2] == lo[o2] && nhi[o2] == hi[o2])
      c->cand[j] = n;
  }
  /* The triangles each pair shares: one sweep, each triangle counted once per cell it meets. */
  for (lt_i32 i = 0; i < c->m; i++) {
    int lo[3], hi[3];
    lt_irg_unpack(lt_irg_range_of(b, c, i), lo, hi);
    if (lo[a] == hi[a]) continue; /* one sub-voxel thick along a: meets no two cells a pair apart */
    for (int z = lo[2]; z <= hi[2]; z++)
      for (int y = lo[1]; y <= hi[1]; y++)
        for (int x = lo[0]; x <= hi[0]; x++) {
          lt_i32 j = c->smap[lt_irg_voxel(c, x, y, z)];
          x = c->box[6 * j + 3] - 1; /* the rest of this row up to the cell's end is the same cell */
          if (c->stamp[j] == i) continue;
          c->stamp[j] = i;
          lt_i32 n = c->cand[j];
          if (n < 0) continue;
          int nlo[3], nhi[3];
          lt_irg_box_of(c, n, nlo, nhi);
          if (lt_irg_meets(lo, hi, nlo, nhi)) c->shared[j]++;
        }
  }
  /* Keep the pairs whose merge lowers the cost; mark the cells something points at. */
  for (lt_i32 j = 0; j < c->voxels; j++) c->stamp[j] = 0;
  for (lt_i32 j = 0; j < c->voxels; j++) {
    lt_i32 n = c->cand[j];
    if (n < 0) continue;
    int lo[3], hi[3], nlo[3], nhi[3];
    lt_irg_box_of(c, j, lo, hi);
    lt_irg_box_of(c, n, nlo, nhi);
    int ulo[3] = {lo[0], lo[1], lo[2]}, uhi[3] = {hi[0], hi[1], hi[2]};
    uhi[a] = nhi[a];
    lt_i32 both = c->count[j] + c->count[n] - c->shared[j];
    if (lt_irg_cost(b, c, ulo, uhi, both) < lt_irg_cost(b, c, lo, hi, c->count[j]) + lt_irg_cost(b, c, nlo, nhi, c->count[n]))
      c->stamp[n] = 1, c->shared[j] = both;
    else
      c->cand[j] = -1;
  }
  /* Pairwise along each chain, from its lower end. */
  lt_i32 merged = 0;
  for (lt_i32 h = 0; h < c->voxels; h++) {
    if (c->cand[h] < 0 || c->stamp[h]) continue;
    for (lt_i32 j = h; j >= 0 && c->cand[j] >= 0;) {
      lt_i32 n = c->cand[j], next = c->cand[n];
      int nlo[3], nhi[3];
      lt_irg_box_of(c, n, nlo, nhi);
      for (int z = nlo[2]; z < nhi[2]; z++)
        for (int y = nlo[1]; y < nhi[1]; y++)
          for (int x = nlo[0]; x < nhi[0]; x++) c->smap[lt_irg_voxel(c, x, y, z)] = j;
      c->box[6 * j + 3 + a] = nhi[a];
      c->count[j] = c->shared[j];
      c->count[n] = -1;
      merged++;
      j = next;
    }
  }
  return merged;
}

/* Fails the build for a full heap (or an impossible map offset) and says so. */
LT_DEVICE int lt_irg_heap_failed(const lt_irg_build *b, lt_i32 at) {
  if (at >= 0) return 0;
  lt_pool_fail(&b->pool, LT_POOL_ERROR_HEAP);
  return 1;
}

/* ---- Handing a top cell on from phase to phase ---- */

/* Work words of the tasks after COUNT (task->work). */
#define LT_IRG_W_PASS 0  /* merge or expansion pass, from 0 */
#define LT_IRG_W_TOP 1   /* the top cell the task builds, or -1: the whole grid */
#define LT_IRG_W_ENTRY 2 /* that top cell's map entry, published by its last task */
#define LT_IRG_W_CHUNK 3 /* cells per chunk */
#define LT_IRG_W_LIVE 4  /* MERGE: live cells before this pass */
#define LT_IRG_W_PAIRS 5 /* MERGE: pairs this pass merges */

/* Cells per chunk of a task over one top cell's cells, and over the whole grid's. */
#define LT_IRG_TOP_CHUNK 64
#define LT_IRG_GLOBAL_CHUNK 256

/* Whether MERGE tasks merge across top cells once all are built (full builds only: a launch
 * of their own, kernels/irgrid_ondemand.h). */
LT_DEVICE int lt_irg_merges_later(const lt_irg_build *b) { return b->global_merge && b->pool.mode == LT_POOL_FULL; }

/* A cell a global merge folded into its partner. */
LT_DEVICE int lt_irg_dead(LT_GLOBAL const lt_irg_cell *cell) { return cell->lo[0] < 0; }

/* A task's work words for a step over cells of top cell t (or, t < 0, the whole grid). */
LT_DEVICE void lt_irg_set_work(LT_GLOBAL lt_task *task, lt_i32 t, lt_i32 entry, lt_i32 pass, lt_i32 live) {
  task->work[LT_IRG_W_PASS] = pass, task->work[LT_IRG_W_TOP] = t, task->work[LT_IRG_W_ENTRY] = entry;
  task->work[LT_IRG_W_CHUNK] = t < 0 ? LT_IRG_GLOBAL_CHUNK : LT_IRG_TOP_CHUNK, task->work[LT_IRG_W_LIVE] = live;
}

/* Chunks of a task over cells [begin, end) of top cell t (or, t < 0, the whole grid). */
LT_DEVICE lt_i32 lt_irg_cell_chunks(lt_i32 t, lt_i32 begin, lt_i32 end) {
  lt_i32 chunk = t < 0 ? LT_IRG_GLOBAL_CHUNK : LT_IRG_TOP_CHUNK, chunks = (end - begin + chunk - 1) / chunk;
  return chunks > 0 ? chunks : 1;
}

/* Hands top cell t (or, t < 0, the whole grid) on from the task in `slot`, whose phase is
 * done, to its next step: the slot becomes a task of `kind` over cells [begin, end)
 * (lt_pool_next_kind), so a ray waiting for the top cell, which names the slot, asks for the
 * step that is running now, and a request carries over. */
LT_DEVICE void lt_irg_hand_on(const lt_irg_build *b, lt_i32 slot, lt_i32 kind, lt_i32 t, lt_i32 entry, lt_i32 pass,
                              lt_i32 live, lt_i32 begin, lt_i32 end) {
  lt_irg_set_work(&b->pool.tasks[slot], t, entry, pass, live);
  lt_fence();
  lt_pool_next_kind(&b->pool, slot, kind, begin, end, lt_irg_cell_chunks(t, begin, end));
}

/* The cells [first, end) of chunk `chunk` of a task over cells. */
LT_DEVICE void lt_irg_chunk_cells(LT_GLOBAL const lt_task *task, lt_i32 chunk, lt_i32 *first, lt_i32 *end) {
  *first = task->begin + chunk * task->work[LT_IRG_W_CHUNK];
  *end = *first + task->work[LT_IRG_W_CHUNK] < task->end ? *first + task->work[LT_IRG_W_CHUNK] : task->end;
}

/* Publishes built top cell t: its cells and sub-map first, then the entry; and retires the
 * task in `slot`, the top cell's last. */
LT_DEVICE void lt_irg_publish_top(const lt_irg_build *b, lt_i32 slot, lt_i32 t, lt_i32 entry) {
  lt_irg_count(b, LT_IRG_STAT_TOP_BUILT, 1);
  lt_fence();
  lt_atomic_store_i32(&b->top_map[t], entry);
  lt_atomic_add_i32(&b->control[LT_IRG_CONTROL_TOPS_LEFT], -1);
  lt_pool_retire(&b->pool, slot);
}

/* Materialises the task's top cell: subdivision, merge passes, the cells and their references. */
LT_DEVICE void lt_irg_build_top(const lt_irg_build *b, lt_i32 slot) {
  LT_GLOBAL lt_task *task = &b->pool.tasks[slot];
  lt_irg_top c;
  c.t = lt_atomic_load_i32(&task->node) - 1;
  c.begin = task->begin, c.m = task->end - task->begin;
  int tx = b->fine_dims.x >> b->shift, ty = b->fine_dims.y >> b->shift;
  int top[3] = {c.t % tx, (c.t / tx) % ty, c.t / (tx * ty)};
  for (int k = 0; k < 3; k++) c.origin[k] = top[k] << b->shift;
  c.level = lt_irg_level(b->cell_density, c.m);
  c.side = 1 << c.level, c.step = 1 << (b->shift - c.level), c.voxels = c.side * c.side * c.side;
  for (int k = 0; k < 3; k++) c.width[k] = lt_grid_axis_of(b->header, k).size * (float)c.step;
  LT_GLOBAL lt_i32 *s = b->scratch + (long)lt_group_id() * LT_IRG_SCRATCH;
  c.smap = s, c.box = s + c.voxels, c.count = s + 7 * c.voxels, c.stamp = s + 8 * c.voxels;
  c.shared = s + 9 * c.voxels, c.cand = s + 10 * c.voxels, c.ranges = s + 12 * LT_IRG_MAX_SUBVOXELS;
  c.cached = 0;
  for (lt_i32 i = 0; i < c.m && i < LT_IRG_SCRATCH_RANGES; i++) c.ranges[i] = lt_irg_pack_range(b, &c, b->refs[c.begin + i]);
  c.cached = c.m < LT_IRG_SCRATCH_RANGES ? c.m : LT_IRG_SCRATCH_RANGES;

  /* The initial subdivision: a cell per sub-voxel, and how many triangles meet each. */
  for (lt_i32 j = 0; j < c.voxels; j++) {
    int x = j % c.side, y = (j / c.side) % c.side, z = j / (c.side * c.side);
    c.smap[j] = j, c.count[j] = 0;
    c.box[6 * j] = x, c.box[6 * j + 1] = y, c.box[6 * j + 2] = z;
    c.box[6 * j + 3] = x + 1, c.box[6 * j + 4] = y + 1, c.box[6 * j + 5] = z + 1;
  }
  lt_u32 placed = 0;
  for (lt_i32 i = 0; i < c.m; i++) {
    int lo[3], hi[3];
    lt_irg_unpack(lt_irg_range_of(b, &c, i), lo, hi);
    for (int z = lo[2]; z <= hi[2]; z++)
      for (int y = lo[1]; y <= hi[1]; y++)
        for (int x = lo[0]; x <= hi[0]; x++) c.count[lt_irg_voxel(&c, x, y, z)]++, placed++;
  }
  lt_irg_count(b, LT_IRG_STAT_INITIAL, (lt_u32)c.voxels);

  /* Merge passes round the axes until a pass leaves at least alpha of the cells it started
   * with (merges fewer than 1 - alpha of them). */
  lt_i32 live = c.voxels, merges = 0;
  if (b->merge && c.voxels > 1) {
    for (int a = 0;; a = (a + 1) % 3) {
      lt_i32 merged = lt_irg_merge_pass(b, &c, a);
      float threshold = (1.0f - b->merge_alpha) * (float)live;
      merges += merged, live -= merged;
      if ((float)merged < threshold || merged == 0) break;
    }
  }
  lt_irg_count(b, LT_IRG_STAT_MERGES, (lt_u32)merges);
  lt_irg_count(b, LT_IRG_STAT_CELLS, (lt_u32)live);

  /* Room for the cells, the sub-map and the references (a top cell of one cell keeps its list). */
  lt_i32 refs = 0;
  for (lt_i32 j = 0; j < c.voxels; j++) refs += c.count[j] > 0 ? c.count[j] : 0;
  lt_i32 first_cell = lt_heap_alloc(&b->cell_heap, live);
  lt_i32 map = lt_heap_alloc(&b->map_heap, c.voxels);
  lt_i32 first_ref = c.voxels == 1 ? c.begin : lt_heap_alloc(&b->ref_heap, refs);
  if (lt_irg_heap_failed(b, first_cell) || lt_irg_heap_failed(b, map) || lt_irg_heap_failed(b, first_ref) ||
      lt_irg_heap_failed(b, map + c.voxels > LT_IRG_MAX_MAP ? -1 : 0))
    return;

  /* Number the live cells (cand: scratch number -> cell), give each its slice of references
   * (shared: the fill cursor), and fill them in list order, which keeps every slice ascending. */
  lt_i32 next = 0, at = first_ref;
  for (lt_i32 j = 0; j < c.voxels; j++) {
    if (c.count[j] < 0) continue;
    c.cand[j] = first_cell + next++;
    c.shared[j] = at, c.stamp[j] = -1;
    LT_GLOBAL lt_irg_cell *cell = &b->cells[c.cand[j]];
    cell->begin = at, cell->end = at + c.count[j];
    at += c.count[j];
  }
  if (c.voxels > 1) {
    for (lt_i32 i = 0; i < c.m; i++) {
      int lo[3], hi[3];
      lt_irg_unpack(lt_irg_range_of(b, &c, i), lo, hi);
      for (int z = lo[2]; z <= hi[2]; z++)
        for (int y = lo[1]; y <= hi[1]; y++)
          for (int x = lo[0]; x <= hi[0]; x++) {
            lt_i32 j = c.smap[lt_irg_voxel(&c, x, y, z)];
            x = c.box[6 * j + 3] - 1; /* the rest of this row up to the cell's end is the same cell */
            if (c.stamp[j] == i) continue;
            c.stamp[j] = i;
            b->refs[c.shared[j]++] = b->refs[c.begin + i];
          }
    }
  }

  /* Each cell's fine box as merging left it; VOXEL_MAP writes the sub-map from these boxes
   * and EXPAND grows them. */
  for (lt_i32 j = 0; j < c.voxels; j++) {
    if (c.count[j] < 0) continue;
    int lo[3], hi[3];
    lt_irg_box_of(&c, j, lo, hi);
    LT_GLOBAL lt_irg_cell *cell = &b->cells[c.cand[j]];
    for (int k = 0; k < 3; k++) cell->lo[k] = c.origin[k] + lo[k] * c.step, cell->hi[k] = c.origin[k] + hi[k] * c.step;
  }
  lt_irg_count(b, LT_IRG_STAT_CELL_REFS, (lt_u32)(c.voxels == 1 ? c.m : refs));
  lt_irg_count(b, LT_IRG_STAT_SORT_OPS, placed);

  /* On to the voxel map over the cells just made (lt_irg_hand_on fences the writes above). */
  lt_i32 entry = LT_IRG_ENTRY(c.level, map);
  lt_irg_hand_on(b, slot, LT_IRG_KIND_VOXEL_MAP, c.t, entry, 0, live, first_cell, first_cell + live);
}

/* The CELL task has one chunk, whose work its phase end does on work-item 0: the merge
 * passes need the whole top cell's scratch at once (see docs/notes/irgrid.md). */
LT_DEVICE void lt_irg_cell_chunk(const lt_irg_build *b, lt_i32 slot, lt_i32 chunk, int lid, int lsize) {
  (void)b, (void)slot, (void)chunk, (void)lid, (void)lsize;
}
LT_DEVICE void lt_irg_cell_end(const lt_irg_build *b, lt_i32 slot) { lt_irg_build_top(b, slot); }

/* ---- The VOXEL_MAP task: one top cell's sub-map, from its cells' boxes ---- */

/* Points the sub-voxels of each cell of the chunk at the cell (cells tile their top cell). */
LT_DEVICE void lt_irg_voxel_map_chunk(const lt_irg_build *b, lt_i32 slot, lt_i32 chunk, int lid, int lsize) {
  LT_GLOBAL const lt_task *task = &b->pool.tasks[slot];
  lt_i32 t = task->work[LT_IRG_W_TOP], entry = task->work[LT_IRG_W_ENTRY], first, end;
  lt_irg_chunk_cells(task, chunk, &first, &end);
  int level = LT_IRG_ENTRY_LEVEL(entry), down = b->shift - level, side = 1 << level;
  int tx = b->fine_dims.x >> b->shift, ty = b->fine_dims.y >> b->shift;
  int origin[3] = {(t % tx) << b->shift, ((t / tx) % ty) << b->shift, (t / (tx * ty)) << b->shift};
  LT_GLOBAL lt_i32 *map = b->sub_maps + LT_IRG_ENTRY_BASE(entry);
  for (lt_i32 j = first + lid; j < end; j += lsize) {
    LT_GLOBAL const lt_irg_cell *cell = &b->cells[j];
    int lo[3], hi[3];
    for (int k = 0; k < 3; k++) lo[k] = (cell->lo[k] - origin[k]) >> down, hi[k] = (cell->hi[k] - origin[k]) >> down;
    for (int z = lo[2]; z < hi[2]; z++)
      for (int y = lo[1]; y < hi[1]; y++)
        for (int x = lo[0]; x < hi[0]; x++) map[x + side * (y + side * z)] = j;
  }
}

/* With the sub-map written: on to the expansion passes, or publish the top cell when there
 * are none here (none asked for, or the MERGE passes across the grid come first). */
LT_DEVICE void lt_irg_voxel_map_end(const lt_irg_build *b, lt_i32 slot) {
  LT_GLOBAL const lt_task *task = &b->pool.tasks[slot];
  lt_i32 t = task->work[LT_IRG_W_TOP], entry = task->work[LT_IRG_W_ENTRY];
  if (b->expansion_passes > 0 && !lt_irg_merges_later(b))
    lt_irg_hand_on(b, slot, LT_IRG_KIND_EXPAND, t, entry, 0, task->work[LT_IRG_W_LIVE], task->begin, task->end);
  else
    lt_irg_publish_top(b, slot, t, entry);
}

/* The build's start, once, by one work-item, before the first launch: the COUNT task,
 * unlocked in every mode (rays wait for the top level without asking for it). */
LT_DEVICE void lt_irg_setup(const lt_irg_build *b) {
  lt_i32 chunks = b->prim_count / LT_IRG_COUNT_CHUNK + (b->prim_count % LT_IRG_COUNT_CHUNK != 0);
  lt_i32 slot = lt_pool_insert(&b->pool, LT_IRG_KIND_COUNT, 0, 0, b->prim_count, 0, chunks);
  if (slot < 0) return;
  lt_fence();
  lt_atomic_store_i32(&b->pool.headers[slot], chunks);
}

#endif
