/* Entry points of the irregular grid (kernels/irgrid_ondemand.h): persistent work-groups that
 * trace rays and build top cells. The native backend calls the same body from
 * kernels/native_irgrid_ondemand.c. */
#include "kernels/irgrid_ondemand.h"

__kernel void lt_irg_ondemand(LT_IRG_ARGS(LT_ARG_PARAM) int setup) {
  __local lt_loop_shared shared;
  lt_irg_args view;
  LT_IRG_ARGS(LT_ARG_FILL)
  lt_irg_kernel(&view, setup, &shared);
}

/* The merge passes across the grid of a full build, a second launch (kernels/irgrid_ondemand.h). */
__kernel void lt_irg_merge(LT_IRG_ARGS(LT_ARG_PARAM) int setup) {
  __local lt_loop_shared shared;
  lt_irg_args view;
  LT_IRG_ARGS(LT_ARG_FILL)
  lt_irg_merge_kernel(&view, setup, &shared);
}
