/* BVH node subdivision as task-pool tasks: the on-demand paper (Vinkler et al. 2016), section
 * 3.4. A task subdivides the node behind one child link: binned SAH split (chunked, bins merged
 * in a global slab), stable partition (count, scatter), bounding boxes when SAH
 * finds no split and the object median is used; then it writes the new node, inserts tasks for
 * its children and links the node into its parent. Nodes small enough for one chunk do all of
 * that in one go. The same code makes full, requested and speculative builds. */
#ifndef LT_BVH_TASK_H
#define LT_BVH_TASK_H

#include "builders/bvh_morton.h"
#include "builders/sah_bins.h"
#include "device/heap.h"
#include "device/pool.h"
#include "device/bvh_node.h"

#define LT_BVH_CHUNK 2048  /* primitives per work chunk */
/* A node of up to LT_BVH_ONE_GO primitives is split in one go by one work-group. On the native
 * backend a group is one thread and there are as many other nodes as groups, so the pool's
 * chunked phases below 16384 cost more in merges and hand-offs than they share; OpenCL keeps
 * one chunk. */
#define LT_BVH_ONE_GO_NATIVE 16384
#ifdef __OPENCL_VERSION__
#define LT_BVH_ONE_GO LT_BVH_CHUNK
#else
#define LT_BVH_ONE_GO LT_BVH_ONE_GO_NATIVE
#endif
#define LT_BVH_SLAB_SIZE LT_BINS_SIZE

/* Phases. */
#define LT_BVH_SMALL 0   /* one chunk does everything */
#define LT_BVH_INIT 1    /* take a bin slab */
#define LT_BVH_BIN 2     /* chunks bin into the slab */
#define LT_BVH_COUNT 3   /* chunks count their left-hand primitives */
#define LT_BVH_SCATTER 4 /* chunks write both sides in order */
#define LT_BVH_BOXES 5   /* object median: chunks bound both halves and move them over */

/* Task data (lt_task.work). */
#define W_BOUNDS 0  /* 6 floats: node bounds, which are also its bin grid */
#define W_SLAB 12
#define W_SPLIT 13  /* axis * 64 + bin, or -1 for the object median */
#define W_LEFT 14   /* primitives going left */

/* Per-work-group counters of the build and its traversal (besides the pool's), one list:
 * X(ID, STAT) with STAT the statistic the host adds it to (LT_STAT_NONE: kept apart). */
#define LT_BVH_STAT_LIST(X)                          \
  X(LT_BVH_STAT_LEAVES, LT_STAT_NONE) /* leaves made, counted into nodes_built */ \
  X(LT_BVH_STAT_SORT_OPS, LT_STAT_SORT_OPS) /* primitives binned or partitioned */ \
  X(LT_BVH_STAT_STEPS, LT_STAT_TRAVERSAL_STEPS) /* node visits */ \
  X(LT_BVH_STAT_TESTS, LT_STAT_INTERSECTIONS) /* ray-triangle tests */ \
  X(LT_BVH_STAT_MORTON, LT_STAT_MORTON_NODES) /* nodes split by Morton code */

enum {
#define LT_BVH_STAT_ENUM(id, stat) id,
  LT_BVH_STAT_LIST(LT_BVH_STAT_ENUM)
#undef LT_BVH_STAT_ENUM
      LT_BVH_STAT_COUNT
};

typedef struct lt_bvh_build {
  lt_pool pool;
  LT_GLOBAL const float *verts;  /* 9 per triangle, in scene order (the scene's own array) */
  LT_GLOBAL const lt_v4 *prim_boxes; /* 2 per triangle: lo, hi (lanes x y z; computed once) */
  LT_GLOBAL lt_i32 *side;        /* per position: its bins packed (BIN to COUNT, where every
                                  * primitive is binned), then 0 left or 1 right (to SCATTER) */
  LT_GLOBAL lt_i32 *index;       /* primitive references, permuted into leaf order */
  LT_GLOBAL lt_i32 *scratch;     /* the other half of the ping-pong (lt_bvh_refs) */
  LT_GLOBAL lt_i32 *chunk_left;  /* at each chunk's first position: its left-hand count, then
                                  * the left-hand count of the chunks before it */
  LT_GLOBAL lt_bvh_node *nodes;
  LT_GLOBAL lt_i32 *slabs;       /* slab_count bin slabs */
  LT_GLOBAL lt_i32 *slab_used;
  LT_GLOBAL lt_u32 *counters;    /* LT_BVH_STAT_COUNT per work-group */
  LT_GLOBAL const lt_u32 *codes; /* Morton top: per position, the sorted Morton codes */
  LT_GLOBAL const lt_v4 *block_boxes; /* Morton top: the pyramid of block boxes (bvh_morton.h) */
  lt_heap node_heap;             /* hands out nodes */
  lt_i32 task_kind;              /* the number the running workload gave these tasks */
  lt_i32 slab_count, max_leaf, bins;
  lt_i32 morton_above; /* a node of more primitives is split by Morton code (none: the count) */
  lt_i32 morton_blocks; /* boxes at the pyramid's bottom level */
  float traversal_cost, intersection_cost;
} lt_bvh_build;

