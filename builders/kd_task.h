/* kd-tree node subdivision as task-pool tasks: the on-demand paper (Vinkler et al. 2016),
 * section 3.5. A task splits the cell behind one child link in one go, on one work-item:
 * binned SAH over all three axes (Wald and Havran 2006 price the planes the same way, with
 * every event instead of bins), a triangle straddling the plane referenced by both children,
 * the left child's references compacted in place in the cell's array and the right child's
 * taken from the device heap, then the node is written, its
 * children get tasks (or are made leaves at once when they are small) and it is linked into
 * its parent. The same code makes full, requested and speculative builds, so a node built on
 * demand has the split plane and references of the same node of the full tree.
 *
 * Termination as in the paper: a leaf at most max_leaf references, depth at most
 * 1.2 * log2(N) + 2 (the host computes max_depth), and the first failed split makes a leaf,
 * where a split fails when its cost is above 0.9 of the leaf's. A split that leaves one side
 * empty is priced 0.8 of its cost (the empty-space bonus of Wald and Havran 2006), so that SAH
 * cuts off empty space where it pays. */
#ifndef LT_KD_TASK_H
#define LT_KD_TASK_H

#include "builders/sah_bins.h"
#include "device/heap.h"
#include "device/kd_node.h"
#include "device/pool.h"

#define LT_KD_FAIL_RATIO 0.9f   /* r_q^min of the paper: a split dearer than this makes a leaf */
#define LT_KD_EMPTY_BONUS 0.8f  /* a split with an empty side costs this much of its price */
#define LT_KD_SWEEP_MAX 1024    /* the exact sweep prices cells of at most this many references */

/* Task data (lt_task.work): the cell's bounds. The task's begin and end are its reference
 * array in the heap. */
#define LT_KD_W_BOUNDS 0

/* Per-work-group counters of the build and its traversal, one list: X(ID, STAT) with STAT
 * the statistic the host adds it to (LT_STAT_NONE: kept apart). */
#define LT_KD_STAT_LIST(X)                                                    \
  X(LT_KD_STAT_LEAVES, LT_STAT_NONE) /* leaves made */                        \
  X(LT_KD_STAT_LEAF_REFS, LT_STAT_NONE) /* references held by leaves */       \
  X(LT_KD_STAT_DEPTH, LT_STAT_NONE) /* deepest leaf (a maximum, not a sum) */ \
  X(LT_KD_STAT_SORT_OPS, LT_STAT_SORT_OPS) /* references binned or partitioned */ \
  X(LT_KD_STAT_STEPS, LT_STAT_TRAVERSAL_STEPS) /* node visits */             \
  X(LT_KD_STAT_TESTS, LT_STAT_INTERSECTIONS) /* ray-triangle tests */

enum {
#define LT_KD_STAT_ENUM(id, stat) id,
  LT_KD_STAT_LIST(LT_KD_STAT_ENUM)
#undef LT_KD_STAT_ENUM
      LT_KD_STAT_COUNT
};

typedef struct lt_kd_build {
  lt_pool pool;
  LT_GLOBAL const float *verts; /* 9 per triangle, in scene order (the scene's own array) */
  LT_GLOBAL const lt_v4 *prim_boxes; /* 2 per triangle: lo, hi (lanes x y z; computed once) */
  LT_GLOBAL lt_kd_node *nodes;  /* from node_heap */
  LT_GLOBAL lt_i32 *refs;       /* reference arrays, from ref_heap */
  LT_GLOBAL lt_i32 *parents;    /* per node: the node whose link leads to it */
  LT_GLOBAL float *cells;       /* per node: its cell, lo xyz hi xyz (stackless backtracking) */
  LT_GLOBAL lt_u32 *counters;   /* LT_KD_STAT_COUNT per work-group */
  lt_heap node_heap, ref_heap;
  lt_i32 task_kind;             /* the number the running workload gave these tasks */
  lt_i32 max_leaf, bins, max_depth;
  lt_i32 sweep; /* exact split sweep over cells of up to LT_KD_SWEEP_MAX references */
  lt_i32 clip;  /* classify by the box of the triangle's part inside the cell */
  float traversal_cost, intersection_cost;
} lt_kd_build;

