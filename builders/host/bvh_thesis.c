/* The Kay-Kajiya and Goldsmith-Salmon builders (builders/host/bvh_thesis.h). */
#include "builders/host/bvh_thesis.h"

#include <stdlib.h>
#include <string.h>

/* Deeper than any tree needs: below it, a Kay-Kajiya node becomes a leaf whatever its size. */
#define KK_MAX_DEPTH 256

static lt_box tri_box(const float *tris, int t, float centroid[3]) {
  lt_box b;
  float c[3];
  lt_tri_bounds(tris + 9 * (size_t)t, &b, centroid ? centroid : c);
  return b;
}

static int new_node(lt__tree *t) {
  int at = t->node_count++;
  lt__tree_node *n = &t->nodes[at];
  n->box = lt_box_empty();
  n->first_child = n->next_sibling = -1;
  n->children = n->first = n->count = 0;
  return at;
}

/* Cost of the tree under `node`, not divided by anything (see lt__tree.cost). */
static double subtree_cost(const lt__tree *t, int node) {
  const lt__tree_node *n = &t->nodes[node];
  double area = lt_box_area(&n->box);
  if (n->count > 0) return area * n->count;
  double cost = area * n->children;
  for (int c = n->first_child; c >= 0; c = t->nodes[c].next_sibling) cost += subtree_cost(t, c);
  return cost;
}

static void finish_cost(lt__tree *t) {
  float root = t->root >= 0 ? lt_box_area(&t->nodes[t->root].box) : 0.0f;
  t->cost = root > 0.0f ? subtree_cost(t, t->root) / root : 0.0;
}

void lt__tree_free(lt__tree *tree) {
  free(tree->nodes);
  free(tree->index);
  memset(tree, 0, sizeof *tree);
  tree->root = -1;
}

/* ---- Kay-Kajiya ---- */

typedef struct kk {
  lt__tree *t;
  const float *tris;
  float *centroids; /* 3 per triangle */
  lt_box *boxes;
} kk;

/* Partitions index[begin, end) by centroid coordinate `axis` below `mid`; returns the split. */
static int partition(kk *b, int begin, int end, int axis, float mid) {
  int *index = b->t->index, i = begin, j = end - 1;
  while (i <= j) {
    if (b->centroids[3 * index[i] + axis] < mid) i++;
    else {
      int s = index[i];
      index[i] = index[j], index[j] = s;
      j--;
    }
  }
  return i;
}

static int longest_axis(const lt_box *box) {
  float d[3];
  for (int k = 0; k < 3; k++) d[k] = box->hi[k] - box->lo[k];
  return d[0] >= d[1] && d[0] >= d[2] ? 0 : d[1] >= d[2] ? 1 : 2;
}

static int kk_build(kk *b, int begin, int end, int depth) {
  lt__tree *t = b->t;
  int at = new_node(t);
  lt_box box = lt_box_empty(), centroids = lt_box_empty();
  for (int i = begin; i < end; i++) {
    int tri = t->index[i];
    lt_box_grow(&box, &b->boxes[tri]);
    const float *c = &b->centroids[3 * tri];
    lt_box p = {{c[0], c[1], c[2]}, {c[0], c[1], c[2]}};
    lt_box_grow(&centroids, &p);
  }
  t->nodes[at].box = box;
  int split = -1;
  if (end - begin > 1 && depth < KK_MAX_DEPTH) {
    /* The spatial median of the box's longest axis; where every centroid falls on one side of
     * it, the middle of the centroids' extent; where they all coincide there, halves. */
    int axis = longest_axis(&box);
    split = partition(b, begin, end, axis, 0.5f * (box.lo[axis] + box.hi[axis]));
    if (split == begin || split == end) {
      axis = longest_axis(&centroids);
      split = partition(b, begin, end, axis, 0.5f * (centroids.lo[axis] + centroids.hi[axis]));
    }
    if (split == begin || split == end)
      split = centroids.hi[axis] > centroids.lo[axis] ? begin + (end - begin) / 2 : -1;
  }
  if (split < 0) {
    t->nodes[at].first = begin, t->nodes[at].count = end - begin;
    return at;
  }
  int left = kk_build(b, begin, split, depth + 1);
  int right = kk_build(b, split, end, depth + 1);
  t->nodes[left].next_sibling = right;
  t->nodes[at].first_child = left, t->nodes[at].children = 2;
  return at;
}

lt_status lt__tree_build_kay_kajiya(const float *tris, size_t n, lt__tree *out) {
  memset(out, 0, sizeof *out);
  out->root = -1;
  kk b = {out, tris, malloc(3 * (n ? n : 1) * sizeof(float)), malloc((n ? n : 1) * sizeof(lt_box))};
  out->nodes = malloc(2 * (n ? n : 1) * sizeof *out->nodes);
  out->index = malloc((n ? n : 1) * sizeof *out->index);
  if (!b.centroids || !b.boxes || !out->nodes || !out->index) {
    free(b.centroids), free(b.boxes);
    lt__tree_free(out);
    return LT_ERROR_OUT_OF_MEMORY;
  }
  for (size_t i = 0; i < n; i++) {
    out->index[i] = (int)i;
    b.boxes[i] = tri_box(tris, (int)i, &b.centroids[3 * i]);
  }
  if (n > 0) out->root = kk_build(&b, 0, (int)n, 0);
  free(b.centroids), free(b.boxes);
  finish_cost(out);
  return LT_OK;
}

