/* The two BVH builders of Thrane and Simonsen's comparison (2005, section 9.3), host-only C,
 * as references for the escape-index BVH (builders/host/escape_bvh.h), not defaults:
 *
 *   Kay-Kajiya        top down: a node's triangles split at the spatial median of the longest
 *                     axis of its box, by centroid; one triangle a leaf (the thesis' leaves)
 *   Goldsmith-Salmon  incremental: each triangle in turn goes down the cheapest path by the
 *                     surface-area cost and becomes a new child or pairs with a leaf; nodes may
 *                     have any number of children; the best of several shuffled orders
 *
 * Both make a tree of nodes with any number of children (lt__tree). */
#ifndef LT_BVH_THESIS_H
#define LT_BVH_THESIS_H

#include <stddef.h>
#include <stdint.h>

#include "device/box.h"
#include "lazytrace.h"

/* A node: inner (count 0) with its children as a list, or a leaf of `count` triangles, the
 * entries index[first .. first + count) of its tree. */
typedef struct lt__tree_node {
  lt_box box;
  int first_child, next_sibling; /* -1: none */
  int children;                  /* inner: how many */
  int first, count;              /* leaf */
} lt__tree_node;

typedef struct lt__tree {
  lt__tree_node *nodes;
  int node_count, root; /* root -1: no triangles */
  int *index;           /* triangle numbers, as the leaves name them */
  double cost;          /* surface-area cost relative to the root's area: sum over inner nodes of
                           area times children, plus sum over leaves of area times triangles */
} lt__tree;

/* Leaves of one triangle, or of all a node's triangles when their centroids coincide; a median
 * that leaves one side empty falls back to the middle of the centroids' extent, then to halves. */
lt_status lt__tree_build_kay_kajiya(const float *tris, size_t n, lt__tree *out);
/* `orders` shuffled insertion orders from `seed` (the same seed, the same tree); keeps the one
 * of least cost. */
lt_status lt__tree_build_goldsmith_salmon(const float *tris, size_t n, int orders, uint64_t seed, lt__tree *out);
void lt__tree_free(lt__tree *tree);

#endif
