/* Collapse of a binary BVH into a 4-ary one (Dammertz, Hanika and Keller, "Shallow Bounding
 * Volume Hierarchies for Fast SIMD Ray Tracing of Incoherent Rays", EGSR 2008, section 3):
 * siblings stored together as one node (Bogolepov and Ulyanov), in depth-first order. */
#include "builders/host/qbvh_collapse.h"

#include <stdlib.h>
#include <string.h>

typedef struct collapser {
  const lt__bvh *bvh;
  lt__qbvh *out; /* NULL while counting */
  int next;      /* nodes handed out */
} collapser;

static lt__bvh_child binary_child(const lt__bvh *bvh, int node, int side) {
  lt__bvh_child c;
  const lt_bvh_node *n = &bvh->nodes[node];
  lt_bvh_child_box(n, side, c.box.lo, c.box.hi);
  c.link = n->link[side], c.count = n->link[2 + side], c.address = node * 2 + side;
  return c;
}

int lt__bvh_child_is_inner(const lt__bvh_child *c) { return c->count == 0 && c->link >= 0; }

int lt__bvh_open_children(const lt__bvh *bvh, int link, int width, lt__bvh_child *kids) {
  int n = 0;
  for (int side = 0; side < 2; side++) {
    lt__bvh_child c = binary_child(bvh, link, side);
    if (c.count > 0 || c.link != LT_BVH_LINK_EMPTY) kids[n++] = c;
  }
  while (n < width) {
    /* The inner child of largest area is the likeliest to be entered: open it. */
    int open = -1;
    float best = -1.0f;
    for (int i = 0; i < n; i++)
      if (lt__bvh_child_is_inner(&kids[i]) && lt_box_area(&kids[i].box) > best) best = lt_box_area(&kids[i].box), open = i;
    if (open < 0) break;
    int node = kids[open].link;
    kids[open] = binary_child(bvh, node, 0);
    kids[n++] = binary_child(bvh, node, 1);
  }
  return n;
}

/* Makes the node holding the children of binary inner node `link` at `depth` (node 0 is at
 * depth 1), then its inner children's nodes; returns its index and puts its children. */
static int collapse(collapser *c, int link, int depth, int *children) {
  lt__bvh_child kids[4];
  int n = lt__bvh_open_children(c->bvh, link, 4, kids);
  *children = n;
  int at = c->next++;
  if (c->out && depth > c->out->max_depth) c->out->max_depth = depth;
  for (int lane = 0; lane < 4; lane++) {
    if (lane >= n) {
      lt_box empty = lt_box_empty();
      if (c->out) lt_qbvh_write_child(&c->out->nodes[at], lane, &empty, -1, 0);
      continue;
    }
    if (!lt__bvh_child_is_inner(&kids[lane])) {
      if (c->out) lt_qbvh_write_child(&c->out->nodes[at], lane, &kids[lane].box, kids[lane].link, kids[lane].count);
      if (c->out) c->out->leaf_count++;
      continue;
    }
    /* Depth first: a node's first inner child's node follows it in memory. */
    int grand;
    int below = collapse(c, kids[lane].link, depth + 1, &grand);
    if (c->out) lt_qbvh_write_child(&c->out->nodes[at], lane, &kids[lane].box, below, -grand);
  }
  return at;
}

int lt__qbvh_count_nodes(const lt__bvh *bvh) {
  collapser c = {bvh, NULL, 0};
  int children;
  collapse(&c, 0, 1, &children);
  return c.next;
}

lt_status lt__qbvh_collapse(const lt__bvh *bvh, int max_nodes, lt__qbvh *out) {
  memset(out, 0, sizeof *out);
  if (!bvh || !bvh->nodes || bvh->node_count < 1) return LT_ERROR_INVALID_ARGUMENT;
  int count = lt__qbvh_count_nodes(bvh);
  if (count > max_nodes || count > LT_QBVH_MAX_NODES) return LT_ERROR_UNSUPPORTED;

  /* A node is 128 bytes: aligned to cache lines, one visit reads two whole lines. */
  size_t bytes = ((size_t)count * sizeof(lt_qbvh_node) + 63) / 64 * 64;
  out->nodes = aligned_alloc(64, bytes);
  if (!out->nodes) return LT_ERROR_OUT_OF_MEMORY;
  memset(out->nodes, 0, bytes);
  collapser c = {bvh, out, 0};
  int children;
  collapse(&c, 0, 1, &children);
  out->node_count = c.next;
  return LT_OK;
}

void lt__qbvh_free(lt__qbvh *qbvh) {
  free(qbvh->nodes);
  memset(qbvh, 0, sizeof *qbvh);
}
