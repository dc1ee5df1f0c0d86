/* Reference-quality SAH BVH build on the host, for the accuracy report: the full sweep over
 * every primitive boundary of the centroid order on each axis (MacDonald and Booth, "Heuristics
 * for ray tracing using space subdivision", 1990), or binning with any number of bins (Wald
 * 2007) where the pool's builder stops at LT_MAX_BINS. Single-threaded and O(n log^2 n): it
 * exists to price what binning gives up, not to be fast. */
#include "builders/host/bvh_sweep.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "builders/sah_bins.h"

typedef struct sweeper {
  const lt__sah_config *config;
  int bins;           /* 0: full sweep */
  lt_box *prim_box;   /* per triangle */
  float *centroid;    /* 3 per triangle */
  int *index;         /* triangle numbers, permuted into leaf order */
  int *scratch;
  float *left_area;   /* per position or bin: area of the boxes to its left */
  lt__bvh *bvh;
  int sort_axis;      /* the axis qsort compares on */
} sweeper;

/* qsort has no context argument: one sweeper at a time sorts (the report is single-threaded). */
static const sweeper *sorting;

static int by_centroid(const void *a, const void *b) {
  int p = *(const int *)a, q = *(const int *)b;
  float cp = sorting->centroid[3 * p + sorting->sort_axis], cq = sorting->centroid[3 * q + sorting->sort_axis];
  return cp < cq ? -1 : cp > cq ? 1 : (p > q) - (p < q);
}

typedef struct choice {
  int axis, position; /* sweep: the first position that goes right; bins: the last bin that goes left */
  float cost;
} choice;

/* Prices every split of index[begin, end) sorted along `axis`. */
static void sweep_axis(sweeper *s, int begin, int end, int axis, float parent_area, choice *best) {
  int n = end - begin;
  s->sort_axis = axis;
  sorting = s;
  qsort(s->index + begin, (size_t)n, sizeof *s->index, by_centroid);
  lt_box acc = lt_box_empty();
  for (int i = 0; i < n - 1; i++) {
    lt_box_grow(&acc, &s->prim_box[s->index[begin + i]]);
    s->left_area[i] = lt_box_area(&acc);
  }
  acc = lt_box_empty();
  for (int i = n - 1; i > 0; i--) {
    lt_box_grow(&acc, &s->prim_box[s->index[begin + i]]);
    float cost = s->config->traversal_cost +
                 s->config->intersection_cost * (s->left_area[i - 1] * i + lt_box_area(&acc) * (n - i)) / parent_area;
    if (cost < best->cost) best->axis = axis, best->position = i, best->cost = cost;
  }
}

/* Prices the bin boundaries of index[begin, end) along `axis`. */
static void bin_axis(sweeper *s, int begin, int end, int axis, const lt_box *cbounds, float parent_area, choice *best) {
  int k = s->bins;
  float extent = cbounds->hi[axis] - cbounds->lo[axis];
  if (!(extent > 0.0f)) return;
  float scale = k / extent;
  lt_box *box = malloc((size_t)k * sizeof *box);
  int *count = calloc((size_t)k, sizeof *count);
  for (int b = 0; b < k; b++) box[b] = lt_box_empty();
  for (int i = begin; i < end; i++) {
    int p = s->index[i], b = lt_bin_of(s->centroid[3 * p + axis], cbounds->lo[axis], scale, k);
    count[b]++;
    lt_box_grow(&box[b], &s->prim_box[p]);
  }
  lt_box acc = lt_box_empty();
  int left = 0;
  for (int b = 0; b < k - 1; b++) {
    lt_box_grow(&acc, &box[b]);
    left += count[b];
    s->left_area[2 * b] = lt_box_area(&acc);
    s->left_area[2 * b + 1] = (float)left;
  }
  acc = lt_box_empty();
  int right = 0;
  for (int b = k - 1; b > 0; b--) {
    lt_box_grow(&acc, &box[b]);
    right += count[b];
    int l = (int)s->left_area[2 * (b - 1) + 1];
    if (l == 0 || right == 0) continue;
    float cost = s->config->traversal_cost +
                 s->config->intersection_cost * (s->left_area[2 * (b - 1)] * l + lt_box_area(&acc) * right) / parent_area;
    if (cost < best->cost) best->axis = axis, best->position = b - 1, best->cost = cost;
  }
  free(box), free(count);
}