/* The build's kernel arguments (device/kernel_args.h); V is its path in the view. */
#define LT_KD_BUILD_ARGS(X, V)                    \
  LT_POOL_ARGS(X, V.pool)                         \
  X(BUF, float, V.verts, verts)                   \
  X(BUF, lt_v4, V.prim_boxes, prim_boxes)         \
  X(BUF, lt_kd_node, V.nodes, nodes)              \
  X(BUF, lt_i32, V.refs, refs)                    \
  X(BUF, lt_i32, V.parents, parents)              \
  X(BUF, float, V.cells, cells)                   \
  X(BUF, lt_u32, V.counters, counters)            \
  LT_HEAP_ARGS(X, V.node_heap, node_heap)         \
  LT_HEAP_ARGS(X, V.ref_heap, ref_heap)           \
  X(VAL, lt_i32, V.task_kind, task_kind)          \
  X(VAL, lt_i32, V.max_leaf, max_leaf)            \
  X(VAL, lt_i32, V.bins, bins)                    \
  X(VAL, lt_i32, V.max_depth, max_depth)          \
  X(VAL, lt_i32, V.sweep, sweep)                  \
  X(VAL, lt_i32, V.clip, clip)                    \
  X(VAL, float, V.traversal_cost, traversal_cost) \
  X(VAL, float, V.intersection_cost, intersection_cost)

LT_DEVICE void lt_kd_count(const lt_kd_build *b, int stat, lt_u32 n) {
  lt_atomic_add_u32(&b->counters[lt_group_id() * LT_KD_STAT_COUNT + stat], n);
}

/* A triangle's box. */
LT_DEVICE lt_box lt_kd_prim_box(const lt_kd_build *b, lt_i32 prim) {
  LT_GLOBAL const lt_v4 *box = b->prim_boxes + 2 * (long)prim;
  return lt_box_of4(box[0], box[1]);
}

#ifdef LT_HAVE_DOUBLE
typedef double lt_kd_real;
#else
typedef float lt_kd_real;
#endif

/* The box of the part of triangle `prim` inside the closed cell ("perfect splits"): the
 * triangle clipped by the cell's six planes (Sutherland and Hodgman) in double, and the bounds
 * taken as floats. A coordinate that is a vertex's own or a cell plane's is exact; one computed
 * where an edge crosses a plane is rounded outwards by a float step, so the box only ever
 * grows: a child that holds part of the triangle always references it, and a triangle that
 * only touches a plane stays on its side. The box stays inside the triangle's own box; it is
 * empty (lo > hi) when nothing of the triangle lies in the cell. */
LT_DEVICE lt_box lt_kd_clipped_box(const lt_kd_build *b, lt_i32 prim, const lt_box *cell) {
  LT_GLOBAL const float *v = b->verts + 9 * (long)prim;
  lt_kd_real poly[2][9][3];
  int exact[2][9]; /* per vertex: bit k when coordinate k is exactly a float */
  int n = 3, cur = 0;
  for (int i = 0; i < 3; i++) {
    for (int k = 0; k < 3; k++) poly[0][i][k] = v[3 * i + k];
    exact[0][i] = 7;
  }
  for (int plane = 0; plane < 6 && n > 0; plane++) {
    int k = plane >> 1, upper = plane & 1, m = 0;
    lt_kd_real bound = upper ? cell->hi[k] : cell->lo[k];
    for (int i = 0; i < n; i++) {
      int j = (i + 1) % n;
      const lt_kd_real *a = poly[cur][i], *c = poly[cur][j];
      int in_a = upper ? a[k] <= bound : a[k] >= bound, in_c = upper ? c[k] <= bound : c[k] >= bound;
      if (in_a && m < 9) {
        for (int x = 0; x < 3; x++) poly[1 - cur][m][x] = a[x];
        exact[1 - cur][m++] = exact[cur][i];
      }
      if (in_a != in_c && m < 9) {
        lt_kd_real t = (bound - a[k]) / (c[k] - a[k]);
        for (int x = 0; x < 3; x++) poly[1 - cur][m][x] = a[x] + t * (c[x] - a[x]);
        poly[1 - cur][m][k] = bound;
        exact[1 - cur][m++] = 1 << k;
      }
    }
    n = m, cur = 1 - cur;
  }
  lt_box box = lt_box_empty(), own = lt_kd_prim_box(b, prim);
  for (int i = 0; i < n; i++)
    for (int k = 0; k < 3; k++) {
      float x = (float)poly[cur][i][k], step = (exact[cur][i] >> k & 1) ? 0.0f : lt_fabsf(x) * 2.4e-7f + 1e-30f;
      float lo = x - step, hi = x + step;
      box.lo[k] = lo < box.lo[k] ? lo : box.lo[k];
      box.hi[k] = hi > box.hi[k] ? hi : box.hi[k];
    }
  for (int k = 0; k < 3 && n > 0; k++) {
    box.lo[k] = box.lo[k] > own.lo[k] ? box.lo[k] : own.lo[k];
    box.hi[k] = box.hi[k] < own.hi[k] ? box.hi[k] : own.hi[k];
  }
  return box;
}

