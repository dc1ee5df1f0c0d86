/* The binary SAH BVH collapsed into an 8-wide tree (device/bvh8_node.h) for the QBVH's native
 * AVX2 path: Dammertz, Hanika and Keller 2008 at width 8. Host-only C. */
#ifndef LT_BVH8_COLLAPSE_H
#define LT_BVH8_COLLAPSE_H

#include "builders/host/bvh_sah.h"
#include "device/bvh8_node.h"

/* The nodes of an 8-wide tree, and its own copy of the binary BVH's triangles in leaf order,
 * every leaf starting at a multiple of four, in blocks of four (device/bvh8_node.h: lt_tri4,
 * vertices and triangle numbers): the traversal reads nothing else. */
typedef struct lt__bvh8 {
  lt_bvh8_node *nodes; /* node 0 holds the root's children; 64-byte aligned */
  int node_count;
  lt_tri4 *blocks; /* tri_slots / 4 blocks: block i is triangles 4i to 4i + 3 */
  int tri_slots;
  int leaf_count;
  int max_depth; /* nodes on the longest path from a collapse's root to a leaf's node */
  int node_capacity, slot_capacity; /* room allocated (appends grow it) */
} lt__bvh8;

/* Collapses a finished binary BVH: each node takes a binary node's two children and opens the
 * inner one of largest surface area while it has fewer than eight. Every box is the binary
 * tree's, bit for bit. LT_ERROR_OUT_OF_MEMORY on allocation. */
lt_status lt__bvh8_collapse(const lt__bvh *bvh, lt__bvh8 *out);
/* Collapses the subtree under inner node `link` of a tree the pool is building (`nodes`;
 * leaves hold triangle numbers from `index` into `verts`, 9 floats a triangle) as far as it is
 * built, into out (zeroed the first time; what it held is replaced, its room reused): unbuilt
 * links become exit lanes (device/bvh8_node.h). *root gets the wide node holding the
 * subtree's children. LT_ERROR_OUT_OF_MEMORY on allocation. */
lt_status lt__bvh8_collapse_built(lt__bvh8 *out, const lt_bvh_node *nodes, int link, const lt_i32 *index,
                                  const float *verts, int *root);
void lt__bvh8_free(lt__bvh8 *bvh8);

#endif
