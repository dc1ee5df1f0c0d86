/* The QBVH traversals, made from the one body (traversal/qbvh_traverse_body.h):
 *
 *   lt_qbvh_traverse         four boxes as one vector (float4 in OpenCL, SSE natively)
 *   lt_qbvh_traverse_scalar  the same with the plain C box test, lane after lane (host code
 *                           only); the tests check that it gives the same hits and counters
 */
#ifndef LT_QBVH_TRAVERSE_H
#define LT_QBVH_TRAVERSE_H

#include "traversal/qbvh_box4.h"

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
