/* Binned SAH split search shared by the host builder and the pool's node tasks (Wald 2007;
 * the on-demand paper, section 3.4: 32 bins, object median when SAH finds no split). A
 * node's bins divide its bounding box (Wald bins the centroids' bounds, which a node would
 * have to gather its primitives once more to know; on the generators the trees came out as
 * good, docs/notes/ondemand_bvh.md), and a primitive falls in the bin of its centroid.
 * Private bins hold float bits; the global slabs that chunks merge into hold the same floats
 * in an order-preserving int encoding, so that atomic integer min and max merge them and the
 * result does not depend on the merge order. */
#ifndef LT_SAH_BINS_H
#define LT_SAH_BINS_H

#include "device/box.h"

#define LT_MAX_BINS 32
/* A global slab's bin: count, box lo xyz, box hi xyz (private bins are lt_bins below). */
#define LT_BIN_STRIDE 7
#define LT_BINS_SIZE (3 * LT_MAX_BINS * LT_BIN_STRIDE)

/* A node of more primitives than LT_BIN_SAMPLES prices its splits on a regular sample: every
 * step-th primitive in the node's order, at most LT_BIN_SAMPLES of them. The split's position
 * is then a little less precise, but the partition, the children's boxes and their counts are
 * exact (computed over every primitive), and at the top levels, which every ray reaches, the
 * binning pass costs a bounded amount instead of a pass over the whole scene per level. */
#define LT_BIN_SAMPLES 16384
LT_DEVICE int lt_bin_step(int n) { return n > LT_BIN_SAMPLES ? (n + LT_BIN_SAMPLES - 1) / LT_BIN_SAMPLES : 1; }
LT_DEVICE int lt_bin_sample_count(int n) {
  int step = lt_bin_step(n);
  return (n + step - 1) / step;
}

/* Per-axis bin scale over a node's box (its grid); 0 on an axis where the box is flat. */
LT_DEVICE void lt_bin_scale(const lt_box *grid, int bins, float scale[3]) {
  for (int k = 0; k < 3; k++) {
    float extent = grid->hi[k] - grid->lo[k];
    scale[k] = extent > 0.0f ? bins / extent : 0.0f;
  }
}

/* Bin of a centroid coordinate; clamped because rounding can land on k == bins. */
LT_DEVICE int lt_bin_clamp(int k, int bins) { return k < 0 ? 0 : k >= bins ? bins - 1 : k; }
LT_DEVICE int lt_bin_of(float c, float lo, float scale, int bins) { return lt_bin_clamp((int)((c - lo) * scale), bins); }

/* The bin scale as a vector (w = 0). */
LT_DEVICE lt_v4 lt_bin_scale4(const lt_box *grid, int bins) {
  float scale[3];
  lt_bin_scale(grid, bins, scale);
  return lt_v4_make(scale[0], scale[1], scale[2], 0.0f);
}

/* Private bins: per axis and bin, how many primitives fell in and the box around them (two
 * vectors, so that adding a primitive is two vector min/max per axis). Only the bins marked in
 * `used` (per axis, bit k for bin k) hold anything; the others' fields are not kept, so that
 * clearing and pricing cost in proportion to the bins in use, not to the bins there are (most
 * nodes are small: a node of 8 primitives fills at most 8 of an axis's 32). */
typedef struct lt_bins {
  lt_v4 lo[3 * LT_MAX_BINS], hi[3 * LT_MAX_BINS];
  lt_i32 count[3 * LT_MAX_BINS];
  lt_u32 used[3];
} lt_bins;

LT_DEVICE void lt_bins_clear(lt_bins *bins) { bins->used[0] = bins->used[1] = bins->used[2] = 0u; }

/* Adds a box to bin k of an axis. The first box of a bin is the bin's box (the same floats
 * as the minimum and maximum with an empty box: boxes are finite, the scene has no others). */
LT_DEVICE void lt_bin_grow(lt_bins *bins, int axis, int k, lt_v4 lo, lt_v4 hi) {
  int i = axis * LT_MAX_BINS + k;
  lt_u32 bit = 1u << k;
  if (bins->used[axis] & bit) {
    bins->count[i]++;
    bins->lo[i] = lt_v4_min(lo, bins->lo[i]), bins->hi[i] = lt_v4_max(hi, bins->hi[i]);
  } else {
    bins->used[axis] |= bit;
    bins->count[i] = 1, bins->lo[i] = lo, bins->hi[i] = hi;
  }
}

