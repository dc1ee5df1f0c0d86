/* Entry point of the on-demand kd-tree (kernels/kd_ondemand.h): persistent work-groups that
 * trace rays and build cells. The native backend calls the same body from
 * kernels/native_kd_ondemand.c. */
#include "kernels/kd_ondemand.h"

__kernel void lt_kd_ondemand(LT_KD_ARGS(LT_ARG_PARAM) int setup) {
  __local lt_loop_shared shared;
  lt_kd_args view;
  LT_KD_ARGS(LT_ARG_FILL)
  lt_kd_kernel(&view, setup, &shared);
}