/* ---- Goldsmith-Salmon ---- */

static uint64_t next_random(uint64_t *s) {
  uint64_t z = (*s += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

static float union_area(const lt_box *a, const lt_box *b) {
  lt_box u = *a;
  lt_box_grow(&u, b);
  return lt_box_area(&u);
}

/* Inserts the triangle at position `pos` of t->index (box `box`). The cost of a tree is each
 * inner node's area times its children (their boxes are tested whenever it is entered) plus
 * each leaf's area (its triangle is tested). At an inner node, whose box grows to take the
 * triangle whatever happens below, the triangle may become a new child (one more test of the
 * node's box, plus its own leaf), pair with a leaf child under a new inner node (two tests of
 * the pair's box, plus its leaf), or go into an inner child, counted at what that child's
 * growth costs its own children plus the least any placement below could add. The cheapest
 * wins; going down repeats the choice there. */
static void gs_insert(lt__tree *t, int pos, const lt_box *box) {
  float self = lt_box_area(box);
  int leaf = new_node(t);
  t->nodes[leaf].box = *box, t->nodes[leaf].first = pos, t->nodes[leaf].count = 1;
  if (t->root < 0) {
    t->root = leaf;
    return;
  }
  int node = t->root;
  if (t->nodes[node].count > 0) {
    int top = new_node(t);
    lt__tree_node *r = &t->nodes[top];
    r->box = t->nodes[node].box;
    lt_box_grow(&r->box, box);
    r->first_child = node, r->children = 2;
    t->nodes[node].next_sibling = leaf;
    t->root = top;
    return;
  }
  for (;;) {
    lt__tree_node *n = &t->nodes[node];
    lt_box_grow(&n->box, box);
    double best = (double)lt_box_area(&n->box) + self;
    int choice = -1;
    for (int c = n->first_child; c >= 0; c = t->nodes[c].next_sibling) {
      const lt__tree_node *child = &t->nodes[c];
      float u = union_area(&child->box, box);
      double cost = child->count > 0 ? 2.0 * u + self
                                     : (double)(u - lt_box_area(&child->box)) * child->children + 2.0 * self;
      if (cost < best) best = cost, choice = c;
    }
    if (choice < 0) {
      t->nodes[leaf].next_sibling = n->first_child;
      n->first_child = leaf, n->children++;
      return;
    }
    if (t->nodes[choice].count > 0) {
      /* The leaf's place becomes an inner node over a copy of it and the new leaf. */
      int copy = new_node(t);
      lt__tree_node *old = &t->nodes[choice], *moved = &t->nodes[copy];
      moved->box = old->box, moved->first = old->first, moved->count = old->count;
      moved->next_sibling = leaf;
      lt_box_grow(&old->box, box);
      old->first_child = copy, old->children = 2, old->first = old->count = 0;
      return;
    }
    node = choice;
  }
}

lt_status lt__tree_build_goldsmith_salmon(const float *tris, size_t n, int orders, uint64_t seed, lt__tree *out) {
  memset(out, 0, sizeof *out);
  out->root = -1;
  size_t cap = n ? n : 1;
  lt_box *boxes = malloc(cap * sizeof *boxes);
  int *order = malloc(cap * sizeof *order);
  lt__tree trial = {malloc(2 * cap * sizeof(lt__tree_node)), 0, -1, malloc(cap * sizeof(int)), 0.0};
  if (!boxes || !order || !trial.nodes || !trial.index) {
    free(boxes), free(order), lt__tree_free(&trial);
    return LT_ERROR_OUT_OF_MEMORY;
  }
  for (size_t i = 0; i < n; i++) boxes[i] = tri_box(tris, (int)i, NULL), order[i] = (int)i;
  uint64_t state = seed;
  for (int o = 0; o < (orders > 0 ? orders : 1); o++) {
    for (size_t i = n; i > 1; i--) {
      size_t j = (size_t)(next_random(&state) % i);
      int s = order[i - 1];
      order[i - 1] = order[j], order[j] = s;
    }
    trial.node_count = 0, trial.root = -1;
    for (size_t i = 0; i < n; i++) {
      trial.index[i] = order[i];
      gs_insert(&trial, (int)i, &boxes[order[i]]);
    }
    finish_cost(&trial);
    if (out->root < 0 && o == 0) {
      *out = trial;
      trial.nodes = malloc(2 * cap * sizeof(lt__tree_node)), trial.index = malloc(cap * sizeof(int));
      if (!trial.nodes || !trial.index) break;
    } else if (trial.cost < out->cost) {
      lt__tree keep = *out;
      *out = trial;
      trial = keep;
    }
  }
  free(boxes), free(order);
  int failed = !trial.nodes || !trial.index;
  lt__tree_free(&trial);
  if (failed) {
    lt__tree_free(out);
    return LT_ERROR_OUT_OF_MEMORY;
  }
  return LT_OK;
}