/* The build's kernel arguments (device/kernel_args.h); V is its path in the view. */
#define LT_BVH_BUILD_ARGS(X, V)                        \
  LT_POOL_ARGS(X, V.pool)                              \
  X(BUF, float, V.verts, verts)                        \
  X(BUF, lt_v4, V.prim_boxes, prim_boxes)              \
  X(BUF, lt_i32, V.side, side)                         \
  X(BUF, lt_i32, V.index, index)                       \
  X(BUF, lt_i32, V.scratch, scratch)                   \
  X(BUF, lt_i32, V.chunk_left, chunk_left)             \
  X(BUF, lt_bvh_node, V.nodes, nodes)                  \
  X(BUF, lt_i32, V.slabs, slabs)                       \
  X(BUF, lt_i32, V.slab_used, slab_used)               \
  X(BUF, lt_u32, V.counters, counters)                 \
  X(BUF, lt_u32, V.codes, codes)                       \
  X(BUF, lt_v4, V.block_boxes, block_boxes)            \
  LT_HEAP_ARGS(X, V.node_heap, node_heap)              \
  X(VAL, lt_i32, V.task_kind, task_kind)               \
  X(VAL, lt_i32, V.slab_count, slab_count)             \
  X(VAL, lt_i32, V.max_leaf, max_leaf)                 \
  X(VAL, lt_i32, V.bins, bins)                         \
  X(VAL, lt_i32, V.morton_above, morton_above)         \
  X(VAL, lt_i32, V.morton_blocks, morton_blocks)       \
  X(VAL, float, V.traversal_cost, traversal_cost)      \
  X(VAL, float, V.intersection_cost, intersection_cost)

LT_DEVICE void lt_bvh_count(const lt_bvh_build *b, int stat, lt_u32 n) {
  lt_atomic_add_u32(&b->counters[lt_group_id() * LT_BVH_STAT_COUNT + stat], n);
}

LT_DEVICE void lt_store_box(LT_GLOBAL lt_i32 *w, const lt_box *box) {
  for (int k = 0; k < 3; k++) w[k] = lt_float_as_int(box->lo[k]), w[3 + k] = lt_float_as_int(box->hi[k]);
}
LT_DEVICE lt_box lt_load_box(LT_GLOBAL const lt_i32 *w) {
  lt_box box;
  for (int k = 0; k < 3; k++) box.lo[k] = lt_int_as_float(w[k]), box.hi[k] = lt_int_as_float(w[3 + k]);
  return box;
}

/* Partitions ping-pong: the references of a node at an even depth lie in index, at an odd
 * depth in scratch, so that a partition writes its children's straight into the other array
 * and nothing is copied back. A leaf at an odd depth moves its own few into index, where
 * traversal reads them. */
LT_DEVICE LT_GLOBAL lt_i32 *lt_bvh_refs(const lt_bvh_build *b, lt_i32 depth) {
  return (depth & 1) ? b->scratch : b->index;
}
LT_DEVICE void lt_bvh_leaf_refs(const lt_bvh_build *b, lt_i32 depth, lt_i32 begin, lt_i32 end) {
  if (depth & 1)
    for (lt_i32 i = begin; i < end; i++) b->index[i] = b->scratch[i];
}

/* Whether the node over [begin, end) at `depth` is one of the Morton top's: more than
 * morton_above primitives whose sorted codes differ (a node whose primitives all share a code is
 * left to the SAH), clear of the depth bound. Only Morton nodes lie above one. */
LT_DEVICE int lt_bvh_is_morton(const lt_bvh_build *b, lt_i32 begin, lt_i32 end, lt_i32 depth) {
  return end - begin > b->morton_above && depth < LT_BVH_MAX_DEPTH - 2 && b->codes[begin] != b->codes[end - 1];
}

