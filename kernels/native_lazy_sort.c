/* The lazy-sort workload compiled as C for the native backend (see kernels/lazy_sort.h). */
#include "kernels/native_kernels.h"

#include "kernels/lazy_sort.h"

void lt__native_lazy_sort_kernel(void *arg) {
  lt_sort_shared shared;
  lt_sort_run((const lt_sort *)arg, &shared);
}
