/* HLBVH_4 of the on-demand paper: Karras's split rule over sorted Morton codes (Karras, "Maximizing
 * Parallelism in the Construction of BVHs, Octrees, and k-d Trees", HPG 2012) inside clusters sharing
 * the top 12 code bits, binned SAH above them (HLBVH: Pantaleoni and Luebke 2010; pbrt-v3 4.3.3). */
#include "builders/host/lbvh.h"
#include "builders/host/morton.h"
#include "builders/host/radix_sort.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define AXIS_BITS   10
#define MORTON_BITS (3 * AXIS_BITS)
/* Four levels of the octree: the "_4" of HLBVH_4; at most 4096 clusters. */
#define CLUSTER_BITS 12
#define RADIX_PASSES ((MORTON_BITS + LT_RADIX_BITS - 1) / LT_RADIX_BITS)
/* Clusters are few, so the top is cheap even with the on-demand paper's 32 bins. */
#define TOP_MAX_BINS 32
/* Triangles per work item of the parallel loops over all triangles: a fixed size, so that the
 * tree (and the sort's stable order) is the same whatever the number of workers. */
#define CHUNK_TRIS (1 << 14)
/* Fewer triangles are built on the calling thread alone. */
#define PARALLEL_MIN_TRIS (2 * CHUNK_TRIS)

typedef struct box {
  float lo[3], hi[3];
} box;

/* A child link being built, with its box. */
typedef struct child {
  box bounds;
  int link, count;
} child;

/* What one serial piece of the build adds to the tree: nodes taken from its range, leaves, the
 * deepest level and its share of the SAH cost. */
typedef struct subtree {
  int next_node; /* next free entry of the node array */
  int leaves, max_depth;
  double cost;
} subtree;

/* The primitives of one cluster: a run of the sorted keys with the same top CLUSTER_BITS. */
typedef struct cluster {
  int begin, end; /* range of the sorted keys */
  int out;        /* first position in leaf order, given when the top build reaches it */
  box bounds;
  float centroid[3];
  /* Where the top hangs its Karras hierarchy: the top node and side (parent -1: the root), at
   * which depth; has_tree is 0 when the cluster went into one of the top's forced leaves. */
  int has_tree, parent, side, depth;
  int reserved; /* its first node in the build's node array, room for end - begin - 1 nodes */
  int first;    /* its first node in the final, compact node array */
  subtree tree;
  child root; /* its hierarchy's root, linked as in the build's node array */
} cluster;

