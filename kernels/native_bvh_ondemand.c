/* The on-demand BVH kernel compiled as C for the native backend (kernels/bvh_ondemand.h). */
#include "kernels/native_kernels.h"

#include "kernels/bvh_ondemand.h"

void lt__native_bvh_ondemand_kernel(void *arg) {
  lt_od_shared shared;
  lt_od_run((const lt_od_trace_args *)arg, &shared);
}
