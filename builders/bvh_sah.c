/* Full binned-SAH BVH build (Wald, "On fast Construction of SAH-based Bounding Volume
 * Hierarchies", 2007), with the parameters of the on-demand paper (Vinkler et al. 2016,
 * section 3.3): 32 bins, leaves of at most 16 triangles or when SAH says stop. */
#include "builders/bvh_sah.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "runtime/error.h"

#define MAX_BINS 256

typedef struct box {
  float lo[3], hi[3];
} box;

typedef struct builder {
  const float *tris;
  const lt__sah_config *config;
  box *prim_box;   /* per triangle */
  float *centroid; /* 3 per triangle */
  int *index;      /* triangle numbers, permuted into leaf order as the build goes */
  lt__bvh *bvh;
} builder;

/* A child link being built, with its box. */
typedef struct child {
  box bounds;
  int link, count;
} child;

static box box_empty(void) {
  box b = {{FLT_MAX, FLT_MAX, FLT_MAX}, {-FLT_MAX, -FLT_MAX, -FLT_MAX}};
  return b;
}

static void box_grow(box *b, const box *o) {
  for (int k = 0; k < 3; k++) {
    b->lo[k] = o->lo[k] < b->lo[k] ? o->lo[k] : b->lo[k];
    b->hi[k] = o->hi[k] > b->hi[k] ? o->hi[k] : b->hi[k];
  }
}

static float box_area(const box *b) {
  float d[3];
  for (int k = 0; k < 3; k++) d[k] = fmaxf(b->hi[k] - b->lo[k], 0.0f);
  return 2.0f * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0]);
}

lt__sah_config lt__sah_config_default(void) {
  lt__sah_config config = {16, 32, 1.0f, 1.0f};
  return config;
}

/* Bin index of a centroid coordinate; clamped because rounding can land on k == bins. */
static int bin_of(float c, float lo, float scale, int bins) {
  int k = (int)((c - lo) * scale);
  return k < 0 ? 0 : k >= bins ? bins - 1 : k;
}

typedef struct split {
  int axis, bin; /* primitives in bins [0, bin] go left */
  float cost;
} split;

/* Evaluates the SAH at every bin boundary on every axis; cost is FLT_MAX if nothing splits.
 * One pass over the primitives bins all three axes, which keeps the triangle data in cache. */
static split find_split(builder *b, int begin, int end, const box *bounds, const box *cbounds) {
  int bins = b->config->bins;
  split best = {-1, -1, FLT_MAX};
  float parent_area = box_area(bounds);
  int count[3][MAX_BINS] = {{0}};
  box bin_box[3][MAX_BINS];
  float scale[3];
  for (int axis = 0; axis < 3; axis++) {
    float extent = cbounds->hi[axis] - cbounds->lo[axis];
    scale[axis] = extent > 0.0f ? bins / extent : 0.0f;
    for (int i = 0; i < bins; i++) bin_box[axis][i] = box_empty();
  }

  /* Count and bound the primitives of each bin. */
  for (int i = begin; i < end; i++) {
    int p = b->index[i];
    const box *pb = &b->prim_box[p];
    for (int axis = 0; axis < 3; axis++) {
      int k = bin_of(b->centroid[3 * p + axis], cbounds->lo[axis], scale[axis], bins);
      count[axis][k]++;
      box_grow(&bin_box[axis][k], pb);
    }
  }
  b->bvh->sort_ops += (uint64_t)(end - begin);

  for (int axis = 0; axis < 3; axis++) {
    if (scale[axis] == 0.0f) continue;

    /* Sweep from the right to get the right-hand areas, then from the left to price splits. */
    float right_area[MAX_BINS];
    int right_count[MAX_BINS];
    box acc = box_empty();
    int n = 0;
    for (int i = bins - 1; i > 0; i--) {
      box_grow(&acc, &bin_box[axis][i]);
      n += count[axis][i];
      right_area[i] = box_area(&acc);
      right_count[i] = n;
    }
    acc = box_empty();
    n = 0;
    for (int i = 0; i < bins - 1; i++) {
      box_grow(&acc, &bin_box[axis][i]);
      n += count[axis][i];
      if (n == 0 || right_count[i + 1] == 0) continue;
      float cost = b->config->traversal_cost +
                   b->config->intersection_cost *
                       (box_area(&acc) * n + right_area[i + 1] * right_count[i + 1]) / parent_area;
      if (cost < best.cost) best = (split){axis, i, cost};
    }
  }
  return best;
}

/* Moves primitives of bins [0, s.bin] to the front of [begin, end); returns the middle. */
static int partition(builder *b, int begin, int end, split s, const box *cbounds) {
  float scale = b->config->bins / (cbounds->hi[s.axis] - cbounds->lo[s.axis]);
  int i = begin, j = end - 1;
  while (i <= j) {
    int p = b->index[i];
    if (bin_of(b->centroid[3 * p + s.axis], cbounds->lo[s.axis], scale, b->config->bins) <= s.bin) {
      i++;
    } else {
      b->index[i] = b->index[j];
      b->index[j--] = p;
    }
  }
  b->bvh->sort_ops += (uint64_t)(end - begin);
  return i;
}

static void set_child(lt_bvh_node *node, int side, const child *c) {
  if (side == 0) {
    node->left_xy = (lt_float4){c->bounds.lo[0], c->bounds.hi[0], c->bounds.lo[1], c->bounds.hi[1]};
    node->lr_z.x = c->bounds.lo[2], node->lr_z.y = c->bounds.hi[2];
    node->link.x = c->link, node->link.z = c->count;
  } else {
    node->right_xy = (lt_float4){c->bounds.lo[0], c->bounds.hi[0], c->bounds.lo[1], c->bounds.hi[1]};
    node->lr_z.z = c->bounds.lo[2], node->lr_z.w = c->bounds.hi[2];
    node->link.y = c->link, node->link.w = c->count;
  }
}