typedef struct builder {
  const lt__sah_config *config;
  int leaf_size, top_bins, depth_limit;
  const uint64_t *keys; /* sorted: Morton code << 32 | triangle number */
  box *sorted_box;      /* triangle boxes in key order, so that leaves read them in sequence */
  cluster *clusters;
  int *cluster_index; /* cluster numbers, permuted by the top build */
  int cluster_count;
  int next_out;       /* next free position in leaf order */
  lt_bvh_node *nodes; /* the build's node array: the top's nodes, then every cluster's range */
  subtree top;
  uint64_t sort_ops;
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

/* Builds the subtree over the sorted keys [first, last] into st's node range; leaf order is key
 * order plus offset. */
static void build_range(const builder *b, subtree *st, int first, int last, int offset, int depth, child *out) {
  if (depth > st->max_depth) st->max_depth = depth;
  int n = last - first + 1;

  /* Small ranges are leaves, and whatever remains at the depth bound, whatever its size. */
  if (n <= b->leaf_size || depth >= b->depth_limit - 1) {
    box bounds = box_empty();
    for (int i = first; i <= last; i++) box_grow(&bounds, &b->sorted_box[i]);
    out->bounds = bounds, out->link = first + offset, out->count = n;
    st->leaves++;
    st->cost += (double)b->config->intersection_cost * n * box_area(&bounds);
    return;
  }

  /* Inner node: split by the codes, then take the exact box from the children. */
  int split = find_split(b->keys, first, last);
  int node = st->next_node++;
  child left, right;
  build_range(b, st, first, split, offset, depth + 1, &left);
  build_range(b, st, split + 1, last, offset, depth + 1, &right);
  set_child(&b->nodes[node], 0, &left);
  set_child(&b->nodes[node], 1, &right);
  out->bounds = left.bounds;
  box_grow(&out->bounds, &right.bounds);
  out->link = node, out->count = 0;
  st->cost += (double)b->config->traversal_cost * box_area(&out->bounds);
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
  b->sort_ops += (uint64_t)(end - begin);

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
  b->sort_ops += (uint64_t)(end - begin);
  return i;
}

/* Builds the tree over cluster_index[begin, end), giving each cluster its place in leaf order
 * as the depth-first walk reaches it, so that leaves come in the order of their triangles. A
 * cluster's own hierarchy is built later, in parallel with the others: the top only notes where
 * it hangs (parent node and side) and takes the cluster's box, which is its hierarchy's box. */
static void build_top(builder *b, int begin, int end, int depth, int parent, int side, child *out) {
  subtree *top = &b->top;

  /* One cluster: its Karras hierarchy takes this place in the tree. */
  if (end - begin == 1) {
    cluster *c = &b->clusters[b->cluster_index[begin]];
    c->out = b->next_out;
    b->next_out += c->end - c->begin;
    c->has_tree = 1, c->parent = parent, c->side = side, c->depth = depth;
    out->bounds = c->bounds, out->link = -1, out->count = 0; /* the link comes with the hierarchy */
    return;
  }
  if (depth > top->max_depth) top->max_depth = depth;

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
    top->leaves++;
    top->cost += (double)b->config->intersection_cost * out->count * box_area(&out->bounds);
    return;
  }

  /* Inner node over two groups of clusters. */
  int mid = split_clusters(b, begin, end);
  int node = top->next_node++;
  child left, right;
  build_top(b, begin, mid, depth + 1, node, 0, &left);
  build_top(b, mid, end, depth + 1, node, 1, &right);
  set_child(&b->nodes[node], 0, &left);
  set_child(&b->nodes[node], 1, &right);
  out->bounds = left.bounds;
  box_grow(&out->bounds, &right.bounds);
  out->link = node, out->count = 0;
  top->cost += (double)b->config->traversal_cost * box_area(&out->bounds);
}

/* ---- The phases of a build ---- */

/* Working arrays and the state one build's phases share. */
typedef struct lbvh_build {
  const float *tris;
  int n, chunks;
  box *prim_box;        /* per triangle, in triangle order */
  box *chunk_centroids; /* bounds of the centroids of each chunk's triangles */
  box cbounds;          /* bounds of all centroids */
  float scale[3];       /* Morton cells per unit length along each axis */
  uint64_t *keys, *tmp;
  uint32_t *digits; /* per chunk and radix bucket (builders/host/radix_sort.h) */
  int *order;       /* clusters by decreasing size: big hierarchies start first */
  builder b;
  lt__bvh *out;
} lbvh_build;

static int chunk_end(const lbvh_build *w, int chunk) {
  long long end = (long long)(chunk + 1) * CHUNK_TRIS;
  return end < w->n ? (int)end : w->n;
}

/* Triangle boxes, and the bounds of each chunk's centroids. */
static void boxes_chunk(void *ctx, int chunk) {
  lbvh_build *w = ctx;
  box cb = box_empty();
  for (int i = chunk * CHUNK_TRIS; i < chunk_end(w, chunk); i++) {
    const float *t = w->tris + 9 * (size_t)i;
    box *pb = &w->prim_box[i];
    for (int k = 0; k < 3; k++) {
      pb->lo[k] = min_f(t[k], min_f(t[3 + k], t[6 + k]));
      pb->hi[k] = max_f(t[k], max_f(t[3 + k], t[6 + k]));
      float c = 0.5f * (pb->lo[k] + pb->hi[k]);
      cb.lo[k] = c < cb.lo[k] ? c : cb.lo[k];
      cb.hi[k] = c > cb.hi[k] ? c : cb.hi[k];
    }
  }
  w->chunk_centroids[chunk] = cb;
}

/* 30-bit Morton codes of the centroids, normalised to the centroid bounds. */
static void codes_chunk(void *ctx, int chunk) {
  lbvh_build *w = ctx;
  for (int i = chunk * CHUNK_TRIS; i < chunk_end(w, chunk); i++) {
    const box *pb = &w->prim_box[i];
    float centre[3];
    for (int k = 0; k < 3; k++) centre[k] = 0.5f * (pb->lo[k] + pb->hi[k]);
    uint32_t code = lt__morton_code(centre, w->cbounds.lo, w->scale);
    w->keys[i] = (uint64_t)code << 32 | (uint32_t)i;
  }
}

