/* Full binned-SAH BVH build on the host. */
#ifndef LT_BVH_SAH_H
#define LT_BVH_SAH_H

#include <stddef.h>
#include <stdint.h>

#include "builders/sah_bins.h"
#include "device/bvh_node.h"
#include "lazytrace.h"

/* Parameters with the on-demand paper's defaults (Vinkler et al. 2016, section 3.3). */
typedef struct lt__sah_config {
  int max_leaf_size;       /* 16: a node with more primitives is always split */
  int bins;                /* 32 bins per axis over the centroid bounds */
  float traversal_cost;    /* 1: cost of a node visit, relative to one triangle test */
  float intersection_cost; /* 1 */
} lt__sah_config;

lt__sah_config lt__sah_config_default(void);

/* A BVH as flat arrays: inner nodes (node 0 is the root) and triangles in leaf order. */
typedef struct lt__bvh {
  lt_bvh_node *nodes;
  int node_count;   /* inner nodes (entries of the node array) */
  lt_tri *tris;
  int tri_count;
  int leaf_count;
  int max_depth;
  uint64_t sort_ops; /* primitives binned plus primitives partitioned (the paper's S_t) */
  double sah_cost;   /* SAH cost of the whole tree, relative to the root box */
} lt__bvh;

/* Builds over n triangles of 9 floats each. */
lt_status lt__bvh_build_sah(const float *tris, size_t n, const lt__sah_config *config, lt__bvh *out);
void lt__bvh_free(lt__bvh *bvh);
/* Completes a host build from the root's box and link: a root that is a leaf goes under an
 * inner node with an empty sibling; the triangles are written in leaf order (leaf_order[i] is
 * the triangle at position i), each carrying its number; the SAH cost is made relative to the
 * root's area. */
void lt__bvh_finish(lt__bvh *out, const float *tris, const int *leaf_order, size_t n, const lt_box *root, int link,
                    int count);
/* Tree nodes, counting leaves: what the statistics call nodes. */
int64_t lt__bvh_tree_nodes(const lt__bvh *bvh);

#endif
