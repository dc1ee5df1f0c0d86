/* The on-demand kd-tree kernel compiled as C for the native backend (kernels/kd_ondemand.h). */
#include "kernels/native_kernels.h"

#include "kernels/kd_ondemand.h"

void lt__native_kd_ondemand_kernel(void *arg) {
  lt__native_launch *launch = arg;
  lt_kd_args view = *(const lt_kd_args *)launch->view; /* each work-group its own copy */
  lt_loop_shared shared;
  lt_kd_kernel(&view, launch->setup, &shared);
}
