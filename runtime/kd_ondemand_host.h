/* The host half of the on-demand kd-tree: buffers, the root task, launches of the persistent
 * kernel (kernels/kd_ondemand.h) on either backend, and its counters. */
#ifndef LT_KD_ONDEMAND_HOST_H
#define LT_KD_ONDEMAND_HOST_H

#include "device/box.h"
#include "device/kd_node.h"
#include "runtime/heap_host.h"
#include "runtime/pool_host.h"

typedef struct lt__kd_config {
  int max_leaf, bins, max_depth;
  int sweep, clip; /* the exact split sweep, split clipping */
  int traversal;   /* LT_KD_TRAVERSE_* (kernels/kd_ondemand.h) */
  float traversal_cost, intersection_cost;
} lt__kd_config;

typedef struct lt__kd {
  lt_context *ctx;
  lt__pool pool;
  lt__heap node_heap, ref_heap;
  lt__buffer verts, prim_boxes, nodes, refs, parents, cells, counters;
  int count;          /* triangles */
  lt_box bounds;      /* the scene's: the root cell */
  lt__kd_config config;
  double leaves, leaf_refs, sort_ops; /* over all launches */
  int depth;          /* deepest leaf so far */
} lt__kd;

/* The depth limit of the paper for n triangles: 1.2 * log2(n) + 2, at most LT_KD_MAX_DEPTH. */
int lt__kd_max_depth(size_t n);

/* An empty tree over the scene: node 0 is a super-root whose link 0 is the root task. */
lt_status lt__kd_create(lt_context *ctx, const lt_scene *scene, const lt__kd_config *config, int mode,
                        int pool_capacity, int node_capacity, int ref_capacity, lt__kd *kd);
void lt__kd_release(lt__kd *kd);
/* One launch: traces count rays (none: a full build builds everything) and writes hits;
 * speculate says whether work-groups without rays build unrequested cells. Adds the launch's
 * pool and traversal counters to stats. */
lt_status lt__kd_launch(lt__kd *kd, const lt_ray *rays, int count, int flags, lt_hit *hits, int speculate,
                        lt_stats *stats);
/* Whether the last launch ran out of nodes or of references. */
void lt__kd_heaps_full(lt__kd *kd, int *nodes_full, int *refs_full);
/* Nodes built so far, inner and leaves (the super-root is not counted). */
double lt__kd_nodes_built(lt__kd *kd);
/* Copies the node array and the reference heap (for tests that compare trees); the caller
 * frees both. */
lt_status lt__kd_snapshot(lt__kd *kd, lt_kd_node **nodes, int *node_count, int **refs, int *ref_count);
/* The SAH cost of the tree as built (for a full build, the tree's): the surface-area-weighted
 * sum over its cells, a traversal cost per inner cell and an intersection cost per reference
 * in a leaf, relative to the root cell; NaN for a tree of one node. */
lt_status lt__kd_sah_cost(lt__kd *kd, double *cost);
/* The on-demand kd-tree behind a structure, or NULL (for tests). */
lt__kd *lt__structure_kd(lt_structure *structure);
/* Device bytes in use: nodes and references handed out by the heaps (references include the
 * arrays of inner cells, which the heap does not free), the pool, and (in the total) the
 * triangles' boxes. */
double lt__kd_bytes(lt__kd *kd, double *node_bytes, double *reference_bytes, double *pool_bytes);

#endif
