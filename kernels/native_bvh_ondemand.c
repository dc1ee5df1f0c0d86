/* The on-demand BVH kernel compiled as C for the native backend (kernels/bvh_ondemand.h). */
#include "kernels/native_kernels.h"

#include "kernels/bvh_ondemand.h"

void lt__native_bvh_ondemand_kernel(void *arg) {
  lt__native_launch *launch = arg;
  lt_od_args view = *(const lt_od_args *)launch->view; /* each work-group its own copy */
  lt_loop_shared shared;
  lt_od_kernel(&view, launch->setup, &shared);
}