/* Inserts the task that will build child `side` of node `node` over [begin, end). */
LT_DEVICE void lt_bvh_spawn(const lt_bvh_build *b, lt_i32 node, int side, lt_i32 begin, lt_i32 end, lt_i32 depth,
                            const lt_box *bounds) {
  LT_GLOBAL lt_bvh_node *n = &b->nodes[node];
  lt_i32 count = end - begin;
  if (count == 1) {
    lt_bvh_leaf_refs(b, depth, begin, end);
    lt_bvh_set_child(n, side, bounds, begin, 1);
    lt_bvh_count(b, LT_BVH_STAT_LEAVES, 1);
    return;
  }
  lt_i32 slot = lt_pool_insert(&b->pool, b->task_kind, node * 2 + side, begin, end, depth, 1); /* SMALL or INIT: one chunk */
  if (slot < 0) {
    lt_bvh_set_child(n, side, bounds, LT_BVH_LINK_EMPTY, 0);
    return;
  }
  LT_GLOBAL lt_task *task = &b->pool.tasks[slot];
  task->phase = count <= LT_BVH_ONE_GO || lt_bvh_is_morton(b, begin, end, depth) ? LT_BVH_SMALL : LT_BVH_INIT;
  lt_store_box(task->work + W_BOUNDS, bounds);
  lt_bvh_set_child(n, side, bounds, lt_bvh_unbuilt_link(slot), 0);
  lt_pool_publish(&b->pool, slot);
}

/* The task's node is split at left_end: make the node, its children, and link it in. */
LT_DEVICE void lt_bvh_finish_split(const lt_bvh_build *b, lt_i32 slot, lt_i32 left_end, const lt_box *left,
                                   const lt_box *right) {
  LT_GLOBAL lt_task *task = &b->pool.tasks[slot];
  lt_i32 node = lt_heap_alloc(&b->node_heap, 1);
  if (node < 0) {
    lt_pool_fail(&b->pool, LT_POOL_ERROR_HEAP);
    return;
  }
  lt_bvh_spawn(b, node, 0, task->begin, left_end, task->depth + 1, left);
  lt_bvh_spawn(b, node, 1, left_end, task->end, task->depth + 1, right);
  lt_bvh_publish_link(b->nodes, lt_atomic_load_i32(&task->node), node, 0);
  lt_pool_retire(&b->pool, slot);
}

LT_DEVICE void lt_bvh_finish_leaf(const lt_bvh_build *b, lt_i32 slot) {
  LT_GLOBAL lt_task *task = &b->pool.tasks[slot];
  lt_bvh_count(b, LT_BVH_STAT_LEAVES, 1);
  lt_bvh_leaf_refs(b, task->depth, task->begin, task->end);
  lt_bvh_publish_link(b->nodes, lt_atomic_load_i32(&task->node), task->begin, task->end - task->begin);
  lt_pool_retire(&b->pool, slot);
}

/* How many positions ahead the passes over a node ask for a primitive's box: they gather
 * boxes through the index, and most of a pass's time was waiting for them. */
#define LT_PREFETCH 16

/* With the Morton top, a node of at most LT_BVH_FEW primitives below it is priced on
 * LT_BVH_FEW_BINS bins per axis instead of b->bins: most nodes a frame prices there are that
 * small, and clearing and pricing all bins, a fixed cost per node, weighed as much as binning
 * their primitives. The tree below the top changes; full, requested and speculative builds
 * still make the same one. */
#define LT_BVH_FEW 64
#define LT_BVH_FEW_BINS 8
LT_DEVICE int lt_bvh_node_bins(const lt_bvh_build *b, lt_i32 n) {
  return b->morton_blocks > 0 && n <= LT_BVH_FEW && LT_BVH_FEW_BINS < b->bins ? LT_BVH_FEW_BINS : b->bins;
}

/* Bins the primitives at positions lo, lo + step, ... below hi into private bins (nbins per
 * axis) over the node's box `grid`. When every primitive is binned (step 1 of the node), each
 * position's packed bins go to side[], so that the partition needs no box again. */