/* The box a reference is classified and priced by: the triangle's own, or with clipping the
 * box of its part inside the cell. */
LT_DEVICE lt_box lt_kd_ref_box(const lt_kd_build *b, lt_i32 prim, const lt_box *cell) {
  return b->clip ? lt_kd_clipped_box(b, prim, cell) : lt_kd_prim_box(b, prim);
}

/* Which children a triangle whose box spans [lo, hi] on the split's axis belongs to: the left
 * when it reaches below the plane, the right when it reaches above, both when it straddles. A
 * triangle that only touches the plane from one side belongs to that side alone, and one lying
 * in the plane to the side the split chose (Wald and Havran 2006): a ray meets either on the
 * plane at the plane's distance, where the traversal visits both cells, or runs in the plane,
 * where it visits both too (traversal/kd_traverse.h). */
LT_DEVICE int lt_kd_goes_left(float lo, float hi, float plane, int planar_left) {
  return lo < plane || (lo == plane && hi == plane && planar_left);
}
LT_DEVICE int lt_kd_goes_right(float lo, float hi, float plane, int planar_left) {
  return hi > plane || (lo == plane && hi == plane && !planar_left);
}

/* The best binned SAH split of a cell: axis and plane, or axis -1 when the first failed split
 * (cost above LT_KD_FAIL_RATIO of the leaf's) makes the cell a leaf. A triangle's box, cut to
 * the cell, adds a start event to the bin of its low end and an end event to the bin of its
 * high end; the plane between bins i - 1 and i has on its left the boxes that start below it,
 * on its right those that end above it. A large cell prices a regular sample of its references
 * (lt_bin_step, as the BVH's tasks do); the partition after it is exact. */
typedef struct lt_kd_split {
  int axis;
  float plane, cost;
  int planar_left; /* triangles lying in the plane go left (else right) */
} lt_kd_split;

/* Sorts x[0, n) ascending (heapsort: no recursion, no scratch). */
LT_DEVICE void lt_kd_sort(float *x, int n) {
  for (int start = n / 2 - 1, end = n; end > 1;) {
    int root;
    if (start >= 0) {
      root = start--;
    } else {
      float t = x[0];
      x[0] = x[--end], x[end] = t;
      root = 0;
    }
    for (int child; (child = 2 * root + 1) < end; root = child) {
      if (child + 1 < end && x[child + 1] > x[child]) child++;
      if (!(x[child] > x[root])) break;
      float t = x[root];
      x[root] = x[child], x[child] = t;
    }
  }
}

/* The SAH cost of a plane with `left` and `right` references. */
LT_DEVICE float lt_kd_price(const lt_kd_build *b, const lt_box *cell, float area, int k, float plane, float left,
                            float right) {
  lt_box lbox = *cell, rbox = *cell;
  lbox.hi[k] = plane, rbox.lo[k] = plane;
  float cost = b->traversal_cost +
               b->intersection_cost * (lt_box_area(&lbox) * left + lt_box_area(&rbox) * right) / area;
  /* The bonus for cutting off empty space, when the empty side is at least a bin wide: the
   * sweep would otherwise shave thin empty slices off a cell level after level, each one a
   * level of the depth limit spent on nothing. */
  float empty_extent = left == 0.0f ? plane - cell->lo[k] : cell->hi[k] - plane;
  int bonus = (left == 0.0f || right == 0.0f) && empty_extent * (float)b->bins >= cell->hi[k] - cell->lo[k];
  return bonus ? cost * LT_KD_EMPTY_BONUS : cost;
}

/* The exact sweep (Wald and Havran 2006, per cell): every end of a reference's box inside the
 * cell is a candidate plane; with both ends sorted per axis, one pass prices them all (left:
 * the boxes that start below the plane, right: those that end above it). */
