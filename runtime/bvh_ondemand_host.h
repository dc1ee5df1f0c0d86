/* The host half of the on-demand BVH: buffers, the root task, launches of the persistent
 * kernel (kernels/bvh_ondemand.h) on either backend, and its counters. */
#ifndef LT_ONDEMAND_INTERNAL_H
#define LT_ONDEMAND_INTERNAL_H

#include "builders/host/bvh8_collapse.h"
#include "builders/host/bvh_sah.h"
#include "runtime/heap_host.h"
#include "runtime/pool_host.h"

typedef struct lt__ondemand {
  lt_context *ctx;
  lt__pool pool;
  lt__heap node_heap;
  lt__buffer verts, prim_boxes, side, index, scratch, chunk_left, nodes, slabs, slab_used, counters;
  lt__buffer codes, block_boxes; /* the Morton top's sorted codes and block boxes (16 bytes without one) */
  int count;          /* triangles */
  lt_box bounds;       /* the scene's */
  int slab_count;
  int morton_above;   /* nodes of more triangles are split by Morton code; the count: none are */
  int morton_blocks;  /* block boxes at the bottom of the pyramid */
  lt__sah_config sah;
  void *kept[8];      /* native: arrays taken from the context (lt__context_take) by slot */
  size_t kept_bytes[8];
  double leaves;      /* leaves built over all launches */
  double sort_ops;
  /* Native: the built part collapsed 8 wide before each launch (runtime/bvh_wide_host.c). */
  int wide_on;        /* collapse before each launch with rays */
  int wide_hold;      /* not before the next launch (a re-trace for statistics) */
  int wide_stride;    /* the sample's stride (lt__ondemand_wide_stride) */
  int wide_guesses;   /* any-hit queries try recent answers first (kernels/native_bvh_wide.c) */
  lt__bvh8 wide;      /* the wide nodes and their triangle copies */
  int wide_collapses; /* collapses so far */
  double wide_ms;     /* host time spent collapsing (part of the launches' time) */
} lt__ondemand;

/* Whether trees on ctx in this pool mode collapse their built part 8 wide: native backend,
 * on demand, a CPU with AVX2, and not LT_BVH_WIDE=0 in the environment (the switch that
 * measures binary against wide traversal). */
int lt__ondemand_wide_wanted(const lt_context *ctx, int pool_mode);
/* The stride of the ray sample traced before each batch (so that the rest of the batch runs
 * on a tree collapsed after the sample's builds; the sample's rays are not traced again, and
 * the sample itself is traced after a sample of its own while it is large enough):
 * LT_BVH_WIDE_SAMPLE (default 16; 0 turns it off), read once when a tree is made, as
 * LT_BVH_WIDE is. */
int lt__ondemand_wide_stride(void);
/* Whether any-hit queries on a native 8-wide tree (this one's, the full QBVH's) try their
 * work-item's recent answers first (LT_BVH_GUESSES=0 in the environment: no). */
int lt__ondemand_wide_guesses(void);
/* That stride for a batch of `count` rays, or 0 for none (none for batches under 1024 samples). */
int lt__ondemand_wide_sample(int stride, int count);
/* Collapses the tree as far as it is built into the wide tree, and marks the root's link
 * wide (only while no launch is running). */
lt_status lt__ondemand_widen(lt__ondemand *od);

/* Bin slabs of trees created from now on (default 64; see ondemand.c). */
extern int lt__ondemand_slab_count;

/* An empty tree over the scene: node 0 is a super-root whose left child is the root task. With
 * morton_above > 0 the triangles are sorted by Morton code first, and nodes of more than
 * morton_above triangles are split by code (builders/bvh_morton.h); 0 keeps the SAH top. */
lt_status lt__ondemand_create(lt_context *ctx, const lt_scene *scene, const lt__sah_config *sah, int mode,
                              int pool_capacity, int node_capacity, int morton_above, lt__ondemand *od);
void lt__ondemand_release(lt__ondemand *od);
/* One launch: traces count rays (none is fine: a full build then builds everything) and writes
 * hits; speculate says whether work-groups without rays build unrequested nodes. Adds the
 * launch's pool and traversal counters to stats. */
lt_status lt__ondemand_launch(lt__ondemand *od, const lt_ray *rays, int count, int flags, lt_hit *hits,
                              int speculate, lt_stats *stats);
/* Whether a launch ran out of nodes (the retry then needs a larger node heap, not a pool). */
int lt__ondemand_heap_full(lt__ondemand *od);
/* Nodes built so far, counting leaves (the super-root is not counted). */
lt_status lt__ondemand_nodes_built(lt__ondemand *od, double *nodes);
/* Copies the node array and references (for tests that compare trees); the caller frees. */
lt_status lt__ondemand_snapshot(lt__ondemand *od, lt_bvh_node **nodes, int *node_count, int **index);
/* The on-demand tree behind a structure, or NULL (for tests). */
lt__ondemand *lt__structure_ondemand(lt_structure *structure);
/* Device bytes held: nodes, references, pool and scratch. */
double lt__ondemand_bytes(const lt__ondemand *od, double *node_bytes, double *reference_bytes, double *pool_bytes);

#endif
