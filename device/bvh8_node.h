/* The 8-wide node of the QBVH's native path: the binary SAH BVH collapsed into an 8-ary tree
 * (Dammertz, Hanika and Keller 2008, at the width of an AVX2 register, as Embree's BVH8),
 * traced eight boxes at a time by traversal/bvh8_traverse.h where the CPU has AVX2. The
 * OpenCL backend and CPUs without AVX2 keep the 4-wide QBVH (device/qbvh_node.h).
 *
 * A node is the group of up to eight siblings: their boxes in SoA form (one 32-byte row per
 * plane, lane i is child i) and each child's link, told by its count as in the QBVH:
 *
 *   inner   count < 0, first >= 0: its own children are the first -count lanes of node `first`
 *   exit    count < 0, first < 0: an unbuilt child of a tree still being built, whose link is
 *           at address -2 - first of the binary tree (device/bvh_node.h): the 8-wide
 *           traversal hands it back to the binary one (first is then that traversal's stack
 *           entry for the link)
 *   leaf    count > 0: `count` triangles from slot `first` of the tree's blocks (below)
 *   empty   count == 0: an unused lane, whose box is the point LT_BVH8_EMPTY_LANE_BOX (below)
 *
 * The tree has its own copy of the triangles in leaf order, in blocks of four in SoA form with
 * their numbers (lt_tri4, as Embree's Triangle4): block i holds slots 4i to 4i + 3, 40 bytes a
 * slot. A leaf of up to four triangles lies within one block, sharing it with its neighbours
 * in leaf order where they fit; a longer leaf starts a block; lanes no leaf holds are copies of
 * their block's lane 0, never tested. The watertight test runs on a block's four triangles in
 * one vector pass (traversal/bvh8_traverse.h); only its last steps, for a possible hit, run per
 * triangle, on the same block's lanes.
 *
 * Node 0 holds the root's children. The traversal's stack holds children (first, count and
 * entry distance), not nodes, so no bits of an index are given up and the node count is
 * bounded by int only. */
#ifndef LT_DEVICE_BVH8_NODE_H
#define LT_DEVICE_BVH8_NODE_H

#include "device/box.h"
#include "device/types.h"

#define LT_BVH8_WIDTH 8

typedef struct lt_bvh8_node {
  float lo_x[8];   /* 32 bytes: the eight children's box lower x */
  float hi_x[8];   /* 32 bytes: upper x */
  float lo_y[8];   /* 32 bytes: lower y */
  float hi_y[8];   /* 32 bytes: upper y */
  float lo_z[8];   /* 32 bytes: lower z */
  float hi_z[8];   /* 32 bytes: upper z */
  lt_i32 first[8]; /* 32 bytes: per child, a node index (inner) or a triangle position (leaf) */
  lt_i32 count[8]; /* 32 bytes: per child, -children (inner), triangles (leaf), 0 (empty) */
} lt_bvh8_node;

/* Four triangles of a leaf, SoA: v[3 * j + k] is coordinate k of vertex j, lane i triangle i,
 * and the four triangles' numbers, so that a hit is finished from the block alone. */
typedef struct lt_tri4 {
  float v[9][4];  /* 144 bytes: v0.x v0.y v0.z v1.x v1.y v1.z v2.x v2.y v2.z, four lanes each */
  lt_i32 prim[4]; /* 16 bytes: the triangles' numbers */
} lt_tri4;

/* An any-hit query's guesses (kernels/native_bvh_wide.c): copies of the triangles that
 * answered one work-item's last eight any-hit queries, tested first, and whether that pays.
 * Kept from ray to ray of one launch, zero at its start. */
typedef struct lt_bvh8_occluders {
  lt_tri4 recent[2]; /* slots 0 to filled - 1 (slot i: block i / 4, lane i % 4) */
  lt_i32 filled;     /* slots holding a triangle, at most 8 */
  lt_i32 next;       /* the slot the next answer takes, over the oldest */
  lt_i32 odds;       /* 4096 x the share of tries that answered, each try weighing 1/16 */
  lt_i32 work;       /* 16 x the node visits of a traversal after a failed try, on average */
  lt_i32 worth;      /* odds x work above a try's cost: every query tries */
  lt_u32 rays;       /* queries that have asked */
  lt_u32 mark;       /* the work-item's node visits before the traversal under way */
} lt_bvh8_occluders;

#ifndef __OPENCL_VERSION__
_Static_assert(sizeof(lt_tri4) == 160, "lt_tri4 is 160 bytes");
_Static_assert(sizeof(lt_bvh8_node) == 256, "lt_bvh8_node is four 64-byte lines");
#endif

/* The box of an empty lane: one point far off, off the axes and diagonals, which the 8-wide
 * slab test rejects by itself (the entry of one axis lies past the exit of another) for every
 * ray that does not pass through that very point within the slabs' rounding (and whose three
 * distances to it do not all overflow), so that the vector traversal needs no mask of the lanes
 * in use. An empty lane entered all the same is a leaf of no triangles: nothing is tested. */
#define LT_BVH8_EMPTY_LANE_BOX {{1e30f, -2e30f, 3e30f}, {1e30f, -2e30f, 3e30f}}

/* Writes lane `lane` of a node that no traversal reads yet (the host's collapse). */
LT_DEVICE void lt_bvh8_write_child(lt_bvh8_node *n, int lane, const lt_box *b, lt_i32 first, lt_i32 count) {
  float *f = (float *)n;
  for (int k = 0; k < 3; k++) f[16 * k + lane] = b->lo[k], f[16 * k + 8 + lane] = b->hi[k];
  n->first[lane] = first, n->count[lane] = count;
}

/* Lane `lane`'s box as two corners. */
LT_DEVICE void lt_bvh8_child_box(const lt_bvh8_node *n, int lane, float lo[3], float hi[3]) {
  const float *f = (const float *)n;
  for (int k = 0; k < 3; k++) lo[k] = f[16 * k + lane], hi[k] = f[16 * k + 8 + lane];
}

#endif