LT_DEVICE lt_kd_split lt_kd_sweep_split(const lt_kd_build *b, lt_i32 begin, lt_i32 n, const lt_box *cell) {
  float lo[LT_KD_SWEEP_MAX], hi[LT_KD_SWEEP_MAX], flat[LT_KD_SWEEP_MAX];
  lt_kd_split best;
  best.axis = -1, best.plane = 0.0f, best.cost = INFINITY, best.planar_left = 1;
  float area = lt_box_area(cell);
  int m = 0;
  for (int k = 0; k < 3 && area > 0.0f; k++) {
    if (!(cell->hi[k] > cell->lo[k])) continue;
    m = 0;
    int flats = 0;
    for (lt_i32 i = 0; i < n; i++) {
      lt_box box = lt_kd_ref_box(b, b->refs[begin + i], cell);
      if (!(box.lo[0] <= box.hi[0])) continue;
      lo[m] = box.lo[k] > cell->lo[k] ? box.lo[k] : cell->lo[k];
      hi[m] = box.hi[k] < cell->hi[k] ? box.hi[k] : cell->hi[k];
      if (box.lo[k] == box.hi[k]) flat[flats++] = box.lo[k];
      m++;
    }
    lt_kd_sort(lo, m), lt_kd_sort(hi, m), lt_kd_sort(flat, flats);
    lt_kd_count(b, LT_KD_STAT_SORT_OPS, (lt_u32)m);
    for (int i = 0, j = 0, f = 0; i < m || j < m;) {
      float plane = i < m ? lo[i] : INFINITY;
      if (j < m && hi[j] < plane) plane = hi[j];
      int ends = j, in_plane = 0;
      while (ends < m && hi[ends] <= plane) ends++;
      while (f < flats && flat[f] < plane) f++;
      while (f + in_plane < flats && flat[f + in_plane] == plane) in_plane++;
      if (plane > cell->lo[k] && plane < cell->hi[k]) {
        /* Triangles lying in the plane on the cheaper side. */
        float left = (float)(i + in_plane), right = (float)(m - ends);
        float cost = lt_kd_price(b, cell, area, k, plane, left, right);
        if (cost < best.cost) best.axis = k, best.plane = plane, best.cost = cost, best.planar_left = 1;
        cost = lt_kd_price(b, cell, area, k, plane, left - (float)in_plane, right + (float)in_plane);
        if (cost < best.cost) best.axis = k, best.plane = plane, best.cost = cost, best.planar_left = 0;
      }
      while (i < m && lo[i] <= plane) i++;
      j = ends;
    }
  }
  if (!(best.cost <= LT_KD_FAIL_RATIO * b->intersection_cost * (float)m)) best.axis = -1;
  return best;
}

LT_DEVICE lt_kd_split lt_kd_best_split(const lt_kd_build *b, lt_i32 begin, lt_i32 n, const lt_box *cell) {
  if (b->sweep && n <= LT_KD_SWEEP_MAX) return lt_kd_sweep_split(b, begin, n, cell);
  lt_i32 starts[3][LT_MAX_BINS], ends[3][LT_MAX_BINS];
  for (int k = 0; k < 3; k++)
    for (int i = 0; i < b->bins; i++) starts[k][i] = ends[k][i] = 0;
  float scale[3];
  lt_bin_scale(cell, b->bins, scale);
  lt_i32 step = lt_bin_step(n), samples = 0;
  for (lt_i32 i = 0; i < n; i += step, samples++) {
    lt_box box = lt_kd_ref_box(b, b->refs[begin + i], cell);
    if (!(box.lo[0] <= box.hi[0])) continue; /* clipped away: in neither child */
    for (int k = 0; k < 3; k++) {
      float lo = box.lo[k] > cell->lo[k] ? box.lo[k] : cell->lo[k];
      float hi = box.hi[k] < cell->hi[k] ? box.hi[k] : cell->hi[k];
      starts[k][lt_bin_of(lo, cell->lo[k], scale[k], b->bins)]++;
      ends[k][lt_bin_of(hi, cell->lo[k], scale[k], b->bins)]++;
    }
  }
  lt_kd_count(b, LT_KD_STAT_SORT_OPS, (lt_u32)samples);

  lt_kd_split best;
  best.axis = -1, best.plane = 0.0f, best.cost = INFINITY, best.planar_left = 1;
  float area = lt_box_area(cell);
  float weight = (float)n / (float)samples; /* a sample's counts stand for the whole cell's */
  for (int k = 0; k < 3 && area > 0.0f; k++) {
    if (scale[k] == 0.0f) continue;
    float extent = cell->hi[k] - cell->lo[k];
    lt_i32 left = 0, right = samples;
    for (int i = 1; i < b->bins; i++) {
      left += starts[k][i - 1], right -= ends[k][i - 1];
      float plane = cell->lo[k] + extent * (float)i / (float)b->bins;
      if (!(plane > cell->lo[k] && plane < cell->hi[k])) continue;
      float cost = lt_kd_price(b, cell, area, k, plane, weight * (float)left, weight * (float)right);
      if (cost < best.cost) best.axis = k, best.plane = plane, best.cost = cost;
    }
  }
  if (!(best.cost <= LT_KD_FAIL_RATIO * b->intersection_cost * (float)n)) best.axis = -1;
  return best;
}