static void gather_chunk(void *ctx, int chunk) {
  lbvh_build *w = ctx;
  for (int i = chunk * CHUNK_TRIS; i < chunk_end(w, chunk); i++) w->b.sorted_box[i] = w->prim_box[(uint32_t)w->keys[i]];
}

static void cluster_bounds(void *ctx, int c) {
  lbvh_build *w = ctx;
  cluster *cl = &w->b.clusters[c];
  cl->bounds = box_empty();
  for (int i = cl->begin; i < cl->end; i++) box_grow(&cl->bounds, &w->b.sorted_box[i]);
  for (int k = 0; k < 3; k++) cl->centroid[k] = 0.5f * (cl->bounds.lo[k] + cl->bounds.hi[k]);
}

/* A cluster's Karras hierarchy, in its reserved range of the node array. */
static void cluster_tree(void *ctx, int item) {
  lbvh_build *w = ctx;
  cluster *c = &w->b.clusters[w->order[item]];
  if (!c->has_tree) return;
  c->tree = (subtree){c->reserved, 0, 0, 0.0};
  build_range(&w->b, &c->tree, c->begin, c->end - 1, c->out - c->begin, c->depth, &c->root);
}

/* Moves the links between a cluster's nodes to where the nodes will be once compact; the nodes
 * themselves move afterwards, on one thread, as the ranges of neighbours may overlap. */
static void cluster_relink(void *ctx, int c) {
  lbvh_build *w = ctx;
  cluster *cl = &w->b.clusters[c];
  if (!cl->has_tree) return;
  int shift = cl->first - cl->reserved;
  for (int i = cl->reserved; i < cl->tree.next_node; i++) {
    lt_bvh_node *node = &w->b.nodes[i];
    for (int side = 0; side < 2; side++)
      if (node->link[2 + side] == 0 && node->link[side] >= 0) node->link[side] += shift;
  }
  if (cl->root.count == 0) cl->root.link += shift;
}

/* Triangles in leaf order, each carrying its number. */
static void cluster_triangles(void *ctx, int c) {
  lbvh_build *w = ctx;
  const cluster *cl = &w->b.clusters[c];
  for (int i = cl->begin; i < cl->end; i++) {
    uint32_t p = (uint32_t)w->keys[i];
    const float *t = w->tris + 9 * (size_t)p;
    lt_tri *dst = &w->out->tris[cl->out + (i - cl->begin)];
    dst->v0 = (lt_float4){t[0], t[1], t[2], lt_int_as_float((int32_t)p)};
    dst->v1 = (lt_float4){t[3], t[4], t[5], 0.0f};
    dst->v2 = (lt_float4){t[6], t[7], t[8], 0.0f};
  }
}

static int compare_u64(const void *a, const void *b) {
  uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
  return x < y ? -1 : x > y;
}

/* Clusters in the order their hierarchies are handed out: largest first, so that a big one does
 * not start last and keep one worker busy alone. */
static void order_clusters(lbvh_build *w, uint64_t *scratch) {
  int count = w->b.cluster_count;
  for (int c = 0; c < count; c++) {
    const cluster *cl = &w->b.clusters[c];
    scratch[c] = (uint64_t)(uint32_t)(INT32_MAX - (cl->end - cl->begin)) << 32 | (uint32_t)c;
  }
  qsort(scratch, (size_t)count, sizeof *scratch, compare_u64);
  for (int c = 0; c < count; c++) w->order[c] = (int)(uint32_t)scratch[c];
}