LT_DEVICE void lt_bvh_bin_range(const lt_bvh_build *b, LT_GLOBAL const lt_i32 *refs, lt_i32 lo, lt_i32 hi,
                                lt_i32 step, int record, const lt_box *grid, int nbins, lt_bins *bins) {
  lt_v4 glo = lt_box_lo4(grid), scale = lt_bin_scale4(grid, nbins);
  for (lt_i32 i = lo; i < hi; i += step) {
    if (i + LT_PREFETCH * step < hi) lt_prefetch(b->prim_boxes + 2 * (long)refs[i + LT_PREFETCH * step]);
    LT_GLOBAL const lt_v4 *box = b->prim_boxes + 2 * (long)refs[i];
    int packed = lt_bins_add(bins, glo, scale, nbins, box[0], box[1]);
    if (record) b->side[i] = packed;
  }
}

/* Notes in side[] which side of split (axis * 64 + bin) each primitive of refs[lo, hi) goes
 * to, 0 left or 1 right, and returns how many go left. With `binned` the primitives' packed
 * bins are already in side[] (every primitive was binned) and only they are read; otherwise
 * the boxes are gathered, each side's box grown into box[0] and box[1], and a primitive's bin
 * is past `bin` exactly when (c - lo) * scale >= bin + 1 on the axis (truncation and the
 * clamp change nothing there): one vector compare against bin + 1 on the axis, infinity on
 * the others. */
LT_DEVICE lt_i32 lt_bvh_sides_of(const lt_bvh_build *b, LT_GLOBAL const lt_i32 *refs, lt_i32 lo, lt_i32 hi,
                                 lt_i32 split, const lt_box *grid, int binned, lt_box box[2]) {
  int axis = split >> 6, bin = split & 63;
  lt_i32 left = 0;
  if (binned) {
    for (lt_i32 i = lo; i < hi; i++) {
      int side = lt_packed_bin(b->side[i], axis) > bin;
      b->side[i] = side;
      left += 1 - side;
    }
    return left;
  }
  lt_v4 glo = lt_box_lo4(grid), scale = lt_bin_scale4(grid, b->bins);
  lt_v4 inf = lt_v4_splat(INFINITY), ninf = lt_v4_splat(-INFINITY);
  lt_v4 edge = lt_v4_make(axis == 0 ? bin + 1.0f : INFINITY, axis == 1 ? bin + 1.0f : INFINITY,
                          axis == 2 ? bin + 1.0f : INFINITY, INFINITY);
  lt_v4 llo = inf, lhi = ninf, rlo = inf, rhi = ninf;
  for (lt_i32 i = lo; i < hi; i++) {
    if (i + LT_PREFETCH < hi) lt_prefetch(b->prim_boxes + 2 * (long)refs[i + LT_PREFETCH]);
    LT_GLOBAL const lt_v4 *p = b->prim_boxes + 2 * (long)refs[i];
    lt_v4 plo = p[0], phi = p[1];
    int side = lt_v4_any_ge(((plo + phi) * 0.5f - glo) * scale, edge);
    b->side[i] = side;
    if (side) {
      rlo = lt_v4_min(plo, rlo), rhi = lt_v4_max(phi, rhi);
    } else {
      llo = lt_v4_min(plo, llo), lhi = lt_v4_max(phi, lhi);
      left++;
    }
  }
  box[0] = lt_box_of4(llo, lhi), box[1] = lt_box_of4(rlo, rhi);
  return left;
}

/* Writes src[lo, hi) stably into dst, left-hand references from position `left` on and the
 * others from `right` on. A position's side is side[i] (0 or 1) when `split` is negative,
 * else its packed bins' bin on the split's axis (axis * 64 + bin) past the split's bin. */
LT_DEVICE void lt_bvh_scatter(const lt_bvh_build *b, LT_GLOBAL const lt_i32 *src, LT_GLOBAL lt_i32 *dst, lt_i32 lo,
                              lt_i32 hi, lt_i32 left, lt_i32 right, lt_i32 split) {
  int axis = split >> 6, bin = split & 63;
  for (lt_i32 i = lo; i < hi; i++) {
    int side = split < 0 ? b->side[i] : lt_packed_bin(b->side[i], axis) > bin;
    if (side) dst[right++] = src[i];
    else dst[left++] = src[i];
  }
}

/* Bounds of refs[lo, hi). */
LT_DEVICE lt_box lt_bvh_bound_range(const lt_bvh_build *b, LT_GLOBAL const lt_i32 *refs, lt_i32 lo, lt_i32 hi) {
  lt_v4 blo = lt_v4_splat(INFINITY), bhi = lt_v4_splat(-INFINITY);
  for (lt_i32 i = lo; i < hi; i++) {
    LT_GLOBAL const lt_v4 *p = b->prim_boxes + 2 * (long)refs[i];
    blo = lt_v4_min(p[0], blo), bhi = lt_v4_max(p[1], bhi);
  }
  return lt_box_of4(blo, bhi);
}