/* Adds one primitive (box lo, hi) to its bin on every axis: the bins of lt_bin_of for the
 * centroid 0.5 * (lo + hi), clamped in float before the conversion (the same bin: truncation
 * and the clamp commute on [0, nbins - 1]) so that the three axes stay in one vector. An axis
 * of no extent (scale 0) puts everything in its bin 0, where no split is priced. Returns the
 * three bins packed a byte each (x lowest), for lt_packed_bin. */
LT_DEVICE int lt_bins_add(lt_bins *bins, lt_v4 clo, lt_v4 scale, int nbins, lt_v4 lo, lt_v4 hi) {
  lt_v4 t = lt_v4_max(((lo + hi) * 0.5f - clo) * scale, lt_v4_splat(0.0f));
  lt_vi4 k = lt_v4_to_int(lt_v4_min(t, lt_v4_splat((float)(nbins - 1))));
  int k0 = lt_v4_lane(k, 0), k1 = lt_v4_lane(k, 1), k2 = lt_v4_lane(k, 2);
  lt_bin_grow(bins, 0, k0, lo, hi);
  lt_bin_grow(bins, 1, k1, lo, hi);
  lt_bin_grow(bins, 2, k2, lo, hi);
  return k0 | k1 << 8 | k2 << 16;
}

/* A primitive's bin on one axis, from lt_bins_add's packed bins. */
LT_DEVICE int lt_packed_bin(int packed, int axis) { return (packed >> (8 * axis)) & 0xff; }

/* Merges private bins into a global slab with atomics (order-independent). */
LT_DEVICE void lt_bins_merge_global(LT_GLOBAL lt_i32 *slab, const lt_bins *bins) {
  for (int i = 0; i < 3 * LT_MAX_BINS; i++) {
    if (!(bins->used[i / LT_MAX_BINS] & 1u << (i % LT_MAX_BINS))) continue;
    LT_GLOBAL lt_i32 *s = slab + i * LT_BIN_STRIDE;
    lt_atomic_add_i32(&s[0], bins->count[i]);
    for (int k = 0; k < 3; k++) {
      lt_atomic_min_i32(&s[1 + k], lt_ordered(lt_v4_lane(bins->lo[i], k)));
      lt_atomic_max_i32(&s[4 + k], lt_ordered(lt_v4_lane(bins->hi[i], k)));
    }
  }
}

/* A cleared global slab, in the slab's encoding. */
LT_DEVICE void lt_bins_clear_global(LT_GLOBAL lt_i32 *slab) {
  for (int i = 0; i < 3 * LT_MAX_BINS; i++) {
    LT_GLOBAL lt_i32 *s = slab + i * LT_BIN_STRIDE;
    lt_atomic_store_i32(&s[0], 0);
    for (int k = 0; k < 3; k++) {
      lt_atomic_store_i32(&s[1 + k], lt_ordered(INFINITY));
      lt_atomic_store_i32(&s[4 + k], lt_ordered(-INFINITY));
    }
  }
}

/* A slab's merged bins back in the private form. */
LT_DEVICE void lt_bins_from_global(lt_bins *bins, LT_GLOBAL lt_i32 *slab) {
  lt_bins_clear(bins);
  for (int i = 0; i < 3 * LT_MAX_BINS; i++) {
    LT_GLOBAL lt_i32 *s = slab + i * LT_BIN_STRIDE;
    bins->count[i] = lt_atomic_load_i32(&s[0]);
    if (bins->count[i] > 0) bins->used[i / LT_MAX_BINS] |= 1u << (i % LT_MAX_BINS);
    float v[6];
    for (int k = 0; k < 6; k++) v[k] = lt_unordered(lt_atomic_load_i32(&s[1 + k]));
    bins->lo[i] = lt_v4_make(v[0], v[1], v[2], 0.0f);
    bins->hi[i] = lt_v4_make(v[3], v[4], v[5], 0.0f);
  }
}

/* The best split found in the bins. */
typedef struct lt_split {
  int axis, bin;          /* primitives in bins [0, bin] of axis go left; axis -1: no split */
  float cost;             /* SAH cost relative to one triangle test, FLT_MAX-like if none */
  int left_count;         /* of the primitives binned (all, unless the node was sampled) */
  lt_box left, right;     /* bounds of each side's binned primitives */
} lt_split;