/* Builds into out, whose arrays are allocated for n triangles (and n nodes). */
static void build_all(lbvh_build *w, const lt__executor *ex) {
  lt__bvh *out = w->out;
  builder *b = &w->b;

  /* Triangle boxes and centroid bounds, then the Morton codes over those bounds. */
  lt__executor_for(ex, w->chunks, boxes_chunk, w);
  w->cbounds = box_empty();
  for (int c = 0; c < w->chunks; c++) box_grow(&w->cbounds, &w->chunk_centroids[c]);
  for (int k = 0; k < 3; k++) {
    float extent = w->cbounds.hi[k] - w->cbounds.lo[k];
    w->scale[k] = extent > 0.0f ? (float)(1 << AXIS_BITS) / extent : 0.0f;
  }
  lt__executor_for(ex, w->chunks, codes_chunk, w);

  /* Sort, and gather the boxes into key order. */
  lt__radix_sort sort = {w->keys, w->tmp, w->digits, w->n, CHUNK_TRIS, 0};
  out->sort_ops += (uint64_t)w->n * (uint64_t)lt__radix_sort_keys(&sort, RADIX_PASSES, 0, ex);
  w->keys = sort.keys, w->tmp = sort.tmp;
  b->keys = w->keys;
  lt__executor_for(ex, w->chunks, gather_chunk, w);

  /* Clusters: runs of keys with the same top CLUSTER_BITS of the code, each found by a binary
   * search for the first key past its prefix; their bounds in parallel. */
  const int prefix_shift = MORTON_BITS - CLUSTER_BITS;
  b->cluster_count = 0;
  for (int i = 0; i < w->n;) {
    uint32_t prefix = code_of(w->keys[i]) >> prefix_shift;
    int lo = i + 1, hi = w->n;
    while (lo < hi) {
      int mid = lo + (hi - lo) / 2;
      if (code_of(w->keys[mid]) >> prefix_shift > prefix)
        hi = mid;
      else
        lo = mid + 1;
    }
    b->clusters[b->cluster_count] = (cluster){.begin = i, .end = lo};
    b->cluster_index[b->cluster_count] = b->cluster_count;
    b->cluster_count++;
    i = lo;
  }
  lt__executor_for(ex, b->cluster_count, cluster_bounds, w);

  /* The SAH top over the clusters, on this thread: its nodes come first in the node array. */
  b->nodes = out->nodes;
  child root;
  build_top(b, 0, b->cluster_count, 0, -1, -1, &root);
  out->sort_ops += b->sort_ops;

  /* Every cluster's Karras hierarchy in parallel, each in a range reserved after the top's
   * nodes: a hierarchy over m triangles has at most m - 1 inner nodes. */
  int next = b->top.next_node;
  for (int c = 0; c < b->cluster_count; c++) {
    cluster *cl = &b->clusters[c];
    cl->reserved = next;
    if (cl->has_tree) next += cl->end - cl->begin - 1;
  }
  order_clusters(w, w->tmp);
  lt__executor_for(ex, b->cluster_count, cluster_tree, w);

  /* The compact node array: the top's nodes, then each cluster's, in cluster order. A cluster
   * only moves down, to where no later cluster's nodes are yet, so moving them in order is safe. */
  int total = b->top.next_node;
  for (int c = 0; c < b->cluster_count; c++) {
    cluster *cl = &b->clusters[c];
    cl->first = total;
    if (cl->has_tree) total += cl->tree.next_node - cl->reserved;
  }
  lt__executor_for(ex, b->cluster_count, cluster_relink, w);
  for (int c = 0; c < b->cluster_count; c++) {
    const cluster *cl = &b->clusters[c];
    if (cl->has_tree && cl->first != cl->reserved)
      memmove(&b->nodes[cl->first], &b->nodes[cl->reserved],
              (size_t)(cl->tree.next_node - cl->reserved) * sizeof *b->nodes);
  }
  out->node_count = total;

  /* Hang every hierarchy where the top left its place, and sum what the pieces counted. */
  out->leaf_count = b->top.leaves, out->max_depth = b->top.max_depth, out->sah_cost = b->top.cost;
  for (int c = 0; c < b->cluster_count; c++) {
    const cluster *cl = &b->clusters[c];
    if (!cl->has_tree) continue;
    if (cl->parent >= 0)
      set_child(&out->nodes[cl->parent], cl->side, &cl->root);
    else
      root = cl->root;
    out->leaf_count += cl->tree.leaves;
    out->max_depth = cl->tree.max_depth > out->max_depth ? cl->tree.max_depth : out->max_depth;
    out->sah_cost += cl->tree.cost;
  }

  /* The root is always an inner node; a scene that is one leaf gets an empty sibling. */
  if (root.count > 0) {
    child empty = {box_empty(), -1, 0};
    out->node_count = 1;
    set_child(&out->nodes[0], 0, &root);
    set_child(&out->nodes[0], 1, &empty);
  }

  lt__executor_for(ex, b->cluster_count, cluster_triangles, w);
  out->tri_count = w->n;
  float root_area = box_area(&root.bounds);
  out->sah_cost = root_area > 0.0f ? out->sah_cost / root_area : 0.0;
}