/* Grows box `i` of a slab's summary (order-preserving ints) with atomics. */
LT_DEVICE void lt_slab_grow_box(LT_GLOBAL lt_i32 *slab, int i, const lt_box *box) {
  for (int k = 0; k < 3; k++) {
    lt_atomic_min_i32(&slab[6 * i + k], lt_ordered(box->lo[k]));
    lt_atomic_max_i32(&slab[6 * i + 3 + k], lt_ordered(box->hi[k]));
  }
}

/* Splits a node in one go on work-item 0 (a node of at most LT_BVH_ONE_GO primitives, or a
 * larger one that found no free bin slab): bins it (a sample of a large one), prices the
 * splits, notes each primitive's side while bounding both sides, and partitions in order
 * into the other array of the ping-pong. Returns 0 when the node is a leaf; else the split,
 * with exact boxes and counts, and its middle in *mid. A node of the Morton top
 * (lt_bvh_is_morton) splits its sorted range by code instead and moves nothing: the
 * host wrote the sorted order into both arrays of the ping-pong, and only Morton nodes lie
 * above, so both still hold it wherever the SAH below takes over. */
LT_DEVICE int lt_bvh_split_small(const lt_bvh_build *b, lt_i32 begin, lt_i32 end, lt_i32 depth, const lt_box *bounds,
                                 lt_split *s, lt_i32 *mid) {
  lt_i32 n = end - begin;
  if (lt_bvh_is_morton(b, begin, end, depth)) {
    *mid = lt_morton_split(b->codes, begin, end - 1);
    s->left = lt_morton_bounds(b->prim_boxes, b->index, b->block_boxes, b->morton_blocks, begin, *mid);
    s->right = lt_morton_bounds(b->prim_boxes, b->index, b->block_boxes, b->morton_blocks, *mid, end);
    lt_bvh_count(b, LT_BVH_STAT_MORTON, 1);
    return 1;
  }
  LT_GLOBAL lt_i32 *src = lt_bvh_refs(b, depth), *dst = lt_bvh_refs(b, depth + 1);
  lt_bins bins;
  int nbins = lt_bvh_node_bins(b, n);
  lt_bins_clear(&bins);
  lt_i32 step = lt_bin_step(n);
  int sampled = step > 1;
  lt_bvh_bin_range(b, src, begin, end, step, !sampled, bounds, nbins, &bins);
  *s = lt_sah_best_split(&bins, bounds, b->traversal_cost, b->intersection_cost);
  lt_bvh_count(b, LT_BVH_STAT_SORT_OPS, (lt_u32)lt_bin_sample_count(n));
  if (lt_sah_make_leaf(n, depth, s, b->max_leaf, b->intersection_cost, LT_BVH_MAX_DEPTH)) return 0;

  /* Object median when SAH found no split: the halves keep their order. */
  if (s->axis < 0) {
    *mid = begin + n / 2;
    s->left = lt_bvh_bound_range(b, src, begin, *mid);
    s->right = lt_bvh_bound_range(b, src, *mid, end);
    for (lt_i32 i = begin; i < end; i++) dst[i] = src[i];
    return 1;
  }

  /* A stable partition. When every primitive was binned, the bins gave the boxes and the
   * left-hand count, and each primitive's bin is in side[]; otherwise a pass over the boxes
   * notes the sides and bounds both first. */
  lt_i32 split = s->axis * 64 + s->bin;
  if (sampled) {
    lt_box box[2];
    s->left_count = lt_bvh_sides_of(b, src, begin, end, split, bounds, 0, box);
    s->left = box[0], s->right = box[1];
  }
  lt_bvh_scatter(b, src, dst, begin, end, begin, begin + s->left_count, sampled ? -1 : split);
  lt_bvh_count(b, LT_BVH_STAT_SORT_OPS, (lt_u32)n);
  *mid = begin + s->left_count;
  return 1;
}

/* A node still to be made inside a subtree task: its link's address, range, depth, boxes. */
typedef struct lt_bvh_pending {
  lt_i32 address, begin, end, depth;
  lt_box bounds;
} lt_bvh_pending;