/* Builds the subtree over index[begin, end): its box, link and count go to the out-arguments. */
static void build(sweeper *s, int begin, int end, int depth, lt_box *bounds, int *link, int *count) {
  lt__bvh *bvh = s->bvh;
  if (depth > bvh->max_depth) bvh->max_depth = depth;
  int n = end - begin;

  /* Bounds of the primitives and of their centroids. */
  lt_box cbounds = lt_box_empty();
  *bounds = lt_box_empty();
  for (int i = begin; i < end; i++) {
    int p = s->index[i];
    const float *c = &s->centroid[3 * p];
    lt_box cb = {{c[0], c[1], c[2]}, {c[0], c[1], c[2]}};
    lt_box_grow(bounds, &s->prim_box[p]);
    lt_box_grow(&cbounds, &cb);
  }

  /* The cheapest split over all axes (sweep or bins). */
  choice best = {-1, -1, INFINITY};
  float area = lt_box_area(bounds);
  if (n > 1 && depth < LT_BVH_MAX_DEPTH - 1 && area > 0.0f)
    for (int axis = 0; axis < 3; axis++) {
      if (s->bins == 0) sweep_axis(s, begin, end, axis, area, &best);
      else bin_axis(s, begin, end, axis, &cbounds, area, &best);
    }
  lt_split as_split;
  as_split.cost = best.cost;
  if (lt_sah_make_leaf(n, depth, &as_split, s->config->max_leaf_size, s->config->intersection_cost, LT_BVH_MAX_DEPTH)) {
    *link = begin, *count = n;
    bvh->leaf_count++;
    bvh->sah_cost += (double)s->config->intersection_cost * n * area;
    return;
  }

  /* Order the range for the chosen split; the object median when none was found. */
  int mid = begin + n / 2;
  if (best.axis >= 0 && s->bins == 0) {
    s->sort_axis = best.axis;
    sorting = s;
    qsort(s->index + begin, (size_t)n, sizeof *s->index, by_centroid);
    mid = begin + best.position;
  } else if (best.axis >= 0) {
    float scale = s->bins / (cbounds.hi[best.axis] - cbounds.lo[best.axis]);
    int left = begin, right = 0;
    for (int i = begin; i < end; i++) {
      int p = s->index[i];
      if (lt_bin_of(s->centroid[3 * p + best.axis], cbounds.lo[best.axis], scale, s->bins) <= best.position)
        s->index[left++] = p;
      else
        s->scratch[right++] = p;
    }
    memcpy(s->index + left, s->scratch, (size_t)right * sizeof *s->index);
    mid = left;
  }
  bvh->sort_ops += (uint64_t)n;

  /* An inner node over both halves. */
  int node = bvh->node_count++;
  *link = node, *count = 0;
  bvh->sah_cost += (double)s->config->traversal_cost * area;
  lt_box box[2];
  int child_link[2], child_count[2];
  build(s, begin, mid, depth + 1, &box[0], &child_link[0], &child_count[0]);
  build(s, mid, end, depth + 1, &box[1], &child_link[1], &child_count[1]);
  for (int side = 0; side < 2; side++)
    lt_bvh_write_child(&bvh->nodes[node], side, &box[side], child_link[side], child_count[side]);
}

lt_status lt__bvh_build_sweep(const float *tris, size_t n, const lt__sah_config *config, int bins, lt__bvh *out) {
  if (n == 0 || n > INT32_MAX / 4) return LT_ERROR_INVALID_ARGUMENT;
  if (bins < 0 || bins == 1 || config->max_leaf_size < 1)
    return LT_ERROR_INVALID_ARGUMENT;
  memset(out, 0, sizeof *out);
  size_t scratch_floats = bins ? 2 * (size_t)bins : n;
  sweeper s = {config, bins, malloc(n * sizeof(lt_box)), malloc(3 * n * sizeof(float)), malloc(n * sizeof(int)),
               malloc(n * sizeof(int)), malloc(scratch_floats * sizeof(float)), out, 0};
  out->nodes = calloc(n, sizeof *out->nodes);
  out->tris = malloc(n * sizeof *out->tris);
  if (!s.prim_box || !s.centroid || !s.index || !s.scratch || !s.left_area || !out->nodes || !out->tris) {
    free(s.prim_box), free(s.centroid), free(s.index), free(s.scratch), free(s.left_area);
    lt__bvh_free(out);
    return LT_ERROR_OUT_OF_MEMORY;
  }
  for (size_t i = 0; i < n; i++) {
    lt_tri_bounds(tris + 9 * i, &s.prim_box[i], &s.centroid[3 * i]);
    s.index[i] = (int)i;
  }

  lt_box root;
  int link, count;
  build(&s, 0, (int)n, 0, &root, &link, &count);
  lt__bvh_finish(out, tris, s.index, n, &root, link, count);
  free(s.prim_box), free(s.centroid), free(s.index), free(s.scratch), free(s.left_area);
  return LT_OK;
}
