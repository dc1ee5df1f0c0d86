/* The one OpenCL program lazytrace builds: every entry point, includes expanded once. */
#include "kernels/bvh_trace.cl"
#include "kernels/bvh_trace_index.cl"
#include "kernels/grid_trace.cl"
#include "kernels/lazy_sort.cl"
#include "kernels/bvh_ondemand.cl"
#include "kernels/kd_ondemand.cl"
#include "kernels/kd_trace.cl"