/* The cheapest bin boundary on any axis (the first on ties, axes in order x, y, z, so that every
 * builder makes the same choice): the one pricing every boundary in order finds, though only
 * the boundaries after bins in use are priced (below). */
LT_DEVICE lt_split lt_sah_best_split(const lt_bins *bins, const lt_box *bounds, float traversal_cost,
                                     float intersection_cost) {
  lt_split best;
  best.axis = -1, best.bin = -1, best.cost = INFINITY, best.left_count = 0;
  float parent_area = lt_box_area(bounds), best_x = INFINITY;
  for (int axis = 0; axis < 3; axis++) {
    int a = axis * LT_MAX_BINS;
    lt_u32 used = bins->used[axis];

    /* Right-hand areas and counts by a sweep from the right, kept at the bins in use: the
     * right-hand side of a boundary starts at the first bin in use past it (empty bins change
     * neither the box nor the count). An empty box's area is 0. */
    float right_area[LT_MAX_BINS];
    int right_count[LT_MAX_BINS];
    lt_v4 lo = lt_v4_splat(INFINITY), hi = lt_v4_splat(-INFINITY);
    int n = 0;
    for (lt_u32 m = used; m; ) {
      int i = lt_high_bit(m);
      m &= ~(1u << i);
      n += bins->count[a + i];
      lo = lt_v4_min(bins->lo[a + i], lo), hi = lt_v4_max(bins->hi[a + i], hi);
      right_area[i] = lt_area4(lo, hi);
      right_count[i] = n;
    }

    /* Prices from the left. The cost, T + I * x / area, never falls where the weighted area x
     * does not (each step rounds monotonically), so a boundary whose x is not below the
     * best's cannot win and is not divided out: the same choice, ties included. The boundary
     * after an empty bin splits the primitives as the one before it does (the same x, which
     * cannot be below the best's), so only boundaries after a bin in use are priced, each
     * against the first bin in use past it: the choice that pricing every boundary in order
     * makes. */
    lo = lt_v4_splat(INFINITY), hi = lt_v4_splat(-INFINITY);
    n = 0;
    for (lt_u32 m = used; m; ) {
      int i = lt_low_bit(m);
      m &= m - 1u;
      if (m == 0) break; /* nothing to the right of the last bin in use */
      int j = lt_low_bit(m);
      n += bins->count[a + i];
      lo = lt_v4_min(bins->lo[a + i], lo), hi = lt_v4_max(bins->hi[a + i], hi);
      float x = lt_area4(lo, hi) * n + right_area[j] * right_count[j];
      if (!(x < best_x)) continue;
      float cost = traversal_cost + intersection_cost * x / parent_area;
      if (cost < best.cost) best.axis = axis, best.bin = i, best.cost = cost, best.left_count = n, best_x = x;
    }
  }
  best.left = best.right = lt_box_empty();
  if (best.axis < 0) return best;

  /* Both sides' primitive bounds, from the chosen axis's bins. */
  lt_v4 lo[2] = {lt_v4_splat(INFINITY), lt_v4_splat(INFINITY)}, hi[2] = {lt_v4_splat(-INFINITY), lt_v4_splat(-INFINITY)};
  for (lt_u32 m = bins->used[best.axis]; m; m &= m - 1u) {
    int i = lt_low_bit(m), j = best.axis * LT_MAX_BINS + i, side = i > best.bin;
    lo[side] = lt_v4_min(bins->lo[j], lo[side]), hi[side] = lt_v4_max(bins->hi[j], hi[side]);
  }
  best.left = lt_box_of4(lo[0], hi[0]), best.right = lt_box_of4(lo[1], hi[1]);
  return best;
}

/* Whether a node of n primitives at this depth becomes a leaf: small enough and SAH sees no
 * gain, a single primitive, or the depth bound that keeps traversal stacks from overflowing.
 * A node of more than max_leaf primitives with no SAH split takes the object median. */
LT_DEVICE int lt_sah_make_leaf(int n, int depth, const lt_split *s, int max_leaf, float intersection_cost,
                               int max_depth) {
  return n <= 1 || depth >= max_depth - 1 || (n <= max_leaf && !(s->cost < intersection_cost * n));
}

#endif
