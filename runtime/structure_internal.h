/* What every structure shares on the host, whatever its kind, and the internal knobs of
 * structures and the reference for tests and the accuracy report: the query flags that pick
 * the numerics (traversal/ray.h), including ones the public API does not offer because they
 * only exist to be measured. */
#ifndef LT_STRUCTURE_INTERNAL_H
#define LT_STRUCTURE_INTERNAL_H

#include "builders/host/bvh_sah.h"
#include "lazytrace.h"

struct lt__structure_class;

struct lt_structure {
  lt_context *ctx;
  const struct lt__structure_class *cls; /* its registry entry (runtime/registry.h) */
  lt_structure_config config;           /* every default filled in */
  const lt_scene *scene;                /* kept to rebuild with larger buffers when one fills up */
  int flags;                            /* query flags every trace adds (triangle test, knobs) */
  void *state;                          /* the class's own, cls->state_size bytes */
};

/* The brute-force reference with query flags (LT_QUERY_FLAG_*) instead of a query kind. */
lt_status lt__reference_trace_flags(const lt_scene *scene, const lt_ray *rays, size_t count, int flags,
                                    lt_hit *hits);
/* Flags added to every later trace of the structure (LT_QUERY_FLAG_PLAIN_SLABS, ...). */
void lt__structure_set_flags(lt_structure *structure, int flags);
/* The query flags a trace of this structure uses for a query kind. */
int lt__structure_flags(const lt_structure *structure, int query);
/* A structure over a tree built on the host (builders/host/bvh_sweep.c, ...), traced by the
 * host-built BVH's kernel like the LBVH; takes the tree's arrays (bvh is left empty). */
lt_status lt__structure_from_bvh(lt_context *ctx, const lt_scene *scene, lt__bvh *bvh, lt_structure **out);
/* A structure of config->kind with nothing built yet (for entries that make their contents
 * another way, such as lt__structure_from_bvh). */
lt_status lt__structure_wrap(lt_context *ctx, const lt_scene *scene, const lt_structure_config *config,
                             lt_structure **out);
/* Fault injection for tests: structures start with the smallest pools, heaps and reference
 * arrays they can have, so that every overflow-and-retry path runs. */
extern int lt__structure_tiny_capacities;
/* The most nodes a QBVH may have (default LT_QBVH_MAX_NODES, what its 26-bit stack entries can
 * name); tests lower it to see a scene beyond it refused clearly. */
extern int lt__structure_qbvh_max_nodes;
/* The SAH parameters of a BVH structure's config. */
lt__sah_config lt__structure_sah(const lt_structure_config *config);

#endif
