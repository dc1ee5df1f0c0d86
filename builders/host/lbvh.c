/* HLBVH_4 of the on-demand paper: Karras's split rule over sorted Morton codes (Karras, "Maximizing
 * Parallelism in the Construction of BVHs, Octrees, and k-d Trees", HPG 2012) inside clusters sharing
 * the top 12 code bits, binned SAH above them (HLBVH: Pantaleoni and Luebke 2010; pbrt-v3 4.3.3). */
#include "builders/host/lbvh.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>


#define AXIS_BITS   10
#define MORTON_BITS (3 * AXIS_BITS)
/* Four levels of the octree: the "_4" of HLBVH_4; at most 4096 clusters. */
#define CLUSTER_BITS 12
#define RADIX_BITS   10
#define RADIX_PASSES ((MORTON_BITS + RADIX_BITS - 1) / RADIX_BITS)
/* Clusters are few, so the top is cheap even with the on-demand paper's 32 bins. */
#define TOP_MAX_BINS 32

typedef struct box {
  float lo[3], hi[3];
} box;

/* A child link being built, with its box. */
typedef struct child {
  box bounds;
  int link, count;
} child;

/* The primitives of one cluster: a run of the sorted keys with the same top CLUSTER_BITS. */
typedef struct cluster {
  int begin, end; /* range of the sorted keys */
  int out;        /* first position in leaf order, given when the top build reaches it */
  box bounds;
  float centroid[3];
} cluster;

typedef struct builder {
  const lt__sah_config *config;
  int leaf_size, top_bins, depth_limit;
  const uint64_t *keys; /* sorted: Morton code << 32 | triangle number */
  box *sorted_box;      /* triangle boxes in key order, so that leaves read them in sequence */
  cluster *clusters;
  int *cluster_index; /* cluster numbers, permuted by the top build */
  int next_out;       /* next free position in leaf order */
  lt__bvh *bvh;
} builder;

/* min and max as comparisons: the scene holds no NaN, and fminf/fmaxf are library calls here. */
static float min_f(float a, float b) { return a < b ? a : b; }
static float max_f(float a, float b) { return a > b ? a : b; }

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
  for (int k = 0; k < 3; k++) d[k] = max_f(b->hi[k] - b->lo[k], 0.0f);
  return 2.0f * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0]);
}

static void set_child(lt_bvh_node *node, int side, const child *c) {
  lt_box x;
  for (int k = 0; k < 3; k++) x.lo[k] = c->bounds.lo[k], x.hi[k] = c->bounds.hi[k];
  lt_bvh_write_child(node, side, &x, c->link, c->count);
}

/* ---- Morton codes and their sort ---- */

/* Moves the low 10 bits of v to every third bit of 30, so that three axes interleave. */
static uint32_t spread_bits(uint32_t v) {
  v = (v * 0x00010001u) & 0xFF0000FFu;
  v = (v * 0x00000101u) & 0x0F00F00Fu;
  v = (v * 0x00000011u) & 0xC30C30C3u;
  v = (v * 0x00000005u) & 0x49249249u;
  return v;
}

/* A centroid coordinate as one of 1024 cells; written so that NaN lands in cell 0. */
static uint32_t quantize(float c, float lo, float scale) {
  float t = (c - lo) * scale;
  if (!(t > 0.0f)) return 0;
  return t >= 1023.0f ? 1023u : (uint32_t)t;
}

/* LSD radix sort of the keys by their code bits. Each pass is stable and the keys start in
 * triangle order, so equal codes end in triangle order and the build is deterministic. Returns
 * the array that holds the result (keys or tmp). */
