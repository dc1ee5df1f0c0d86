/* The trace kernel compiled as C for the native backend: each work-group (one thread) takes
 * chunks of rays from a shared counter until none are left. */
#include "kernels/native_kernels.h"

#include "kernels/trace_body.h"

/* Rays per chunk: big enough to amortise the atomic, small enough to balance the threads. */
#define CHUNK 64

void lt__native_trace_kernel(void *arg) {
  lt__native_trace_args *a = arg;
  lt_trace_counters counters = {0, 0};
  uint64_t steps = 0, tests = 0;
  for (;;) {
    lt_u32 begin = lt_atomic_add_u32(&a->next_ray, CHUNK);
    if (begin >= (lt_u32)a->count) break;
    lt_u32 end = begin + CHUNK < (lt_u32)a->count ? begin + CHUNK : (lt_u32)a->count;
    for (lt_u32 i = begin; i < end; i++) {
      if (lt_trace_one(a->rays, (int)i, a->flags, a->nodes, a->tris, a->hits, &counters) != 0)
        __atomic_store_n(&a->error, 1, __ATOMIC_RELAXED);
    }

    /* Fold the 32-bit counters into 64-bit ones after every chunk. */
    steps += counters.traversal_steps, tests += counters.intersections;
    counters.traversal_steps = counters.intersections = 0;
  }
  __atomic_fetch_add(&a->traversal_steps, steps, __ATOMIC_RELAXED);
  __atomic_fetch_add(&a->intersections, tests, __ATOMIC_RELAXED);
}
