/* The kd-tree node: its layout, and every way to make or read one. The pool's node tasks
 * (builders/kd_task.h) and the traversals (traversal/kd_traverse.h) go through this header, so
 * the link encoding is written down once.
 *
 * A node is inner (an axis and a split plane, two child links) or a leaf (its references, a
 * range of the reference heap). A child link is one word:
 *
 *   node      link >= 0: the index of the child node (inner or leaf)
 *   empty     link == -1: a cell with nothing in it (no node is made for it)
 *   unbuilt   link <= -2: the pool task in slot -2 - link will build it
 *
 * Node 0 is the super-root: its link 0 is the tree's root, its link 1 is empty, so that the
 * root, too, is reached through a link that a task replaces. A link is addressed as
 * node * 2 + side. A task writes its node with plain stores, then a fence, then stores the link
 * to it atomically: a traversal that reads a built link reads a whole node. */
#ifndef LT_DEVICE_KD_NODE_H
#define LT_DEVICE_KD_NODE_H

#include "device/types.h"

/* The deepest a kd-tree may be: the depth limit 1.2 * log2(N) + 2 of the on-demand paper
 * (section 3.5) is 40 for 2^31 triangles, and every builder makes a leaf at this depth
 * whatever it holds, so a traversal stack of this many entries never overflows. */
#define LT_KD_MAX_DEPTH 44
#define LT_KD_STACK_SIZE (LT_KD_MAX_DEPTH + 1)

/* The traversals a kernel may run (traversal/kd_traverse.h, traversal/kd_stackless.h). */
#define LT_KD_TRAVERSE_STACK 0
#define LT_KD_TRAVERSE_RESTART 1
#define LT_KD_TRAVERSE_BACKTRACK 2

#define LT_KD_LEAF_AXIS 3
#define LT_KD_LINK_EMPTY (-1)

typedef struct lt_kd_node {
  lt_i32 link[2]; /* 8 bytes: inner: the children's links; leaf: link[0] is the first reference */
  float split;    /* 4 bytes: inner: the plane's coordinate on its axis */
  lt_i32 meta;    /* 4 bytes: axis 0-2 for an inner node; a leaf: LT_KD_LEAF_AXIS | count << 2 */
} lt_kd_node;

#ifndef __OPENCL_VERSION__
_Static_assert(sizeof(lt_kd_node) == 16, "lt_kd_node is 16 bytes on both sides");
#endif

/* The link of a child that the task in `slot` will build, and back. */
LT_DEVICE lt_i32 lt_kd_unbuilt_link(lt_i32 slot) { return -2 - slot; }
LT_DEVICE lt_i32 lt_kd_unbuilt_slot(lt_i32 link) { return -2 - link; }

/* Writes an inner node or a leaf that no other work-item can see yet (plain stores). */
LT_DEVICE void lt_kd_write_inner(LT_GLOBAL lt_kd_node *n, int axis, float split, lt_i32 left, lt_i32 right) {
  n->link[0] = left, n->link[1] = right, n->split = split, n->meta = axis;
}
LT_DEVICE void lt_kd_write_leaf(LT_GLOBAL lt_kd_node *n, lt_i32 first, lt_i32 count) {
  n->link[0] = first, n->link[1] = 0, n->split = 0.0f, n->meta = LT_KD_LEAF_AXIS | count << 2;
}

LT_DEVICE int lt_kd_axis(lt_i32 meta) { return meta & 3; }
LT_DEVICE lt_i32 lt_kd_leaf_count(lt_i32 meta) { return meta >> 2; }

/* Replaces the link at `address` once the node it points to is written: a fence, then the
 * link, atomically. */
LT_DEVICE void lt_kd_publish_link(LT_GLOBAL lt_kd_node *nodes, lt_i32 address, lt_i32 link) {
  lt_fence();
  lt_atomic_store_i32(&nodes[address >> 1].link[address & 1], link);
}

/* Sets a link of a node not yet published (its own link comes later, behind a fence). */
LT_DEVICE void lt_kd_set_link(LT_GLOBAL lt_kd_node *nodes, lt_i32 address, lt_i32 link) {
  lt_atomic_store_i32(&nodes[address >> 1].link[address & 1], link);
}

/* Reads the link at `address` of a tree that may still grow, with acquire order, so that the
 * node it names is read as written. */
LT_DEVICE lt_i32 lt_kd_read_link(LT_GLOBAL const lt_kd_node *nodes, lt_i32 address) {
  return lt_atomic_load_acquire_i32(&nodes[address >> 1].link[address & 1]);
}

#endif
