/* Entry point of the scheduler's test workload (kernels/lazy_sort.h): one persistent
 * work-group per compute unit runs the pool. The native backend calls the same body from
 * kernels/native_lazy_sort.c. */
#include "kernels/lazy_sort.h"

__kernel void lt_lazy_sort(LT_SORT_ARGS(LT_ARG_PARAM) int setup) {
  __local lt_loop_shared shared;
  lt_sort_args view;
  LT_SORT_ARGS(LT_ARG_FILL)
  lt_sort_kernel(&view, setup, &shared);
}
