/* The irregular grid's kernel compiled as C for the native backend (kernels/irgrid_ondemand.h). */
#include "kernels/native_kernels.h"

#include "kernels/irgrid_ondemand.h"

void lt__native_irgrid_ondemand_kernel(void *arg) {
  lt__native_launch *launch = arg;
  lt_irg_args view = *(const lt_irg_args *)launch->view; /* each work-group its own copy */
  lt_loop_shared shared;
  lt_irg_kernel(&view, launch->setup, &shared);
}

void lt__native_irgrid_merge_kernel(void *arg) {
  lt__native_launch *launch = arg;
  lt_irg_args view = *(const lt_irg_args *)launch->view; /* each work-group its own copy */
  lt_loop_shared shared;
  lt_irg_merge_kernel(&view, launch->setup, &shared);
}
