/* The vocabulary every kernel-side file uses, whichever backend compiles it: OpenCL C 1.2 on a
 * device, or C11 on the host for the native backend, the reference and the tests. */
#ifndef LT_COMPAT_H
#define LT_COMPAT_H

#ifdef __OPENCL_VERSION__
#include "device/compat_opencl.h"
#else
#include "device/compat_native.h"
#endif

#endif
