/* The binary BVH node: its layout, and every way to make or read one. Host builders (the
 * LBVH, the sweep builder), the pool's node tasks and the one traversal body all go through
 * this header, so the link encoding is written down once.
 *
 * A node holds the boxes of both children, so that a visit tests two boxes with one fetch
 * (Aila and Laine 2009). A child is one of four kinds, told by its link and count:
 *
 *   inner     link >= 0 (a node index), count 0
 *   leaf      count > 0: `count` references from position `link`
 *   empty     link == -1, count 0 (the super-root's right child, a root that is one leaf)
 *   unbuilt   link <= -2, count 0: the pool task in slot -2 - link will build it
 *   wide      link >= 0, count < 0: an inner node whose subtree, as far as it was built,
 *             also exists as an 8-wide tree (device/bvh8_node.h), its children in the lanes of
 *             wide node -1 - count (lt_bvh_wide_node); its unbuilt links are exit lanes that
 *             lead back here. Native backend only, on trees built on demand: the host
 *             collapses the built part between launches (runtime/bvh_wide_host.c) and marks
 *             the root's link. lt_bvh_child_kind calls it inner, so a reader that knows no
 *             wide trees follows `link` into the binary subtree, which stays as it was.
 *
 * Two leaf formats, on purpose. A tree built on the host copies its triangles into leaf order
 * (lt_tri, 48 bytes each, the triangle's number in v0.w): a leaf is one contiguous read, and
 * the copy is one pass at the end of a build nobody waits on mid-way. A tree built through the
 * pool partitions 4-byte triangle numbers in place, level by level, and traversal reads the
 * scene's vertices through them: copying 48-byte triangles at every level would cost the
 * build more than the indirection costs the trace. The view (traversal/bvh_view.h) says which.
 *
 * A link is addressed as node * 2 + side. Links that traversal may read while a task replaces
 * them are read and written with atomics, the count before the link on writing and after it on
 * reading, with a fence between, so that a reader never sees half a link. */
#ifndef LT_DEVICE_BVH_NODE_H
#define LT_DEVICE_BVH_NODE_H

#include "device/box.h"
#include "device/types.h"

/* The deepest a BVH may be, so that a traversal stack of this many entries never overflows:
 * every builder makes a leaf at this depth whatever its size. */
#define LT_BVH_MAX_DEPTH 64
#define LT_BVH_STACK_SIZE LT_BVH_MAX_DEPTH

typedef struct lt_bvh_node {
  lt_float4 left_xy;  /* 16 bytes: left child lo.x, hi.x, lo.y, hi.y */
  lt_float4 right_xy; /* 16 bytes: right child lo.x, hi.x, lo.y, hi.y */
  lt_float4 lr_z;     /* 16 bytes: left lo.z, hi.z, right lo.z, hi.z */
  lt_i32 link[4];     /* 16 bytes: left link, right link, left count, right count (an array,
                         not an int4, so that single fields can be used atomically) */
} lt_bvh_node;

#ifndef __OPENCL_VERSION__
_Static_assert(sizeof(lt_bvh_node) == 64, "lt_bvh_node is 64 bytes on both sides");
_Static_assert(_Alignof(lt_bvh_node) == 16, "lt_bvh_node is 16-byte aligned on both sides");
#endif

/* What a child link holds. */
#define LT_CHILD_EMPTY 0
#define LT_CHILD_INNER 1
#define LT_CHILD_LEAF 2
#define LT_CHILD_UNBUILT 3
#define LT_CHILD_WIDE 4 /* only where a traversal asks lt_bvh_child_is_wide */

#define LT_BVH_LINK_EMPTY (-1)

/* The link of a child that the task in `slot` will build, and back. */
LT_DEVICE lt_i32 lt_bvh_unbuilt_link(lt_i32 slot) { return -2 - slot; }
LT_DEVICE lt_i32 lt_bvh_unbuilt_slot(lt_i32 link) { return -2 - link; }

/* The count of a wide child whose 8-wide tree starts at wide node `wide`, and back. */
LT_DEVICE lt_i32 lt_bvh_wide_count(lt_i32 wide) { return -1 - wide; }
LT_DEVICE lt_i32 lt_bvh_wide_node(lt_i32 count) { return -1 - count; }

/* Whether an inner child (by lt_bvh_child_kind) is also a wide one. */
LT_DEVICE int lt_bvh_child_is_wide(lt_i32 count) { return count < 0; }