/* A full build makes the whole subtree of a small node in its task, depth first from a
 * private stack, with no pool traffic below LT_BVH_CHUNK primitives. Each node links into its
 * parent as it is made (a full build traces nothing meanwhile); the subtree's own link, into
 * the node above the task, comes last. The nodes are those lt_bvh_split_small makes one task
 * at a time, so the tree is the same in every mode. */
LT_DEVICE void lt_bvh_subtree(const lt_bvh_build *b, lt_i32 slot) {
  LT_GLOBAL lt_task *task = &b->pool.tasks[slot];
  lt_bvh_pending stack[LT_BVH_MAX_DEPTH + 1], cur;
  cur.address = lt_atomic_load_i32(&task->node), cur.begin = task->begin, cur.end = task->end;
  cur.depth = task->depth;
  cur.bounds = lt_load_box(task->work + W_BOUNDS);
  lt_i32 top = 0, root_link = -1, root_count = 0, root_address = cur.address;
  for (;;) {
    lt_split s;
    lt_i32 mid = cur.end, link, count;
    if (lt_bvh_split_small(b, cur.begin, cur.end, cur.depth, &cur.bounds, &s, &mid)) {
      link = lt_heap_alloc(&b->node_heap, 1), count = 0;
      if (link < 0) {
        lt_pool_fail(&b->pool, LT_POOL_ERROR_HEAP);
        return;
      }
      LT_GLOBAL lt_bvh_node *node = &b->nodes[link];
      lt_bvh_set_child(node, 0, &s.left, LT_BVH_LINK_EMPTY, 0);
      lt_bvh_set_child(node, 1, &s.right, LT_BVH_LINK_EMPTY, 0);
      lt_bvh_pending right;
      right.address = link * 2 + 1, right.begin = mid, right.end = cur.end, right.depth = cur.depth + 1;
      right.bounds = s.right;
      stack[top++] = right;
    } else {
      link = cur.begin, count = cur.end - cur.begin;
      lt_bvh_leaf_refs(b, cur.depth, cur.begin, cur.end);
      lt_bvh_count(b, LT_BVH_STAT_LEAVES, 1);
    }
    if (cur.address == root_address) root_link = link, root_count = count;
    else lt_bvh_publish_link(b->nodes, cur.address, link, count);

    /* Down the left child of a new node, else the last right child left behind. */
    if (count == 0) {
      cur.address = link * 2, cur.end = mid, cur.depth++;
      cur.bounds = s.left;
    } else if (top > 0) {
      cur = stack[--top];
    } else {
      break;
    }
  }
  lt_bvh_publish_link(b->nodes, root_address, root_link, root_count);
  lt_pool_retire(&b->pool, slot);
}

/* A whole node in one chunk (work-item 0): split it and spawn its children's tasks, or in a
 * full build make the whole subtree of a small one. */
LT_DEVICE void lt_bvh_small(const lt_bvh_build *b, lt_i32 slot) {
  LT_GLOBAL lt_task *task = &b->pool.tasks[slot];
  if (b->pool.mode == LT_POOL_FULL && task->end - task->begin <= LT_BVH_CHUNK) {
    lt_bvh_subtree(b, slot);
    return;
  }
  lt_box bounds = lt_load_box(task->work + W_BOUNDS);
  lt_split s;
  lt_i32 mid;
  if (lt_bvh_split_small(b, task->begin, task->end, task->depth, &bounds, &s, &mid))
    lt_bvh_finish_split(b, slot, mid, &s.left, &s.right);
  else
    lt_bvh_finish_leaf(b, slot);
}

/* Takes a free bin slab, or returns -1 when all are in use. */
LT_DEVICE lt_i32 lt_bvh_take_slab(const lt_bvh_build *b) {
  for (lt_i32 i = 0; i < b->slab_count; i++)
    if (lt_atomic_cas_i32(&b->slab_used[i], 0, 1) == 0) return i;
  return -1;
}

