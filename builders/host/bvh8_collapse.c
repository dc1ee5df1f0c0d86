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
} collapser;

/* Makes the node holding the children of binary inner node `link` at `depth` (node 0 is at
 * depth 1), then its inner children's nodes; returns its index and puts its children. */
static int collapse(collapser *c, int link, int depth, int *children) {
  lt__bvh_child kids[LT_BVH8_WIDTH];
  int n = lt__bvh_open_children(c->bvh, link, LT_BVH8_WIDTH, kids);
  *children = n;
  int at = c->next++;
  if (c->out && depth > c->out->max_depth) c->out->max_depth = depth;
  for (int lane = 0; lane < LT_BVH8_WIDTH; lane++) {
    /* Empty lanes get empty boxes and count 0; leaves keep the binary tree's triangles. */
    if (lane >= n || !lt__bvh_child_is_inner(&kids[lane])) {
      if (!c->out) continue;
      lt_box empty = lt_box_empty();
      if (lane >= n)
        lt_bvh8_write_child(&c->out->nodes[at], lane, &empty, -1, 0);
      else
        lt_bvh8_write_child(&c->out->nodes[at], lane, &kids[lane].box, kids[lane].link, kids[lane].count);
      if (lane < n) c->out->leaf_count++;
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
  collapser counting = {bvh, NULL, 0};
  int children;
  collapse(&counting, 0, 1, &children);

  /* A node is 256 bytes: aligned to cache lines, one visit reads four whole lines. */
  size_t bytes = (size_t)counting.next * sizeof(lt_bvh8_node);
  out->nodes = aligned_alloc(64, bytes);
  if (!out->nodes) return LT_ERROR_OUT_OF_MEMORY;
  memset(out->nodes, 0, bytes);
  collapser c = {bvh, out, 0};
  collapse(&c, 0, 1, &children);
  out->node_count = c.next;
  return LT_OK;
}

void lt__bvh8_free(lt__bvh8 *bvh8) {
  free(bvh8->nodes);
  memset(bvh8, 0, sizeof *bvh8);
}
