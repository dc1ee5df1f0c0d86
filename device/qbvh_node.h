/* The QBVH node (Bogolepov and Ulyanov, "One approach to traversing QBVH on a GPU"): the
 * binary SAH BVH collapsed into a 4-ary tree whose siblings are stored together, and the
 * 32-bit stack entry of the paper's traversal. The collapse (builders/host/qbvh_collapse.c)
 * and the traversal (traversal/qbvh_traverse_body.h) both go through this header.
 *
 * A node is the group of up to four siblings, stored contiguously: their boxes in SoA form, so
 * that one ray meets all four boxes with one 4-lane test, and each child's link. A child of a
 * node is one of three kinds, told by its count:
 *
 *   inner   count < 0: its own children are the first -count lanes of node `first`
 *           (the paper's "first child plus count", 2 to 4 children)
 *   leaf    count > 0: `count` triangles (lt_tri, leaf order) from position `first`
 *   empty   count == 0: an unused lane (a node of 2 or 3 children, a one-leaf scene)
 *
 * Node 0 holds the root's children. A stack entry names a node (the first child of a group of
 * siblings) in its low 26 bits and three 2-bit lane offsets above: the siblings still to
 * visit, nearest first, the last one repeated to mark the end (see lt_qbvh_entry_pop). So a
 * tree may have at most 2^26 nodes (LT_QBVH_MAX_NODES); a node has at least two children and
 * every leaf holds a triangle, so a scene of up to 2^26 triangles always fits, and the host
 * refuses a tree beyond it with LT_ERROR_UNSUPPORTED. Triangle positions are whole 32-bit
 * ints, not limited by the entry. */
#ifndef LT_DEVICE_QBVH_NODE_H
#define LT_DEVICE_QBVH_NODE_H

#include "device/box.h"
#include "device/types.h"

/* Bits of a stack entry that name a node, and the nodes they can name. */
#define LT_QBVH_INDEX_BITS 26
#define LT_QBVH_MAX_NODES (1 << LT_QBVH_INDEX_BITS)
#define LT_QBVH_INDEX_MASK (LT_QBVH_MAX_NODES - 1)

/* A QBVH is never deeper than the binary BVH it collapses (LT_BVH_MAX_DEPTH), and a ray holds
 * at most one stack entry per level, so a stack this size never overflows. */
#define LT_QBVH_STACK_SIZE 64

typedef struct lt_qbvh_node {
  lt_float4 lo_x; /* 16 bytes: the four children's box lower x */
  lt_float4 hi_x; /* 16 bytes: upper x */
  lt_float4 lo_y; /* 16 bytes: lower y */
  lt_float4 hi_y; /* 16 bytes: upper y */
  lt_float4 lo_z; /* 16 bytes: lower z */
  lt_float4 hi_z; /* 16 bytes: upper z */
  lt_i32 first[4]; /* 16 bytes: per child, a node index (inner) or a triangle position (leaf) */
  lt_i32 count[4]; /* 16 bytes: per child, -children (inner), triangles (leaf), 0 (empty) */
} lt_qbvh_node;

#ifndef __OPENCL_VERSION__
_Static_assert(sizeof(lt_qbvh_node) == 128, "lt_qbvh_node is 128 bytes on both sides");
_Static_assert(_Alignof(lt_qbvh_node) == 16, "lt_qbvh_node is 16-byte aligned on both sides");
#endif

/* Writes lane `lane` of a node that no traversal reads yet (the host's collapse). */
LT_DEVICE void lt_qbvh_write_child(lt_qbvh_node *n, int lane, const lt_box *b, lt_i32 first, lt_i32 count) {
  float *f = (float *)n;
  for (int k = 0; k < 3; k++) f[8 * k + lane] = b->lo[k], f[8 * k + 4 + lane] = b->hi[k];
  n->first[lane] = first, n->count[lane] = count;
}

/* Lane `lane`'s box as two corners. */
LT_DEVICE void lt_qbvh_child_box(LT_GLOBAL const lt_qbvh_node *n, int lane, float lo[3], float hi[3]) {
  LT_GLOBAL const float *f = (LT_GLOBAL const float *)n;
  for (int k = 0; k < 3; k++) lo[k] = f[8 * k + lane], hi[k] = f[8 * k + 4 + lane];
}

/* A stack entry: node `node` and the lanes o0, o1, o2 still to visit in that order, where a
 * group of fewer than three repeats its last lane (two lanes a, b: a, b, b; one lane a: a, a, a
 * would never be pushed, the nearest child is visited at once). */
LT_DEVICE lt_u32 lt_qbvh_entry(lt_i32 node, int o0, int o1, int o2) {
  return (lt_u32)node | (lt_u32)o0 << 26 | (lt_u32)o1 << 28 | (lt_u32)o2 << 30;
}

/* The paper's pop: takes the next lane of the entry at the top of the stack and returns the
 * child's position as node * 4 + lane. Offsets never repeat within a group, so the entry is
 * finished when the offset after the one taken equals it; otherwise the offsets move down by
 * one and the last is repeated. *sp drops by one when the entry is finished. */
LT_DEVICE lt_i32 lt_qbvh_entry_pop(lt_u32 *stack, lt_i32 *sp) {
  lt_u32 data = stack[*sp - 1];
  lt_u32 offsets = data >> 26;
  lt_u32 lane = offsets & 3u, rest = offsets >> 2;
  lt_u32 node = data & (lt_u32)LT_QBVH_INDEX_MASK;
  if ((rest & 3u) == lane) (*sp)--;
  else stack[*sp - 1] = node | (rest | (rest << 2 & 0x30u)) << 26;
  return (lt_i32)(node * 4u + lane);
}

#endif
