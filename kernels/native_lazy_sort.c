/* The lazy-sort workload compiled as C for the native backend (see kernels/lazy_sort.h). */
#include "kernels/native_kernels.h"

#include "kernels/lazy_sort.h"

void lt__native_lazy_sort_kernel(void *arg) {
  lt__native_launch *launch = arg;
  lt_sort_args view = *(const lt_sort_args *)launch->view; /* each work-group its own copy */
  lt_loop_shared shared;
  lt_sort_kernel(&view, launch->setup, &shared);
}