static uint64_t *radix_sort(uint64_t *keys, uint64_t *tmp, size_t n, uint64_t *ops) {
  enum { buckets = 1 << RADIX_BITS };
  size_t count[RADIX_PASSES][buckets];
  memset(count, 0, sizeof count);

  /* One read of the keys counts the digits of every pass. */
  for (size_t i = 0; i < n; i++)
    for (int p = 0; p < RADIX_PASSES; p++) count[p][(keys[i] >> (32 + p * RADIX_BITS)) & (buckets - 1)]++;

  for (int p = 0; p < RADIX_PASSES; p++) {
    int shift = 32 + p * RADIX_BITS;
    /* A digit that is the same in every key would only copy the array. */
    if (count[p][(keys[0] >> shift) & (buckets - 1)] == n) continue;

    /* Exclusive prefix sums give each bucket's first slot; then scatter in order. */
    size_t sum = 0;
    for (int d = 0; d < buckets; d++) {
      size_t c = count[p][d];
      count[p][d] = sum;
      sum += c;
    }
    for (size_t i = 0; i < n; i++) tmp[count[p][(keys[i] >> shift) & (buckets - 1)]++] = keys[i];
    uint64_t *swap = keys;
    keys = tmp, tmp = swap;
    *ops += n;
  }
  return keys;
}

/* ---- Karras hierarchy inside a cluster ---- */

static uint32_t code_of(uint64_t key) { return (uint32_t)(key >> 32); }

/* Last index of the left half of keys[first, last]: where the highest bit in which the first and
 * last codes differ turns from 0 to 1 (Karras's split rule), or the middle when all codes are
 * equal, which Karras resolves by appending the index to the key. */
static int find_split(const uint64_t *keys, int first, int last) {
  uint32_t a = code_of(keys[first]), z = code_of(keys[last]);
  if (a == z) return first + (last - first) / 2;
  uint32_t bit = 0x80000000u >> __builtin_clz(a ^ z);

  /* Codes are sorted and share the bits above `bit`, so those with it clear come first. */
  int lo = first + 1, hi = last;
  while (lo < hi) {
    int mid = lo + (hi - lo) / 2;
    if (code_of(keys[mid]) & bit)
      hi = mid;
    else
      lo = mid + 1;
  }
  return lo - 1;
}

/* Builds the subtree over the sorted keys [first, last]; leaf order is key order plus offset. */
static void build_range(builder *b, int first, int last, int offset, int depth, child *out) {
  lt__bvh *bvh = b->bvh;
  if (depth > bvh->max_depth) bvh->max_depth = depth;
  int n = last - first + 1;

  /* Small ranges are leaves, and whatever remains at the depth bound, whatever its size. */
  if (n <= b->leaf_size || depth >= b->depth_limit - 1) {
    box bounds = box_empty();
    for (int i = first; i <= last; i++) box_grow(&bounds, &b->sorted_box[i]);
    out->bounds = bounds, out->link = first + offset, out->count = n;
    bvh->leaf_count++;
    bvh->sah_cost += (double)b->config->intersection_cost * n * box_area(&bounds);
    return;
  }

  /* Inner node: split by the codes, then take the exact box from the children. */
  int split = find_split(b->keys, first, last);
  int node = bvh->node_count++;
  child left, right;
  build_range(b, first, split, offset, depth + 1, &left);
  build_range(b, split + 1, last, offset, depth + 1, &right);
  set_child(&bvh->nodes[node], 0, &left);
  set_child(&bvh->nodes[node], 1, &right);
  out->bounds = left.bounds;
  box_grow(&out->bounds, &right.bounds);
  out->link = node, out->count = 0;
  bvh->sah_cost += (double)b->config->traversal_cost * box_area(&out->bounds);
}

/* ---- SAH top over the clusters ---- */

static int bin_of(float c, float lo, float scale, int bins) {
  int k = (int)((c - lo) * scale);
  return k < 0 ? 0 : k >= bins ? bins - 1 : k;
}

/* Splits cluster_index[begin, end) by binned SAH over the cluster centroids, each cluster
 * weighted by its triangles; returns the middle. The object median when no bin boundary
 * separates the clusters. */
