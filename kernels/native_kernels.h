/* Native entries of the kernels: each runs on every native work-group (see lt__native_run). */
#ifndef LT_NATIVE_KERNELS_H
#define LT_NATIVE_KERNELS_H

#include <stdint.h>

#include "device/bvh_node.h"

typedef struct lt__native_trace_args {
  const float *rays; /* 8 floats a ray */
  int count;
  int flags;         /* query flags (LT_QUERY_FLAG_*: any hit, triangle and slab tests) */
  const lt_bvh_node *nodes;
  const lt_tri *tris;
  lt_hit_record *hits;
  lt_u32 next_ray;   /* shared: the next ray to hand out */
  int error;         /* set to 1 on a stack overflow */
  uint64_t traversal_steps, intersections;
} lt__native_trace_args;

/* kernels/native_trace.c: arg is an lt__native_trace_args. */
void lt__native_trace_kernel(void *arg);
/* kernels/native_lazy_sort.c: arg is an lt_sort (kernels/lazy_sort.h). */
void lt__native_lazy_sort_kernel(void *arg);
/* kernels/native_bvh_ondemand.c: arg is an lt_od_trace_args (kernels/bvh_ondemand.h). */
void lt__native_bvh_ondemand_kernel(void *arg);

#endif