/* Takes a node for the cell that link `address` leads to, noting its parent and cell; -1 (the
 * heap error set) when the node heap is full. */
LT_DEVICE lt_i32 lt_kd_new_node(const lt_kd_build *b, lt_i32 address, const lt_box *cell) {
  lt_i32 node = lt_heap_alloc(&b->node_heap, 1);
  if (node < 0) {
    lt_pool_fail(&b->pool, LT_POOL_ERROR_HEAP);
    return -1;
  }
  b->parents[node] = address >> 1;
  for (int k = 0; k < 3; k++) b->cells[6 * (long)node + k] = cell->lo[k], b->cells[6 * (long)node + 3 + k] = cell->hi[k];
  return node;
}

/* Makes a leaf node over refs[first, first + count) for the cell behind link `address` and
 * returns its index, or -1 (the heap error set) when the node heap is full. */
LT_DEVICE lt_i32 lt_kd_make_leaf(const lt_kd_build *b, lt_i32 address, const lt_box *cell, lt_i32 first, lt_i32 count,
                                 lt_i32 depth) {
  lt_i32 node = lt_kd_new_node(b, address, cell);
  if (node < 0) return -1;
  lt_kd_write_leaf(&b->nodes[node], first, count);
  lt_kd_count(b, LT_KD_STAT_LEAVES, 1);
  lt_kd_count(b, LT_KD_STAT_LEAF_REFS, (lt_u32)count);
  lt_atomic_max_i32(&b->counters[lt_group_id() * LT_KD_STAT_COUNT + LT_KD_STAT_DEPTH], depth);
  return node;
}

/* Whether a cell of `count` references at `depth` is a leaf before any split is priced. */
LT_DEVICE int lt_kd_small(const lt_kd_build *b, lt_i32 count, lt_i32 depth) {
  return count <= b->max_leaf || depth >= b->max_depth;
}

/* The link to child `side` of `node`: empty, a leaf made now, or a task inserted (and published
 * once the link to it is in place). */
LT_DEVICE void lt_kd_spawn(const lt_kd_build *b, lt_i32 node, int side, lt_i32 first, lt_i32 count, lt_i32 depth,
                           const lt_box *cell) {
  lt_i32 address = node * 2 + side;
  if (count == 0) {
    lt_kd_set_link(b->nodes, address, LT_KD_LINK_EMPTY);
    return;
  }
  if (lt_kd_small(b, count, depth)) {
    lt_i32 leaf = lt_kd_make_leaf(b, address, cell, first, count, depth);
    lt_kd_set_link(b->nodes, address, leaf < 0 ? LT_KD_LINK_EMPTY : leaf);
    return;
  }
  lt_i32 slot = lt_pool_insert(&b->pool, b->task_kind, address, first, first + count, depth, 1);
  if (slot < 0) {
    lt_kd_set_link(b->nodes, address, LT_KD_LINK_EMPTY);
    return;
  }
  LT_GLOBAL lt_task *task = &b->pool.tasks[slot];
  for (int k = 0; k < 3; k++)
    task->work[LT_KD_W_BOUNDS + k] = lt_float_as_int(cell->lo[k]),
                             task->work[LT_KD_W_BOUNDS + 3 + k] = lt_float_as_int(cell->hi[k]);
  lt_kd_set_link(b->nodes, address, lt_kd_unbuilt_link(slot));
  lt_pool_publish(&b->pool, slot);
}