/* The kind of a child from its link and count (a wide child is an inner one here). */
LT_DEVICE int lt_bvh_child_kind(lt_i32 link, lt_i32 count) {
  if (link <= -2) return LT_CHILD_UNBUILT;
  if (count > 0) return LT_CHILD_LEAF;
  return link >= 0 ? LT_CHILD_INNER : LT_CHILD_EMPTY;
}

/* A child's box as two corners. */
LT_DEVICE void lt_bvh_child_box(const lt_bvh_node *n, int side, float lo[3], float hi[3]) {
  lt_float4 xy = side ? n->right_xy : n->left_xy, z = n->lr_z;
  lo[0] = xy.x, hi[0] = xy.y, lo[1] = xy.z, hi[1] = xy.w;
  lo[2] = side ? z.z : z.x, hi[2] = side ? z.w : z.y;
}

/* Writes the box of child `side` (plain stores: a node's boxes never change once linked). */
LT_DEVICE void lt_bvh_write_box(LT_GLOBAL lt_bvh_node *node, int side, const lt_box *x) {
  if (side == 0) {
    node->left_xy = lt_make_float4(x->lo[0], x->hi[0], x->lo[1], x->hi[1]);
    node->lr_z.x = x->lo[2], node->lr_z.y = x->hi[2];
  } else {
    node->right_xy = lt_make_float4(x->lo[0], x->hi[0], x->lo[1], x->hi[1]);
    node->lr_z.z = x->lo[2], node->lr_z.w = x->hi[2];
  }
}

/* Writes child `side` of a node that no other work-item can see yet (a host builder's array,
 * or a node a task has just allocated): plain stores. */
LT_DEVICE void lt_bvh_write_child(LT_GLOBAL lt_bvh_node *node, int side, const lt_box *x, lt_i32 link, lt_i32 count) {
  lt_bvh_write_box(node, side, x);
  node->link[side] = link, node->link[2 + side] = count;
}

/* The same for a node in a tree that traversal reads while it grows: the count and then the
 * link atomically (the node is published later, by the link to it, behind a fence). */
LT_DEVICE void lt_bvh_set_child(LT_GLOBAL lt_bvh_node *node, int side, const lt_box *x, lt_i32 link, lt_i32 count) {
  lt_bvh_write_box(node, side, x);
  lt_atomic_store_i32(&node->link[2 + side], count);
  lt_atomic_store_i32(&node->link[side], link);
}

/* Replaces the unbuilt link at `address` (node * 2 + side) with a built one: the count first,
 * then the link, so that a traversal reading the link and then the count never sees half. */
LT_DEVICE void lt_bvh_publish_link(LT_GLOBAL lt_bvh_node *nodes, lt_i32 address, lt_i32 link, lt_i32 count) {
  LT_GLOBAL lt_bvh_node *node = &nodes[address >> 1];
  int side = address & 1;
  if (count > 0) lt_atomic_store_i32(&node->link[2 + side], count);
  lt_fence();
  lt_atomic_store_i32(&node->link[side], link);
}

/* Reads child `side` of node n of a tree that may still grow: the link first, with acquire
 * order, then the count, which the publisher stored before the link; returns the child's kind.
 * (A load and a full fence here cost a locked instruction per link on x86: about 40% of the
 * on-demand kernel's samples.) */
LT_DEVICE int lt_bvh_read_child_acquire(LT_GLOBAL const lt_bvh_node *n, int side, lt_i32 *link, lt_i32 *count) {
  *link = lt_atomic_load_acquire_i32(&n->link[side]);
  *count = lt_atomic_load_relaxed_i32(&n->link[2 + side]);
  return lt_bvh_child_kind(*link, *count);
}

/* The same, addressed as node * 2 + side (a link a suspended ray re-reads). */
LT_DEVICE int lt_bvh_read_link(LT_GLOBAL const lt_bvh_node *nodes, lt_i32 address, lt_i32 *link, lt_i32 *count) {
  return lt_bvh_read_child_acquire(&nodes[address >> 1], address & 1, link, count);
}

/* Reads child `side` of a node of a finished tree (plain loads); returns its kind. */
LT_DEVICE int lt_bvh_child(LT_GLOBAL const lt_bvh_node *n, int side, lt_i32 *link, lt_i32 *count) {
  *link = n->link[side], *count = n->link[2 + side];
  return lt_bvh_child_kind(*link, *count);
}

#endif
