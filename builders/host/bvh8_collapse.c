/* Collapse of a binary BVH into an 8-ary one (Dammertz, Hanika and Keller, "Shallow Bounding
 * Volume Hierarchies for Fast SIMD Ray Tracing of Incoherent Rays", EGSR 2008, section 3, at
 * the width of an AVX2 register): siblings stored together, nodes in depth-first order. */
#include "builders/host/bvh8_collapse.h"

#include <stdlib.h>
#include <string.h>

#include "builders/host/qbvh_collapse.h"

typedef struct collapser {
  const lt__bvh *bvh;
  lt__bvh8 *out; /* NULL while counting */
  int next;      /* nodes handed out */
  int slots;     /* triangle slots handed out */
} collapser;

/* Copies a leaf's `count` triangles from position `first` of the binary tree's to slot `at`
 * (a multiple of four) of the tree's own, pads to the next multiple of four with copies of its
 * first triangle, and writes the blocks. */
static void write_leaf(const lt__bvh *bvh, int first, int count, lt__bvh8 *out, int at) {
  for (int i = 0; i < (count + 3) / 4 * 4; i++) {
    lt_tri t = bvh->tris[first + (i < count ? i : 0)];
    out->tris[at + i] = t;
    lt_tri4 *b = &out->blocks[(at + i) / 4];
    const lt_float4 *v[3] = {&t.v0, &t.v1, &t.v2};
    for (int j = 0; j < 3; j++)
      b->v[3 * j][i % 4] = v[j]->x, b->v[3 * j + 1][i % 4] = v[j]->y, b->v[3 * j + 2][i % 4] = v[j]->z;
  }
}

/* Makes the node holding the children of binary inner node `link` at `depth` (node 0 is at
 * depth 1), then its inner children's nodes; returns its index and puts its children. */
static int collapse(collapser *c, int link, int depth, int *children) {
  lt__bvh_child kids[LT_BVH8_WIDTH];
  int n = lt__bvh_open_children(c->bvh, link, LT_BVH8_WIDTH, kids);
  *children = n;
  int at = c->next++;
  if (c->out && depth > c->out->max_depth) c->out->max_depth = depth;
  for (int lane = 0; lane < LT_BVH8_WIDTH; lane++) {
    /* Empty lanes get empty boxes and count 0; a leaf's triangles go to the next slots. */
    if (lane >= n || !lt__bvh_child_is_inner(&kids[lane])) {
      int slot = c->slots;
      if (lane < n) c->slots += (kids[lane].count + 3) / 4 * 4;
      if (!c->out) continue;
      if (lane >= n) {
        lt_box empty = lt_box_empty();
        lt_bvh8_write_child(&c->out->nodes[at], lane, &empty, -1, 0);
        continue;
      }
      write_leaf(c->bvh, kids[lane].link, kids[lane].count, c->out, slot);
      lt_bvh8_write_child(&c->out->nodes[at], lane, &kids[lane].box, slot, kids[lane].count);
      c->out->leaf_count++;
      continue;
    }
    /* Depth first: a node's first inner child's node follows it in memory. */
    int grand;
    int below = collapse(c, kids[lane].link, depth + 1, &grand);
    if (c->out) lt_bvh8_write_child(&c->out->nodes[at], lane, &kids[lane].box, below, -grand);
  }
  return at;
}

lt_status lt__bvh8_collapse(const lt__bvh *bvh, lt__bvh8 *out) {
  memset(out, 0, sizeof *out);
  if (!bvh || !bvh->nodes || bvh->node_count < 1) return LT_ERROR_INVALID_ARGUMENT;
  collapser counting = {bvh, NULL, 0, 0};
  int children;
  collapse(&counting, 0, 1, &children);

  /* A node is 256 bytes: aligned to cache lines, one visit reads four whole lines. */
  size_t bytes = (size_t)counting.next * sizeof(lt_bvh8_node);
  size_t slots = (size_t)counting.slots > 0 ? (size_t)counting.slots : 4;
  out->nodes = aligned_alloc(64, bytes);
  out->tris = aligned_alloc(64, (slots * sizeof(lt_tri) + 63) / 64 * 64);
  out->blocks = aligned_alloc(64, (slots / 4 * sizeof(lt_tri4) + 63) / 64 * 64);
  if (!out->nodes || !out->tris || !out->blocks) return lt__bvh8_free(out), LT_ERROR_OUT_OF_MEMORY;
  memset(out->nodes, 0, bytes);
  collapser c = {bvh, out, 0, 0};
  collapse(&c, 0, 1, &children);
  out->node_count = c.next;
  out->tri_slots = c.slots;
  return LT_OK;
}

void lt__bvh8_free(lt__bvh8 *bvh8) {
  free(bvh8->nodes);
  free(bvh8->tris);
  free(bvh8->blocks);
  memset(bvh8, 0, sizeof *bvh8);
}