static int split_clusters(builder *b, int begin, int end) {
  int bins = b->top_bins;
  int *index = b->cluster_index;
  box cbounds = box_empty();
  for (int i = begin; i < end; i++) {
    const float *c = b->clusters[index[i]].centroid;
    box point = {{c[0], c[1], c[2]}, {c[0], c[1], c[2]}};
    box_grow(&cbounds, &point);
  }

  /* Bin the clusters along all three axes in one pass. */
  int count[3][TOP_MAX_BINS] = {{0}};
  box bin_box[3][TOP_MAX_BINS];
  float scale[3];
  for (int axis = 0; axis < 3; axis++) {
    float extent = cbounds.hi[axis] - cbounds.lo[axis];
    scale[axis] = extent > 0.0f ? bins / extent : 0.0f;
    for (int k = 0; k < bins; k++) bin_box[axis][k] = box_empty();
  }
  for (int i = begin; i < end; i++) {
    const cluster *c = &b->clusters[index[i]];
    for (int axis = 0; axis < 3; axis++) {
      int k = bin_of(c->centroid[axis], cbounds.lo[axis], scale[axis], bins);
      count[axis][k] += c->end - c->begin;
      box_grow(&bin_box[axis][k], &c->bounds);
    }
  }
  b->bvh->sort_ops += (uint64_t)(end - begin);

  /* Price every bin boundary; the parent's area is the same for all, so it is left out. */
  int best_axis = -1, best_bin = -1;
  float best_cost = FLT_MAX;
  for (int axis = 0; axis < 3; axis++) {
    if (scale[axis] == 0.0f) continue;
    float right_area[TOP_MAX_BINS];
    int right_count[TOP_MAX_BINS];
    box acc = box_empty();
    int n = 0;
    for (int k = bins - 1; k > 0; k--) {
      box_grow(&acc, &bin_box[axis][k]);
      n += count[axis][k];
      right_area[k] = box_area(&acc), right_count[k] = n;
    }
    acc = box_empty(), n = 0;
    for (int k = 0; k < bins - 1; k++) {
      box_grow(&acc, &bin_box[axis][k]);
      n += count[axis][k];
      if (n == 0 || right_count[k + 1] == 0) continue;
      float cost = box_area(&acc) * n + right_area[k + 1] * right_count[k + 1];
      if (cost < best_cost) best_axis = axis, best_bin = k, best_cost = cost;
    }
  }
  if (best_axis < 0) return begin + (end - begin) / 2;

  /* Move the clusters of bins [0, best_bin] to the front. */
  int i = begin, j = end - 1;
  while (i <= j) {
    int c = index[i];
    if (bin_of(b->clusters[c].centroid[best_axis], cbounds.lo[best_axis], scale[best_axis], bins) <= best_bin) {
      i++;
    } else {
      index[i] = index[j];
      index[j--] = c;
    }
  }
  b->bvh->sort_ops += (uint64_t)(end - begin);
  return i;
}

/* Builds the tree over cluster_index[begin, end), giving each cluster its place in leaf order
 * as the depth-first walk reaches it, so that leaves come in the order of their triangles. */
static void build_top(builder *b, int begin, int end, int depth, child *out) {
  lt__bvh *bvh = b->bvh;

  /* One cluster: its Karras hierarchy takes this place in the tree. */
  if (end - begin == 1) {
    cluster *c = &b->clusters[b->cluster_index[begin]];
    c->out = b->next_out;
    b->next_out += c->end - c->begin;
    build_range(b, c->begin, c->end - 1, c->out - c->begin, depth, out);
    return;
  }
  if (depth > bvh->max_depth) bvh->max_depth = depth;

  /* At the depth bound the remaining clusters become one leaf, laid out side by side. */
  if (depth >= b->depth_limit - 1) {
    out->bounds = box_empty(), out->link = b->next_out;
    for (int i = begin; i < end; i++) {
      cluster *c = &b->clusters[b->cluster_index[i]];
      c->out = b->next_out;
      b->next_out += c->end - c->begin;
      box_grow(&out->bounds, &c->bounds);
    }
    out->count = b->next_out - out->link;
    bvh->leaf_count++;
    bvh->sah_cost += (double)b->config->intersection_cost * out->count * box_area(&out->bounds);
    return;
  }

  /* Inner node over two groups of clusters. */
  int mid = split_clusters(b, begin, end);
  int node = bvh->node_count++;
  child left, right;
  build_top(b, begin, mid, depth + 1, &left);
  build_top(b, mid, end, depth + 1, &right);
  set_child(&bvh->nodes[node], 0, &left);
  set_child(&bvh->nodes[node], 1, &right);
  out->bounds = left.bounds;
  box_grow(&out->bounds, &right.bounds);
  out->link = node, out->count = 0;
  bvh->sah_cost += (double)b->config->traversal_cost * box_area(&out->bounds);
}

