/* Entry point of the on-demand BVH (kernels/bvh_ondemand.h): persistent work-groups that
 * trace rays and build nodes. The native backend calls the same body from
 * kernels/native_bvh_ondemand.c. */
#include "kernels/bvh_ondemand.h"

__kernel void lt_bvh_ondemand(__global int *headers, __global lt_task *tasks, __global int *empty_cache,
                              __global int *priority_cache, __global lt_pool_control *control,
                              __global uint *stats, __global int *order, int4 sizes, int mode,
                              __global const float *verts, __global const float4 *prim_boxes,
                              __global int *side, __global int *index, __global int *scratch,
                              __global int *chunk_left, __global lt_bvh_node *nodes, __global int *slabs,
                              __global int *slab_used, __global uint *counters, int4 build_sizes,
                              float2 costs, __global const float *rays, __global lt_hit_record *hits,
                              int4 trace_params) {
  __local lt_od_shared shared;
  lt_od_trace_args a;
  lt_pool *pool = &a.build.pool;
  pool->headers = headers, pool->tasks = tasks, pool->empty_cache = empty_cache;
  pool->priority_cache = priority_cache, pool->control = control, pool->stats = stats, pool->order = order;
  pool->capacity = sizes.x, pool->empty_size = sizes.y, pool->priority_size = sizes.z, pool->order_size = sizes.w;
  pool->mode = mode;
  a.build.verts = verts, a.build.prim_boxes = prim_boxes, a.build.side = side, a.build.index = index, a.build.scratch = scratch, a.build.chunk_left = chunk_left;
  a.build.nodes = nodes, a.build.slabs = slabs, a.build.slab_used = slab_used, a.build.counters = counters;
  a.build.slab_count = build_sizes.x, a.build.node_capacity = build_sizes.y;
  a.build.max_leaf = build_sizes.z, a.build.bins = build_sizes.w;
  a.build.traversal_cost = costs.x, a.build.intersection_cost = costs.y;
  a.rays = rays, a.hits = hits;
  a.ray_count = trace_params.x, a.any_hit = trace_params.y;
  a.max_idle_polls = trace_params.z, a.speculate = trace_params.w;
  lt_od_run(&a, &shared);
}
