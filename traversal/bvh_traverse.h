/* The BVH traversals, made from the one body (traversal/bvh_traverse_body.h):
 *
 *   lt_bvh_advance_ondemand  a tree the pool is building (links change under the ray; leaves
 *                            are triangle numbers into the scene's vertices)
 *   lt_bvh_advance_tris      a finished tree built on the host (leaves are triangles in leaf
 *                            order)
 *   lt_bvh_advance_index     a finished tree built by the pool (leaves are triangle numbers;
 *                            plain loads, no requests)
 *
 * A tree being built culls each popped far child against the best hit as it is now
 * (LT_BVH_TRAVERSE_CULL_POPS): a far child hidden since it was pushed is then neither visited
 * nor requested, and a request costs a build. On a finished tree the saved visits (5% of the
 * LBVH's on house) paid for the extra stack of entry distances only on the native backend, and
 * it keeps the host-built trees' traversal as it was, counters included.
 */
#ifndef LT_BVH_TRAVERSE_H
#define LT_BVH_TRAVERSE_H

#include "traversal/bvh_view.h"

#define LT_BVH_TRAVERSE_NAME lt_bvh_advance_ondemand
#define LT_BVH_TRAVERSE_ONDEMAND 1
#define LT_BVH_TRAVERSE_LEAF_TRIS 0
#define LT_BVH_TRAVERSE_CULL_POPS 1
#include "traversal/bvh_traverse_body.h"

#define LT_BVH_TRAVERSE_NAME lt_bvh_advance_tris
#define LT_BVH_TRAVERSE_ONDEMAND 0
#define LT_BVH_TRAVERSE_LEAF_TRIS 1
#define LT_BVH_TRAVERSE_CULL_POPS 0
#include "traversal/bvh_traverse_body.h"

#define LT_BVH_TRAVERSE_NAME lt_bvh_advance_index
#define LT_BVH_TRAVERSE_ONDEMAND 0
#define LT_BVH_TRAVERSE_LEAF_TRIS 0
#define LT_BVH_TRAVERSE_CULL_POPS 0
#include "traversal/bvh_traverse_body.h"

#endif
