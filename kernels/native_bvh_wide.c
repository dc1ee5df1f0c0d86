/* The on-demand traversal's way into a wide subtree (traversal/bvh_view.h): the 8-wide AVX2
 * traversal of traversal/bvh8_traverse.h from the ray's best hit so far. Kept out of line: the
 * persistent kernel is baseline x86-64, this function AVX2, and only CPUs with AVX2 have wide
 * subtrees (the host checks lt_bvh8_supported before it makes any). */
#include "kernels/native_kernels.h"

#if defined(__x86_64__)
#include "traversal/bvh8_traverse.h"
#include "traversal/bvh_view.h"

LT_BVH8_TARGET __attribute__((noinline)) int lt__bvh_wide_trace(const lt_bvh_wide_view *w, const lt_ray_setup *r,
                                                                lt_hit_record *hit, lt_i32 node, lt_trace_counters *c) {
  return lt_bvh8_traverse_from(w->nodes, w->blocks, w->tris, r, node, hit, c, 1);
}
#endif