/* One chunk of the current phase. Work-items share BIN; the others run on item 0. */
LT_DEVICE void lt_bvh_chunk(const lt_bvh_build *b, lt_i32 slot, lt_i32 chunk, int lid, int lsize) {
  LT_GLOBAL lt_task *task = &b->pool.tasks[slot];
  lt_i32 begin = task->begin, end = task->end, phase = task->phase;
  lt_i32 lo = begin + chunk * LT_BVH_CHUNK, hi = lo + LT_BVH_CHUNK < end ? lo + LT_BVH_CHUNK : end;
  lt_box bounds = lt_load_box(task->work + W_BOUNDS);
  int sampled = lt_bin_step(end - begin) > 1;
  LT_GLOBAL lt_i32 *slab = b->slabs + (lt_i32)task->work[W_SLAB] * LT_BVH_SLAB_SIZE;
  LT_GLOBAL lt_i32 *src = lt_bvh_refs(b, task->depth), *dst = lt_bvh_refs(b, task->depth + 1);

  if (phase == LT_BVH_BIN) {
    /* This chunk's part of the sample: sample j is the primitive at begin + j * step. */
    lt_i32 step = lt_bin_step(end - begin), samples = lt_bin_sample_count(end - begin);
    lt_i32 j0 = chunk * LT_BVH_CHUNK, j1 = j0 + LT_BVH_CHUNK < samples ? j0 + LT_BVH_CHUNK : samples;
    lt_bins bins;
    lt_bins_clear(&bins);
    lt_bvh_bin_range(b, src, begin + (j0 + lid) * step, begin + j1 * step, lsize * step, !sampled, &bounds, b->bins,
                     &bins);
    lt_bins_merge_global(slab, &bins);
    return;
  }
  /* SMALL and INIT have one chunk, whose work lt_bvh_end_phase does: a chunk must never
   * retire its own task, because its finisher still counts the chunk done afterwards. */
  if (lid != 0 || phase == LT_BVH_SMALL || phase == LT_BVH_INIT) return;
  if (phase == LT_BVH_COUNT) {
    /* Each primitive's side and the left-hand count; when binning saw only a sample, both
     * sides' boxes too (otherwise the bins had them). */
    lt_box box[2];
    b->chunk_left[lo] = lt_bvh_sides_of(b, src, lo, hi, task->work[W_SPLIT], &bounds, !sampled, box);
    if (sampled)
      for (int side = 0; side < 2; side++) lt_slab_grow_box(slab, side, &box[side]);
  } else if (phase == LT_BVH_SCATTER) {
    /* This chunk's place: COUNT's end turned the chunks' left-hand counts into prefix sums. */
    lt_i32 before = b->chunk_left[lo];
    lt_bvh_scatter(b, src, dst, lo, hi, begin + before, begin + task->work[W_LEFT] + (lo - begin - before), -1);
  } else if (phase == LT_BVH_BOXES) {
    /* Both halves of the object median, merged into the slab's two boxes, and moved to the
     * other array as they are. */
    lt_i32 mid = begin + task->work[W_LEFT];
    lt_box box[2];
    box[0] = lt_bvh_bound_range(b, src, lo, hi < mid ? hi : mid);
    box[1] = lt_bvh_bound_range(b, src, lo > mid ? lo : mid, hi);
    for (lt_i32 i = lo; i < hi; i++) dst[i] = src[i];
    for (int side = 0; side < 2; side++) lt_slab_grow_box(slab, side, &box[side]);
  }
}

/* Reads box `i` of the slab's summary (stored by lt_bvh_end_phase or BOXES). */
LT_DEVICE lt_box lt_slab_box(LT_GLOBAL const lt_i32 *slab, int i) {
  lt_box box;
  for (int k = 0; k < 3; k++) box.lo[k] = lt_unordered(slab[6 * i + k]), box.hi[k] = lt_unordered(slab[6 * i + 3 + k]);
  return box;
}

LT_DEVICE void lt_slab_put_box(LT_GLOBAL lt_i32 *slab, int i, const lt_box *box) {
  for (int k = 0; k < 3; k++) slab[6 * i + k] = lt_ordered(box->lo[k]), slab[6 * i + 3 + k] = lt_ordered(box->hi[k]);
}

LT_DEVICE void lt_bvh_release_slab(const lt_bvh_build *b, LT_GLOBAL lt_task *task) {
  lt_fence();
  lt_atomic_store_i32(&b->slab_used[task->work[W_SLAB]], 0);
}

