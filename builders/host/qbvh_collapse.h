/* The binary SAH BVH collapsed into a QBVH (device/qbvh_node.h): Dammertz, Hanika and Keller
 * 2008, with the sibling layout of Bogolepov and Ulyanov. Host-only C. */
#ifndef LT_QBVH_COLLAPSE_H
#define LT_QBVH_COLLAPSE_H

#include "builders/host/bvh_sah.h"
#include "device/qbvh_node.h"

/* The nodes of a QBVH; its leaves point into the binary BVH's triangles (lt__bvh.tris), which
 * the collapse leaves where they are. */
typedef struct lt__qbvh {
  lt_qbvh_node *nodes; /* node 0 holds the root's children; 64-byte aligned */
  int node_count;
  int leaf_count;
  int max_depth; /* nodes on the longest path from node 0 to a leaf's node: the stack bound */
} lt__qbvh;

/* A child of a binary inner node as the collapses see it: its box and its link (count > 0 a
 * leaf of count triangles from link, count 0 and link >= 0 an inner node, link <= -2 unbuilt
 * in a tree still being built, else empty), and where that link is (node * 2 + side). */
typedef struct lt__bvh_child {
  lt_box box;
  int link, count;
  int address;
} lt__bvh_child;

int lt__bvh_child_is_inner(const lt__bvh_child *c);
/* The children of binary inner node `link`, opened while there are fewer than `width`: each
 * time the inner child of largest surface area gives way to its two children. Returns how
 * many there are (2 to width, fewer when all are leaves or empty links are dropped; unbuilt
 * ones are kept, never opened). Shared
 * by the 4-wide collapse and the 8-wide one (builders/host/bvh8_collapse.c). */
int lt__bvh_open_children(const lt__bvh *bvh, int link, int width, lt__bvh_child *kids);

/* Collapses a finished binary BVH (lt__bvh_build_sah, lt__bvh_build_lbvh): each node takes a
 * binary node's two children and opens the inner one of largest surface area while it has
 * fewer than four. LT_ERROR_UNSUPPORTED when the tree needs more than max_nodes nodes (at most
 * LT_QBVH_MAX_NODES, what a stack entry can name), LT_ERROR_OUT_OF_MEMORY on allocation. */
lt_status lt__qbvh_collapse(const lt__bvh *bvh, int max_nodes, lt__qbvh *out);
/* The nodes the collapse of bvh makes, without making them. */
int lt__qbvh_count_nodes(const lt__bvh *bvh);
void lt__qbvh_free(lt__qbvh *qbvh);

#endif
