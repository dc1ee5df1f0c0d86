/* The vocabulary every kernel-side file uses, whichever backend compiles it: OpenCL C 1.2 on a
 * device, or C11 on the host for the native backend, the reference and the tests. */
#ifndef LT_COMPAT_H
#define LT_COMPAT_H

#ifdef __OPENCL_VERSION__
#include "kernels/compat_opencl.h"
#else
#include "kernels/compat_native.h"
#endif

/* The relative error of a slab distance is at most 2 * gamma(3), with gamma(n) =
 * n * eps / (1 - n * eps) and eps = 2^-24 (Ize 2013; pbrt 3, section 3.9.2). */
#define LT_SLAB_ROUNDING_EPS 3.5762793e-7f

#endif
