/* Entry point of the scheduler's test workload (kernels/lazy_sort.h): one persistent
 * work-group per compute unit runs the pool. The native backend calls the same body from
 * kernels/native_lazy_sort.c. */
#include "kernels/lazy_sort.h"

__kernel void lt_lazy_sort(__global int *headers, __global lt_task *tasks, __global int *empty_cache,
                           __global int *priority_cache, __global lt_pool_control *control,
                           __global uint *stats, __global int *order, int4 sizes, int mode,
                           __global uint *keys, __global uint *scratch, __global int *state,
                           __global int4 *nodes, __global const int *queries, __global uint *answers,
                           int query_count, int node_capacity, int max_idle_polls) {
  __local lt_sort_shared shared;
  lt_sort s;
  s.pool.headers = headers, s.pool.tasks = tasks, s.pool.empty_cache = empty_cache;
  s.pool.priority_cache = priority_cache, s.pool.control = control, s.pool.stats = stats, s.pool.order = order;
  s.pool.capacity = sizes.x, s.pool.empty_size = sizes.y, s.pool.priority_size = sizes.z, s.pool.order_size = sizes.w;
  s.pool.mode = mode;
  s.keys = keys, s.scratch = scratch, s.state = state, s.nodes = nodes;
  s.queries = queries, s.answers = answers, s.query_count = query_count;
  s.node_capacity = node_capacity, s.max_idle_polls = max_idle_polls;
  lt_sort_run(&s, &shared);
}
