/* The body of the trace kernel for one ray, shared by the OpenCL entry (kernels/trace.cl) and
 * the native backend (kernels/native_trace.c). */
#ifndef LT_TRACE_BODY_H
#define LT_TRACE_BODY_H

#include "traversal/bvh_traverse.h"

/* Traces ray i of a ray array in the file layout (8 floats a ray) and writes hits[i]; flags are
 * the query flags (LT_QUERY_FLAG_*). A miss is written as t = +infinity, u = v = 0,
 * prim = -1. Returns 0, or -1 on stack overflow. */
LT_DEVICE int lt_trace_one(LT_GLOBAL const float *rays, int i, int flags,
                           LT_GLOBAL const lt_bvh_node *nodes, LT_GLOBAL const lt_tri *tris,
                           LT_GLOBAL lt_hit_record *hits, lt_trace_counters *counters) {
  LT_GLOBAL const float *ray = rays + 8 * (long)i;
  lt_ray_setup r = lt_ray_prepare(ray[0], ray[1], ray[2], ray[3], ray[4], ray[5], ray[6], ray[7]);
  r.flags = flags;
  lt_hit_record hit;
  int status = lt_bvh_traverse(&r, nodes, tris, flags & LT_QUERY_FLAG_ANY, &hit, counters);
  if (hit.prim < 0) {
    hit.t = INFINITY;
    hit.u = hit.v = 0.0f;
  }
  hits[i] = hit;
  return status;
}

#endif
