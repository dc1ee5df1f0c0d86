/* Full binned-SAH BVH build (Wald, "On fast Construction of SAH-based Bounding Volume
 * Hierarchies", 2007), with the parameters of the on-demand paper (Vinkler et al. 2016,
 * section 3.3): 32 bins, leaves of at most 16 triangles or when SAH says stop. */
#include "builders/host/bvh_sah.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "builders/sah_bins.h"

typedef struct builder {
  const float *tris;
  const lt__sah_config *config;
  lt_box *prim_box; /* per triangle */
  float *centroid;  /* 3 per triangle */
  int *index;       /* triangle numbers, permuted into leaf order as the build goes */
  int *scratch;     /* room for the stable partition */
  lt__bvh *bvh;
} builder;

/* A child link being built, with its box. */
typedef struct child {
  lt_box bounds;
  int link, count;
} child;

lt__sah_config lt__sah_config_default(void) {
  lt__sah_config config = {16, 32, 1.0f, 1.0f};
  return config;
}

/* Bins the range (every primitive, or a regular sample of a large node) over the node's box
 * and prices the splits (sah_bins.h). */
static lt_split find_split(builder *b, int begin, int end, const lt_box *bounds) {
  lt_bins bins;
  lt_v4 clo = lt_box_lo4(bounds), scale = lt_bin_scale4(bounds, b->config->bins);
  lt_bins_clear(&bins);
  int step = lt_bin_step(end - begin);
  for (int i = begin; i < end; i += step) {
    const lt_box *box = &b->prim_box[b->index[i]];
    lt_bins_add(&bins, clo, scale, b->config->bins, lt_box_lo4(box), lt_box_hi4(box));
  }
  b->bvh->sort_ops += (uint64_t)lt_bin_sample_count(end - begin);
  return lt_sah_best_split(&bins, bounds, b->config->traversal_cost, b->config->intersection_cost);
}

/* Stable partition: the primitives of bins [0, s.bin] keep their order at the front, the
 * others keep theirs behind them, as the pool's chunked partition does. Returns the middle. */
static int partition(builder *b, int begin, int end, const lt_split *s, const lt_box *bounds) {
  float scale[3];
  lt_bin_scale(bounds, b->config->bins, scale);
  int left = begin, right = 0;
  for (int i = begin; i < end; i++) {
    int p = b->index[i];
    if (lt_bin_of(b->centroid[3 * p + s->axis], bounds->lo[s->axis], scale[s->axis], b->config->bins) <= s->bin)
      b->index[left++] = p;
    else
      b->scratch[right++] = p;
  }
  memcpy(b->index + left, b->scratch, (size_t)right * sizeof *b->index);
  b->bvh->sort_ops += (uint64_t)(end - begin);
  return left;
}

void lt__bvh_finish(lt__bvh *out, const float *tris, const int *leaf_order, size_t n, const lt_box *root, int link,
                    int count) {
  if (count > 0) {
    lt_box empty = lt_box_empty();
    out->node_count = 1;
    lt_bvh_write_child(&out->nodes[0], 0, root, link, count);
    lt_bvh_write_child(&out->nodes[0], 1, &empty, LT_BVH_LINK_EMPTY, 0);
  }
  for (size_t i = 0; i < n; i++) {
    const float *t = tris + 9 * (size_t)leaf_order[i];
    out->tris[i].v0 = lt_make_float4(t[0], t[1], t[2], lt_int_as_float(leaf_order[i]));
    out->tris[i].v1 = lt_make_float4(t[3], t[4], t[5], 0.0f);
    out->tris[i].v2 = lt_make_float4(t[6], t[7], t[8], 0.0f);
  }
  out->tri_count = (int)n;
  float root_area = lt_box_area(root);
  out->sah_cost = root_area > 0.0f ? out->sah_cost / root_area : 0.0;
}

/* Builds the subtree over index[begin, end) and describes it as a child link. */
static void build(builder *b, int begin, int end, int depth, child *out) {
  lt__bvh *bvh = b->bvh;
  if (depth > bvh->max_depth) bvh->max_depth = depth;

  /* Bounds of the primitives: the node's box and its bin grid. */
  lt_box bounds = lt_box_empty();
  for (int i = begin; i < end; i++) lt_box_grow(&bounds, &b->prim_box[b->index[i]]);
  out->bounds = bounds;
  int n = end - begin;

  /* Leaf when small enough and SAH sees no gain, or at the depth bound. */
  lt_split s;
  s.axis = -1, s.cost = INFINITY;
  if (n > 1 && depth < LT_BVH_MAX_DEPTH - 1) s = find_split(b, begin, end, &bounds);
  if (lt_sah_make_leaf(n, depth, &s, b->config->max_leaf_size, b->config->intersection_cost, LT_BVH_MAX_DEPTH)) {
    out->link = begin, out->count = n;
    bvh->leaf_count++;
    bvh->sah_cost += (double)b->config->intersection_cost * n * lt_box_area(&bounds);
    return;
  }

  /* Split where SAH says, or at the object median when no boundary divides the centroids. */
  int mid = s.axis >= 0 ? partition(b, begin, end, &s, &bounds) : begin + n / 2;
  int node = bvh->node_count++;
  out->link = node, out->count = 0;
  bvh->sah_cost += (double)b->config->traversal_cost * lt_box_area(&bounds);
  child left, right;
  build(b, begin, mid, depth + 1, &left);
  build(b, mid, end, depth + 1, &right);
  lt_bvh_write_child(&bvh->nodes[node], 0, &left.bounds, left.link, left.count);
  lt_bvh_write_child(&bvh->nodes[node], 1, &right.bounds, right.link, right.count);
}

lt_status lt__bvh_build_sah(const float *tris, size_t n, const lt__sah_config *config, lt__bvh *out) {
  if (n == 0 || n > INT32_MAX / 2) return LT_ERROR_INVALID_ARGUMENT;
  if (config->bins < 2 || config->bins > LT_MAX_BINS || config->max_leaf_size < 1)
    return LT_ERROR_INVALID_ARGUMENT;
  memset(out, 0, sizeof *out);
  builder b = {tris, config, malloc(n * sizeof(lt_box)), malloc(3 * n * sizeof(float)), malloc(n * sizeof(int)),
               malloc(n * sizeof(int)), out};
  out->nodes = calloc(n, sizeof *out->nodes);
  out->tris = malloc(n * sizeof *out->tris);
  if (!b.prim_box || !b.centroid || !b.index || !b.scratch || !out->nodes || !out->tris) {
    free(b.prim_box), free(b.centroid), free(b.index), free(b.scratch);
    lt__bvh_free(out);
    return LT_ERROR_OUT_OF_MEMORY;
  }

  /* Per-triangle boxes and centroids. */
  for (size_t i = 0; i < n; i++) {
    lt_tri_bounds(tris + 9 * i, &b.prim_box[i], &b.centroid[3 * i]);
    b.index[i] = (int)i;
  }

  child root;
  build(&b, 0, (int)n, 0, &root);
  lt__bvh_finish(out, tris, b.index, n, &root.bounds, root.link, root.count);
  free(b.prim_box), free(b.centroid), free(b.index), free(b.scratch);
  return LT_OK;
}

void lt__bvh_free(lt__bvh *bvh) {
  free(bvh->nodes);
  free(bvh->tris);
  bvh->nodes = NULL, bvh->tris = NULL;
}

int64_t lt__bvh_tree_nodes(const lt__bvh *bvh) { return (int64_t)bvh->node_count + bvh->leaf_count; }
