/* The escape-index BVH node (Thrane and Simonsen 2005, section 9.4): a BVH stored as its own
 * depth-first, left-to-right traversal order, so that a ray walks it without a stack. Each
 * node holds one box. A ray that meets a node's box goes on to the next node in the array (an
 * inner node's first child, or whatever follows a leaf); a ray that misses it, or is done
 * with a leaf, jumps to the node's escape index: the first node after its subtree. Escapes
 * only point forwards, so the walk ends when the index reaches the node count (the escape of
 * every node on the tree's right edge).
 *
 * A leaf's escape is always its own index plus one, so a leaf keeps its triangles there
 * instead (the thesis' "relative escape index equal to one"):
 *
 *   inner   count == 0: link is the escape index (1 to the node count)
 *   leaf    count > 0: `count` triangles (lt_tri, leaf order) from position `link`
 *
 * 32 bytes a node, the thesis' eight floats. The host makes the layout from a binary or n-ary
 * host tree (builders/host/escape_bvh.c); the traversal is traversal/escape_bvh_traverse.h. */
#ifndef LT_DEVICE_ESCAPE_BVH_NODE_H
#define LT_DEVICE_ESCAPE_BVH_NODE_H

#include "device/box.h"
#include "device/types.h"

typedef struct lt_escape_node {
  float lo[3];  /* 12 bytes: box lower corner */
  lt_i32 link;  /* 4 bytes: escape index (inner), first triangle position (leaf) */
  float hi[3];  /* 12 bytes: box upper corner */
  lt_i32 count; /* 4 bytes: 0 (inner), triangles (leaf) */
} lt_escape_node;

#ifndef __OPENCL_VERSION__
_Static_assert(sizeof(lt_escape_node) == 32, "lt_escape_node is 32 bytes on both sides");
#endif

/* The index a ray goes on to after node i when it misses the box or is done with the leaf. */
LT_DEVICE lt_i32 lt_escape_next(LT_GLOBAL const lt_escape_node *n, lt_i32 i) { return n->count > 0 ? i + 1 : n->link; }

#endif
