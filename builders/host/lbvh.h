/* Fast LBVH build over Morton codes with an SAH-built top: the on-demand paper's HLBVH_4. */
#ifndef LT_LBVH_H
#define LT_LBVH_H

#include <stddef.h>

#include "builders/host/bvh_sah.h"
#include "builders/host/executor.h"

/* Builds over n triangles of 9 floats each into the flat format of lt__bvh_build_sah (free it
 * with lt__bvh_free). A NULL config means lt__sah_config_default(). Of the config, leaves hold at
 * most max_leaf_size / 4 triangles (at least 1), the top over the clusters uses min(bins, 32)
 * bins, and the two costs price the top splits and sah_cost. sort_ops counts n per radix pass
 * plus the clusters binned and partitioned by the top. */
lt_status lt__bvh_build_lbvh(const float *tris, size_t n, const lt__sah_config *config, lt__bvh *out);

/* The same build with a tighter depth bound, 2..LT_BVH_MAX_DEPTH: a node at depth
 * depth_limit - 1 is always a leaf. Lets tests reach the forced leaves on small scenes. */
lt_status lt__bvh_build_lbvh_limited(const float *tris, size_t n, const lt__sah_config *config, int depth_limit,
                                     lt__bvh *out);

/* The same build with its loops run by an executor (NULL, or under 32768 triangles: on the
 * calling thread): triangle boxes, Morton codes, the radix sort's passes, the clusters' boxes,
 * their Karras hierarchies and the triangles in leaf order run in parallel; the SAH top over at
 * most 4096 clusters runs on the calling thread. The tree is the same, node for node, whatever
 * the number of workers. */
lt_status lt__bvh_build_lbvh_with(const float *tris, size_t n, const lt__sah_config *config, int depth_limit,
                                  const lt__executor *executor, lt__bvh *out);

#endif