/* Splits the task's cell, or makes it a leaf, and links the result into its parent. */
LT_DEVICE void lt_kd_build_node(const lt_kd_build *b, lt_i32 slot) {
  LT_GLOBAL lt_task *task = &b->pool.tasks[slot];
  lt_i32 begin = task->begin, n = task->end - task->begin, depth = task->depth;
  lt_i32 address = lt_atomic_load_i32(&task->node);
  lt_box cell;
  for (int k = 0; k < 3; k++)
    cell.lo[k] = lt_int_as_float(task->work[LT_KD_W_BOUNDS + k]),
    cell.hi[k] = lt_int_as_float(task->work[LT_KD_W_BOUNDS + 3 + k]);

  lt_kd_split s;
  s.axis = -1;
  if (!lt_kd_small(b, n, depth)) s = lt_kd_best_split(b, begin, n, &cell);
  if (s.axis < 0) {
    lt_i32 leaf = lt_kd_make_leaf(b, address, &cell, begin, n, depth);
    if (leaf >= 0) lt_kd_publish_link(b->nodes, address, leaf);
    lt_pool_retire(&b->pool, slot);
    return;
  }

  /* The exact partition: count both sides, take both arrays at once, write them in order. */
  int axis = s.axis, planar_left = s.planar_left;
  float plane = s.plane;
  lt_i32 left = 0, right = 0;
  for (lt_i32 i = begin; i < begin + n; i++) {
    lt_box box = lt_kd_ref_box(b, b->refs[i], &cell);
    left += lt_kd_goes_left(box.lo[axis], box.hi[axis], plane, planar_left);
    right += lt_kd_goes_right(box.lo[axis], box.hi[axis], plane, planar_left);
  }
  lt_i32 node = lt_kd_new_node(b, address, &cell);
  lt_i32 first_right = node < 0 ? -1 : right == 0 ? 0 : lt_heap_alloc(&b->ref_heap, right);
  if (node < 0 || first_right < 0) {
    lt_pool_fail(&b->pool, LT_POOL_ERROR_HEAP);
    return;
  }
  /* The left side stays in the cell's own array, compacted in place (it never overtakes the
   * read position); the right side goes to the new one. */
  lt_i32 l = begin, r = first_right;
  for (lt_i32 i = begin; i < begin + n; i++) {
    lt_i32 prim = b->refs[i];
    lt_box box = lt_kd_ref_box(b, prim, &cell);
    if (lt_kd_goes_right(box.lo[axis], box.hi[axis], plane, planar_left)) b->refs[r++] = prim;
    if (lt_kd_goes_left(box.lo[axis], box.hi[axis], plane, planar_left)) b->refs[l++] = prim;
  }
  lt_kd_count(b, LT_KD_STAT_SORT_OPS, (lt_u32)n);

  lt_kd_write_inner(&b->nodes[node], axis, plane, LT_KD_LINK_EMPTY, LT_KD_LINK_EMPTY);
  lt_box lcell = cell, rcell = cell;
  lcell.hi[axis] = plane, rcell.lo[axis] = plane;
  lt_kd_spawn(b, node, 0, begin, left, depth + 1, &lcell);
  lt_kd_spawn(b, node, 1, first_right, right, depth + 1, &rcell);
  lt_kd_publish_link(b->nodes, address, node);
  lt_pool_retire(&b->pool, slot);
}

/* The pool's hooks: a task has one chunk, whose work the end of its phase does on work-item 0
 * (a chunk must never retire its own task). */
LT_DEVICE void lt_kd_chunk(const lt_kd_build *b, lt_i32 slot, lt_i32 chunk, int lid, int lsize) {
  (void)b, (void)slot, (void)chunk, (void)lid, (void)lsize;
}
LT_DEVICE void lt_kd_end_phase(const lt_kd_build *b, lt_i32 slot) { lt_kd_build_node(b, slot); }

/* The tree's start: node 0 is the super-root, whose link 0 is the root (a task, or a leaf when
 * the scene is small) over references 0 .. count - 1. Run once, by one work-item, before the
 * first launch. */
LT_DEVICE void lt_kd_setup(const lt_kd_build *b, lt_i32 count, const lt_box *bounds) {
  lt_i32 root = lt_kd_new_node(b, -2, bounds);
  lt_i32 first = root < 0 ? -1 : lt_heap_alloc(&b->ref_heap, count);
  if (root < 0 || first < 0) {
    lt_pool_fail(&b->pool, LT_POOL_ERROR_HEAP);
    return;
  }
  for (lt_i32 i = 0; i < count; i++) b->refs[first + i] = i;
  lt_kd_write_inner(&b->nodes[root], 0, 0.0f, LT_KD_LINK_EMPTY, LT_KD_LINK_EMPTY);
  lt_kd_spawn(b, root, 0, first, count, 0, bounds);
}

#endif
