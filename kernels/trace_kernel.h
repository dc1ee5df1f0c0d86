/* What every trace kernel of a finished structure shares: the batch of rays it answers, and
 * the native backend's launch record. A structure's trace kernel is made by
 * kernels/trace_kernel_body.h from its view and a function that traces one ray. */
#ifndef LT_TRACE_KERNEL_H
#define LT_TRACE_KERNEL_H

#include "device/kernel_args.h"
#include "device/types.h"

/* The rays in the ray file's layout (8 floats each) and where their hits go. */
typedef struct lt_trace_batch {
  LT_GLOBAL const float *rays;
  LT_GLOBAL lt_hit_record *hits;
  lt_i32 count;
  lt_i32 flags; /* query flags (LT_QUERY_FLAG_*) */
} lt_trace_batch;

/* The batch's kernel arguments (device/kernel_args.h); V is its path in the view. */
#define LT_TRACE_BATCH_ARGS(X, V)       \
  X(BUF, float, V.rays, rays)           \
  X(BUF, lt_hit_record, V.hits, hits)   \
  X(VAL, lt_i32, V.count, ray_count)    \
  X(VAL, lt_i32, V.flags, flags)

/* Writes a ray's hit in the hit file's layout: a miss is t = +infinity, u = v = 0. */
LT_DEVICE void lt_trace_batch_put(const lt_trace_batch *b, lt_i32 i, lt_hit_record hit) {
  if (hit.prim < 0) hit.t = INFINITY, hit.u = hit.v = 0.0f;
  b->hits[i] = hit;
}

#ifndef __OPENCL_VERSION__
#include <stdint.h>
/* A native launch of a trace kernel. Work-group g owns a contiguous share of the rays and
 * takes chunks of it from the front; once its share is done it takes chunks from the others'
 * shares, so the groups finish together. Shares rather than one counter for all: with every
 * group taking the next chunk of one counter, neighbouring chunks went to different cores, and
 * two threads traced AO rays 13-15% slower (docs/notes/trace_speed.md, "Rays handed out in
 * shares"). Counters are folded into 64 bits. */
typedef struct lt__native_trace_share {
  _Alignas(64) lt_u32 next; /* the share's next ray to hand out: its own cache line */
  lt_u32 end;               /* one past the share's last ray */
} lt__native_trace_share;

typedef struct lt__native_trace_launch {
  const void *view;                /* the structure's view struct */
  lt__native_trace_share *shares;  /* one a work-group */
  int error;                       /* set to 1 when a traversal would overflow its stack */
  uint64_t traversal_steps, intersections;
} lt__native_trace_launch;
#endif

#endif