/* ---- Entry points ---- */

/* Working arrays of one build. */
typedef struct scratch {
  box *prim_box;   /* per triangle, in triangle order */
  box *sorted_box; /* per triangle, in key order */
  uint64_t *keys, *tmp;
  cluster *clusters;
  int *cluster_index;
} scratch;

/* Builds into out, whose arrays are allocated for n triangles. */
static void build_all(const float *tris, size_t n, const lt__sah_config *config, int depth_limit, scratch *s,
                      lt__bvh *out) {
  /* Triangle boxes, and the bounds of their centroids. */
  box cbounds = box_empty();
  for (size_t i = 0; i < n; i++) {
    const float *t = tris + 9 * i;
    box *pb = &s->prim_box[i];
    for (int k = 0; k < 3; k++) {
      pb->lo[k] = min_f(t[k], min_f(t[3 + k], t[6 + k]));
      pb->hi[k] = max_f(t[k], max_f(t[3 + k], t[6 + k]));
      float c = 0.5f * (pb->lo[k] + pb->hi[k]);
      cbounds.lo[k] = c < cbounds.lo[k] ? c : cbounds.lo[k];
      cbounds.hi[k] = c > cbounds.hi[k] ? c : cbounds.hi[k];
    }
  }

  /* 30-bit Morton codes of the centroids, normalised to the centroid bounds. */
  float scale[3];
  for (int k = 0; k < 3; k++) {
    float extent = cbounds.hi[k] - cbounds.lo[k];
    scale[k] = extent > 0.0f ? (float)(1 << AXIS_BITS) / extent : 0.0f;
  }
  for (size_t i = 0; i < n; i++) {
    const box *pb = &s->prim_box[i];
    uint32_t q[3];
    for (int k = 0; k < 3; k++) q[k] = quantize(0.5f * (pb->lo[k] + pb->hi[k]), cbounds.lo[k], scale[k]);
    uint32_t code = spread_bits(q[0]) << 2 | spread_bits(q[1]) << 1 | spread_bits(q[2]);
    s->keys[i] = (uint64_t)code << 32 | (uint32_t)i;
  }

  /* Sort, and gather the boxes into key order. */
  const uint64_t *sorted = radix_sort(s->keys, s->tmp, n, &out->sort_ops);
  for (size_t i = 0; i < n; i++) s->sorted_box[i] = s->prim_box[(uint32_t)sorted[i]];

  /* Clusters: runs of keys with the same top CLUSTER_BITS of the code. */
  int cluster_count = 0;
  for (int i = 0; i < (int)n;) {
    uint32_t prefix = code_of(sorted[i]) >> (MORTON_BITS - CLUSTER_BITS);
    cluster *c = &s->clusters[cluster_count];
    c->begin = i, c->bounds = box_empty();
    for (; i < (int)n && code_of(sorted[i]) >> (MORTON_BITS - CLUSTER_BITS) == prefix; i++)
      box_grow(&c->bounds, &s->sorted_box[i]);
    c->end = i;
    for (int k = 0; k < 3; k++) c->centroid[k] = 0.5f * (c->bounds.lo[k] + c->bounds.hi[k]);
    s->cluster_index[cluster_count] = cluster_count;
    cluster_count++;
  }

  /* The tree: the SAH top, and a Karras hierarchy under each of its cluster leaves. LBVH leaves
   * are a quarter of the SAH bound (4 by default): nothing prices a leaf against a split here,
   * so small leaves keep the cost of a poor Morton split low, as in Karras's one-triangle leaves. */
  int leaf_size = config->max_leaf_size / 4 > 1 ? config->max_leaf_size / 4 : 1;
  int top_bins = config->bins < TOP_MAX_BINS ? config->bins : TOP_MAX_BINS;
  builder b = {config, leaf_size, top_bins, depth_limit, sorted, s->sorted_box, s->clusters, s->cluster_index, 0, out};
  child root;
  build_top(&b, 0, cluster_count, 0, &root);

  /* The root is always an inner node; a scene that is one leaf gets an empty sibling. */
  if (root.count > 0) {
    child empty = {box_empty(), -1, 0};
    out->node_count = 1;
    set_child(&out->nodes[0], 0, &root);
    set_child(&out->nodes[0], 1, &empty);
  }

  /* Triangles in leaf order, each carrying its number. */
  for (int c = 0; c < cluster_count; c++) {
    const cluster *cl = &s->clusters[c];
    for (int i = cl->begin; i < cl->end; i++) {
      uint32_t p = (uint32_t)sorted[i];
      const float *t = tris + 9 * (size_t)p;
      lt_tri *dst = &out->tris[cl->out + (i - cl->begin)];
      dst->v0 = (lt_float4){t[0], t[1], t[2], lt_int_as_float((int32_t)p)};
      dst->v1 = (lt_float4){t[3], t[4], t[5], 0.0f};
      dst->v2 = (lt_float4){t[6], t[7], t[8], 0.0f};
    }
  }
  out->tri_count = (int)n;
  float root_area = box_area(&root.bounds);
  out->sah_cost = root_area > 0.0f ? out->sah_cost / root_area : 0.0;
}