/* ---- Entry points ---- */

lt_status lt__bvh_build_lbvh_with(const float *tris, size_t n, const lt__sah_config *config, int depth_limit,
                                  const lt__executor *executor, lt__bvh *out) {
  lt__sah_config defaults = lt__sah_config_default();
  if (!config) config = &defaults;
  if (!tris || !out || n == 0 || n > INT32_MAX / 2) return LT_ERROR_INVALID_ARGUMENT;
  if (config->bins < 2 || config->max_leaf_size < 1 || depth_limit < 2 || depth_limit > LT_BVH_MAX_DEPTH)
    return LT_ERROR_INVALID_ARGUMENT;

  /* Everything is allocated up front. LBVH leaves are a quarter of the SAH bound (4 by
   * default): nothing prices a leaf against a split here, so small leaves keep the cost of a
   * poor Morton split low, as in Karras's one-triangle leaves. */
  memset(out, 0, sizeof *out);
  int chunks = (int)((n + CHUNK_TRIS - 1) / CHUNK_TRIS);
  lbvh_build w = {.tris = tris, .n = (int)n, .chunks = chunks, .out = out};
  w.b = (builder){.config = config,
                  .leaf_size = config->max_leaf_size / 4 > 1 ? config->max_leaf_size / 4 : 1,
                  .top_bins = config->bins < TOP_MAX_BINS ? config->bins : TOP_MAX_BINS,
                  .depth_limit = depth_limit};
  w.prim_box = malloc(n * sizeof(box));
  w.b.sorted_box = malloc(n * sizeof(box));
  w.chunk_centroids = malloc((size_t)chunks * sizeof(box));
  w.keys = malloc((n > (1 << CLUSTER_BITS) ? n : (1 << CLUSTER_BITS)) * sizeof(uint64_t));
  w.tmp = malloc((n > (1 << CLUSTER_BITS) ? n : (1 << CLUSTER_BITS)) * sizeof(uint64_t));
  w.digits = malloc((size_t)chunks * LT_RADIX_BUCKETS * sizeof(uint32_t));
  w.b.clusters = malloc(((size_t)1 << CLUSTER_BITS) * sizeof(cluster));
  w.b.cluster_index = malloc(((size_t)1 << CLUSTER_BITS) * sizeof(int));
  w.order = malloc(((size_t)1 << CLUSTER_BITS) * sizeof(int));
  out->nodes = malloc(n * sizeof *out->nodes); /* n nodes hold the top and every reserved range */
  out->tris = malloc(n * sizeof *out->tris);
  lt_status status = LT_OK;
  void *keys = w.keys, *tmp = w.tmp; /* the sort swaps them */
  if (w.prim_box && w.b.sorted_box && w.chunk_centroids && w.keys && w.tmp && w.digits && w.b.clusters &&
      w.b.cluster_index && w.order && out->nodes && out->tris) {
    /* Threads pay off only past a few chunks of triangles: starting them costs more than a
     * small scene's whole build. */
    build_all(&w, n >= PARALLEL_MIN_TRIS ? executor : NULL);
    /* Give back the node array's unused tail. A failure here is reported like every other
     * failed allocation of the build: one rule, whichever allocation it was. */
    lt_bvh_node *fit = realloc(out->nodes, (size_t)(out->node_count > 0 ? out->node_count : 1) * sizeof *out->nodes);
    if (fit) {
      out->nodes = fit;
    } else {
      lt__bvh_free(out);
      status = LT_ERROR_OUT_OF_MEMORY;
    }
  } else {
    lt__bvh_free(out);
    status = LT_ERROR_OUT_OF_MEMORY;
  }
  free(w.prim_box), free(w.b.sorted_box), free(w.chunk_centroids), free(keys), free(tmp), free(w.digits);
  free(w.b.clusters), free(w.b.cluster_index), free(w.order);
  return status;
}

lt_status lt__bvh_build_lbvh_limited(const float *tris, size_t n, const lt__sah_config *config, int depth_limit,
                                     lt__bvh *out) {
  return lt__bvh_build_lbvh_with(tris, n, config, depth_limit, NULL, out);
}

lt_status lt__bvh_build_lbvh(const float *tris, size_t n, const lt__sah_config *config, lt__bvh *out) {
  return lt__bvh_build_lbvh_limited(tris, n, config, LT_BVH_MAX_DEPTH, out);
}