/* Called by the work-group that finished the last chunk of a phase (work-item 0). */
LT_DEVICE void lt_bvh_end_phase(const lt_bvh_build *b, lt_i32 slot) {
  LT_GLOBAL lt_task *task = &b->pool.tasks[slot];
  lt_i32 begin = task->begin, end = task->end, n = end - begin, phase = task->phase;
  lt_i32 chunks = (n + LT_BVH_CHUNK - 1) / LT_BVH_CHUNK;
  if (phase == LT_BVH_SMALL) {
    lt_bvh_small(b, slot);
    return;
  }

  /* A cleared slab for the bins; without one, the node is built here in one go. */
  if (phase == LT_BVH_INIT) {
    lt_i32 s = lt_bvh_take_slab(b);
    task->work[W_SLAB] = s;
    if (s < 0) {
      lt_bvh_small(b, slot);
      return;
    }
    lt_bins_clear_global(b->slabs + s * LT_BVH_SLAB_SIZE);
    lt_pool_next_phase(&b->pool, slot, LT_BVH_BIN, (lt_bin_sample_count(n) + LT_BVH_CHUNK - 1) / LT_BVH_CHUNK);
    return;
  }
  LT_GLOBAL lt_i32 *slab = b->slabs + task->work[W_SLAB] * LT_BVH_SLAB_SIZE;

  if (phase == LT_BVH_BIN) {
    /* Price the splits from the merged bins; keep the outcome in the slab. */
    lt_bins bins;
    lt_bins_from_global(&bins, slab);
    lt_box bounds = lt_load_box(task->work + W_BOUNDS);
    lt_split s = lt_sah_best_split(&bins, &bounds, b->traversal_cost, b->intersection_cost);
    lt_bvh_count(b, LT_BVH_STAT_SORT_OPS, (lt_u32)lt_bin_sample_count(n));
    if (lt_sah_make_leaf(n, task->depth, &s, b->max_leaf, b->intersection_cost, LT_BVH_MAX_DEPTH)) {
      lt_bvh_release_slab(b, task);
      lt_bvh_finish_leaf(b, slot);
      return;
    }

    /* Object median: the halves keep their order; the next phase bounds them. */
    if (s.axis < 0) {
      lt_box empty = lt_box_empty();
      for (int i = 0; i < 2; i++) lt_slab_put_box(slab, i, &empty);
      task->work[W_SPLIT] = -1;
      task->work[W_LEFT] = n / 2;
      lt_pool_next_phase(&b->pool, slot, LT_BVH_BOXES, chunks);
      return;
    }
    /* Both sides' boxes: from the bins when every primitive was binned, else grown by COUNT. */
    lt_box empty = lt_box_empty();
    int sampled = lt_bin_step(n) > 1;
    lt_slab_put_box(slab, 0, sampled ? &empty : &s.left), lt_slab_put_box(slab, 1, sampled ? &empty : &s.right);
    task->work[W_SPLIT] = s.axis * 64 + s.bin;
    lt_pool_next_phase(&b->pool, slot, LT_BVH_COUNT, chunks);
  } else if (phase == LT_BVH_COUNT) {
    /* The chunks' left-hand counts become prefix sums: where each chunk's left side starts. */
    lt_fence();
    lt_i32 left = 0;
    for (lt_i32 c = 0; c < chunks; c++) {
      lt_i32 l = b->chunk_left[begin + c * LT_BVH_CHUNK];
      b->chunk_left[begin + c * LT_BVH_CHUNK] = left;
      left += l;
    }
    task->work[W_LEFT] = left;
    lt_pool_next_phase(&b->pool, slot, LT_BVH_SCATTER, chunks);
  } else {
    /* SCATTER or BOXES done: the children's boxes are in the slab. */
    if (phase == LT_BVH_SCATTER) lt_bvh_count(b, LT_BVH_STAT_SORT_OPS, (lt_u32)n);
    lt_box left = lt_slab_box(slab, 0), right = lt_slab_box(slab, 1);
    lt_i32 left_end = begin + task->work[W_LEFT];
    lt_bvh_release_slab(b, task);
    lt_bvh_finish_split(b, slot, left_end, &left, &right);
  }
}

/* The tree's start, made by the same spawn as every other node: node 0 is a super-root whose
 * left child is the scene's root (a task, or a leaf when there is one triangle) and whose
 * right child is empty. Run once, by one work-item, before the first launch. */
LT_DEVICE void lt_bvh_setup(const lt_bvh_build *b, lt_i32 count, const lt_box *bounds) {
  lt_i32 root = lt_heap_alloc(&b->node_heap, 1);
  if (root < 0) {
    lt_pool_fail(&b->pool, LT_POOL_ERROR_HEAP);
    return;
  }
  lt_box empty = lt_box_empty();
  lt_bvh_set_child(&b->nodes[root], 1, &empty, LT_BVH_LINK_EMPTY, 0);
  lt_bvh_spawn(b, root, 0, 0, count, 0, bounds);
}

#endif
