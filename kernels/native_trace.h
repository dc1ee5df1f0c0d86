/* Native entry of the trace kernel (kernels/native_trace.c). */
#ifndef LT_NATIVE_TRACE_H
#define LT_NATIVE_TRACE_H

#include <stdint.h>

#include "kernels/shared_types.h"

typedef struct lt__native_trace_args {
  const float *rays; /* 8 floats a ray */
  int count;
  int any_hit;
  const lt_bvh_node *nodes;
  const lt_tri *tris;
  lt_hit_record *hits;
  lt_u32 next_ray;   /* shared: the next ray to hand out */
  int error;         /* set to 1 on a stack overflow */
  uint64_t traversal_steps, intersections;
} lt__native_trace_args;

/* Runs on every native work-group; see lt__native_run. */
void lt__native_trace_kernel(void *arg);

#endif
