/* The QBVH traversals, made from the one body (traversal/qbvh_traverse_body.h):
 *
 *   lt_qbvh_traverse         four boxes as one vector (float4 in OpenCL, SSE natively)
 *   lt_qbvh_traverse_scalar  the same with the plain C box test, lane after lane (host code
 *                           only); the tests check that it gives the same hits and counters
 */
#ifndef LT_QBVH_TRAVERSE_H
#define LT_QBVH_TRAVERSE_H

#include "traversal/qbvh_box4.h"

/* Intersects the `count` triangles of a leaf from position `first` (kept out of line: it is
 * called from two places of the loop). */
LT_DEVICE_OUTLINE void lt_qbvh_leaf(LT_GLOBAL const lt_tri *tris, const lt_ray_setup *r, lt_hit_record *hit, lt_i32 first,
                                    lt_i32 count, lt_trace_counters *c) {
  for (lt_i32 k = first; k < first + count; k++) {
    lt_tri tri = tris[k];
    float v0[3] = {tri.v0.x, tri.v0.y, tri.v0.z}, v1[3] = {tri.v1.x, tri.v1.y, tri.v1.z};
    float v2[3] = {tri.v2.x, tri.v2.y, tri.v2.z};
    c->intersections++;
    lt_intersect_triangle(r, v0, v1, v2, lt_float_as_int(tri.v0.w), hit);
  }
}

#define LT_QBVH_TRAVERSE_NAME lt_qbvh_traverse
#define LT_QBVH_TRAVERSE_BOX4 lt_qbvh_box4
#include "traversal/qbvh_traverse_body.h"

/* Host code only (the tests): the OpenCL program stays small. */
#ifndef __OPENCL_VERSION__
#define LT_QBVH_TRAVERSE_NAME lt_qbvh_traverse_scalar
#define LT_QBVH_TRAVERSE_BOX4(r, q, n, tmax, t) ((void)(q), lt_qbvh_box4_scalar((r), (n), (tmax), (t)))
#include "traversal/qbvh_traverse_body.h"
#endif

#endif
