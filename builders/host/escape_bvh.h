/* The escape-index layout of a BVH built on the host (device/escape_bvh_node.h): the tree's
 * nodes in depth-first, left-to-right order, each inner node with the index of the first node
 * after its subtree. Host-only C. */
#ifndef LT_ESCAPE_BVH_H
#define LT_ESCAPE_BVH_H

#include "builders/host/bvh_sah.h"
#include "builders/host/bvh_thesis.h"
#include "device/escape_bvh_node.h"

typedef struct lt__escape_bvh {
  lt_escape_node *nodes; /* at least one (an empty scene: one inner node with an empty box) */
  int node_count;
  int leaf_count;
  int max_depth; /* nodes on the longest path from a top node to a leaf, the top node counted */
} lt__escape_bvh;

/* Lays out a finished binary BVH (lt__bvh_build_sah and the other host builders). The root
 * node's two children are the first nodes of the sequence (the root itself, which every ray
 * that meets any child meets, is left out); empty children are left out. The leaves point into
 * bvh->tris, which stay where they are. LT_ERROR_OUT_OF_MEMORY on allocation. */
lt_status lt__escape_bvh_from_bvh(const lt__bvh *bvh, lt__escape_bvh *out);
/* Lays out a tree of any number of children a node (builders/host/bvh_thesis.h) the same way
 * (the root's children first) and copies its triangles (9 floats each) into leaf order
 * (*tris_out, 16-byte aligned, each carrying its number). LT_ERROR_OUT_OF_MEMORY on allocation. */
lt_status lt__escape_bvh_from_tree(const lt__tree *tree, const float *tris, lt__escape_bvh *out, lt_tri **tris_out);
void lt__escape_bvh_free(lt__escape_bvh *e);

#endif