lt_status lt__bvh_build_lbvh_limited(const float *tris, size_t n, const lt__sah_config *config, int depth_limit,
                                     lt__bvh *out) {
  lt__sah_config defaults = lt__sah_config_default();
  if (!config) config = &defaults;
  if (!tris || !out || n == 0 || n > INT32_MAX / 2)
    return LT_ERROR_INVALID_ARGUMENT;
  if (config->bins < 2 || config->max_leaf_size < 1 || depth_limit < 2 || depth_limit > LT_BVH_MAX_DEPTH)
    return LT_ERROR_INVALID_ARGUMENT;

  /* Everything is allocated up front: n inner nodes are enough, as every inner node but the
   * single-leaf root has two non-empty children. */
  memset(out, 0, sizeof *out);
  scratch s = {malloc(n * sizeof(box)),
               malloc(n * sizeof(box)),
               malloc(n * sizeof(uint64_t)),
               malloc(n * sizeof(uint64_t)),
               malloc(((size_t)1 << CLUSTER_BITS) * sizeof(cluster)),
               malloc(((size_t)1 << CLUSTER_BITS) * sizeof(int))};
  out->nodes = calloc(n, sizeof *out->nodes);
  out->tris = malloc(n * sizeof *out->tris);
  lt_status status = LT_OK;
  if (s.prim_box && s.sorted_box && s.keys && s.tmp && s.clusters && s.cluster_index && out->nodes && out->tris) {
    build_all(tris, n, config, depth_limit, &s, out);
  } else {
    lt__bvh_free(out);
    status = LT_ERROR_OUT_OF_MEMORY;
  }
  free(s.prim_box), free(s.sorted_box), free(s.keys), free(s.tmp), free(s.clusters), free(s.cluster_index);
  return status;
}

lt_status lt__bvh_build_lbvh(const float *tris, size_t n, const lt__sah_config *config, lt__bvh *out) {
  return lt__bvh_build_lbvh_limited(tris, n, config, LT_BVH_MAX_DEPTH, out);
}
