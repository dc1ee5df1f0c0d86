/* Entry point of the on-demand BVH (kernels/bvh_ondemand.h): persistent work-groups that
 * trace rays and build nodes. The native backend calls the same body from
 * kernels/native_bvh_ondemand.c. */
#include "kernels/bvh_ondemand.h"

__kernel void lt_bvh_ondemand(LT_OD_ARGS(LT_ARG_PARAM) int setup) {
  __local lt_loop_shared shared;
  lt_od_args view;
  LT_OD_ARGS(LT_ARG_FILL)
  lt_od_kernel(&view, setup, &shared);
}