/* Builds the subtree over index[begin, end) and describes it as a child link. */
static void build(builder *b, int begin, int end, int depth, child *out) {
  lt__bvh *bvh = b->bvh;
  if (depth > bvh->max_depth) bvh->max_depth = depth;

  /* Bounds of the primitives and of their centroids. */
  box bounds = box_empty(), cbounds = box_empty();
  for (int i = begin; i < end; i++) {
    int p = b->index[i];
    box_grow(&bounds, &b->prim_box[p]);
    box c = {{b->centroid[3 * p], b->centroid[3 * p + 1], b->centroid[3 * p + 2]},
             {b->centroid[3 * p], b->centroid[3 * p + 1], b->centroid[3 * p + 2]}};
    box_grow(&cbounds, &c);
  }
  out->bounds = bounds;
  int n = end - begin;
  float leaf_cost = b->config->intersection_cost * n;

  /* Leaf when small enough and SAH sees no gain, or when the depth bound is reached. */
  split s = {-1, -1, FLT_MAX};
  if (n > 1 && depth < LT_BVH_MAX_DEPTH - 1) s = find_split(b, begin, end, &bounds, &cbounds);
  int make_leaf = n <= 1 || depth >= LT_BVH_MAX_DEPTH - 1 ||
                  (n <= b->config->max_leaf_size && s.cost >= leaf_cost);
  if (make_leaf) {
    out->link = begin, out->count = n;
    bvh->leaf_count++;
    bvh->sah_cost += (double)leaf_cost * box_area(&bounds);
    return;
  }

  /* Split where SAH says, or at the object median when all centroids coincide. */
  int mid = s.axis >= 0 ? partition(b, begin, end, s, &cbounds) : begin + n / 2;
  int node = bvh->node_count++;
  out->link = node, out->count = 0;
  bvh->sah_cost += (double)b->config->traversal_cost * box_area(&bounds);
  child left, right;
  build(b, begin, mid, depth + 1, &left);
  build(b, mid, end, depth + 1, &right);
  set_child(&bvh->nodes[node], 0, &left);
  set_child(&bvh->nodes[node], 1, &right);
}

lt_status lt__bvh_build_sah(const float *tris, size_t n, const lt__sah_config *config, lt__bvh *out) {
  if (n == 0 || n > INT32_MAX / 2) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "BVH build: %zu triangles", n);
  if (config->bins < 2 || config->bins > MAX_BINS || config->max_leaf_size < 1)
    return lt__fail(LT_ERROR_INVALID_ARGUMENT, "BVH build: bins must be 2..%d and leaves at least 1", MAX_BINS);
  memset(out, 0, sizeof *out);
  builder b = {tris, config, malloc(n * sizeof(box)), malloc(3 * n * sizeof(float)), malloc(n * sizeof(int)), out};
  out->nodes = calloc(n, sizeof *out->nodes);
  out->tris = malloc(n * sizeof *out->tris);
  if (!b.prim_box || !b.centroid || !b.index || !out->nodes || !out->tris) {
    free(b.prim_box), free(b.centroid), free(b.index);
    lt__bvh_free(out);
    return lt__fail(LT_ERROR_OUT_OF_MEMORY, "BVH build: out of memory for %zu triangles", n);
  }

  /* Per-triangle boxes and centroids. */
  for (size_t i = 0; i < n; i++) {
    const float *t = tris + 9 * i;
    box *pb = &b.prim_box[i];
    for (int k = 0; k < 3; k++) {
      pb->lo[k] = fminf(t[k], fminf(t[3 + k], t[6 + k]));
      pb->hi[k] = fmaxf(t[k], fmaxf(t[3 + k], t[6 + k]));
      b.centroid[3 * i + k] = 0.5f * (pb->lo[k] + pb->hi[k]);
    }
    b.index[i] = (int)i;
  }

  /* The root is always an inner node; a scene that is one leaf gets an empty sibling. */
  child root;
  build(&b, 0, (int)n, 0, &root);
  if (root.count > 0) {
    child empty = {box_empty(), -1, 0};
    out->node_count = 1;
    set_child(&out->nodes[0], 0, &root);
    set_child(&out->nodes[0], 1, &empty);
  }

  /* Triangles in leaf order, each carrying its number. */
  for (size_t i = 0; i < n; i++) {
    const float *t = tris + 9 * b.index[i];
    out->tris[i].v0 = (lt_float4){t[0], t[1], t[2], lt_int_as_float(b.index[i])};
    out->tris[i].v1 = (lt_float4){t[3], t[4], t[5], 0.0f};
    out->tris[i].v2 = (lt_float4){t[6], t[7], t[8], 0.0f};
  }
  out->tri_count = (int)n;
  float root_area = box_area(&root.bounds);
  out->sah_cost = root_area > 0.0f ? out->sah_cost / root_area : 0.0;
  free(b.prim_box), free(b.centroid), free(b.index);
  return LT_OK;
}

void lt__bvh_free(lt__bvh *bvh) {
  free(bvh->nodes);
  free(bvh->tris);
  bvh->nodes = NULL, bvh->tris = NULL;
}

int64_t lt__bvh_tree_nodes(const lt__bvh *bvh) { return (int64_t)bvh->node_count + bvh->leaf_count; }
