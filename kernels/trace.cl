/* Entry point of the trace kernel: one work-item per ray over a full BVH. The body is shared
 * with the native backend (kernels/native_trace.c). */
#include "kernels/trace_body.h"

__kernel void lt_trace_bvh(__global const float *rays, int count, int flags,
                           __global const lt_bvh_node *nodes, __global const lt_tri *tris,
                           __global lt_hit_record *hits, __global lt_u32 *counters,
                           __global int *error) {
  lt_trace_counters local_counters = {0, 0};
  int i = lt_global_id();
  if (i < count) {
    if (lt_trace_one(rays, i, flags, nodes, tris, hits, &local_counters) != 0) atomic_xchg(error, 1);
  }

  /* One counter slot per work-group keeps the sums far from 32-bit overflow. */
  __global lt_u32 *slot = counters + 2 * lt_group_id();
  if (local_counters.traversal_steps) lt_atomic_add_u32(slot, local_counters.traversal_steps);
  if (local_counters.intersections) lt_atomic_add_u32(slot + 1, local_counters.intersections);
}
