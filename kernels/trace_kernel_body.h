/* A trace kernel for a finished structure, instantiated by include:
 *
 *   #define LT_TRACE_ENTRY       the OpenCL entry point's name
 *   #define LT_TRACE_NATIVE      the native backend's function (void fn(void *launch))
 *   #define LT_TRACE_VIEW        the structure's view struct; its member `batch` is an lt_trace_batch
 *   #define LT_TRACE_ARGS(X)     its kernel arguments (device/kernel_args.h)
 *   #define LT_TRACE_ONE(v, i, c) traces ray i of the batch and writes its hit; 0, or -1 when
 *                                the traversal would overflow its stack
 *   or, native only,
 *   #define LT_TRACE_RANGE(v, begin, end, c)  the same for rays [begin, end) (0, or nonzero
 *                                when some traversal would overflow): one call a chunk, and
 *   #define LT_TRACE_STATE       optionally, a type of per-thread state kept across the thread's
 *                                chunks (zero at first), passed as LT_TRACE_RANGE's fifth argument
 *
 * OpenCL runs one work-item per ray; the native backend runs one thread per work-group, each
 * taking chunks of rays from its own share of them, then from the others' (kernels/trace_kernel.h,
 * lt__native_trace_share) until none are left. No include guard. */
#include "kernels/trace_kernel.h"

#ifdef __OPENCL_VERSION__
__kernel void LT_TRACE_ENTRY(LT_TRACE_ARGS(LT_ARG_PARAM) __global lt_u32 *counters, __global int *error) {
  LT_TRACE_VIEW view;
  LT_TRACE_ARGS(LT_ARG_FILL)
  lt_trace_counters local_counters = {0, 0};
  int i = lt_global_id();
  if (i < view.batch.count && LT_TRACE_ONE(&view, i, &local_counters) != 0) atomic_xchg(error, 1);

  /* One counter slot per work-group keeps the sums far from 32-bit overflow. */
  __global lt_u32 *slot = counters + 2 * lt_group_id();
  if (local_counters.traversal_steps) lt_atomic_add_u32(slot, local_counters.traversal_steps);
  if (local_counters.intersections) lt_atomic_add_u32(slot + 1, local_counters.intersections);
}
#else
void LT_TRACE_NATIVE(void *arg) {
  /* Rays per chunk: big enough to amortise the atomic, small enough to balance the threads. */
  enum { CHUNK = 64 };
  lt__native_trace_launch *launch = arg;
  const LT_TRACE_VIEW *view = launch->view;
  lt_trace_counters counters = {0, 0};
  uint64_t steps = 0, tests = 0;
#ifdef LT_TRACE_STATE
  LT_TRACE_STATE state;
  memset(&state, 0, sizeof state);
#endif
  /* The group's own share first, then what is left of the others' (lt__native_trace_share). */
  int groups = lt_num_groups();
  for (int k = 0; k < groups; k++) {
    lt__native_trace_share *share = &launch->shares[(lt_group_id() + k) % groups];
    for (;;) {
      lt_u32 begin = lt_atomic_add_u32(&share->next, CHUNK);
      if (begin >= share->end) break;
      lt_u32 end = begin + CHUNK < share->end ? begin + CHUNK : share->end;
#if defined(LT_TRACE_RANGE) && defined(LT_TRACE_STATE)
      if (LT_TRACE_RANGE(view, (lt_i32)begin, (lt_i32)end, &counters, &state) != 0)
        __atomic_store_n(&launch->error, 1, __ATOMIC_RELAXED);
#elif defined(LT_TRACE_RANGE)
      if (LT_TRACE_RANGE(view, (lt_i32)begin, (lt_i32)end, &counters) != 0)
        __atomic_store_n(&launch->error, 1, __ATOMIC_RELAXED);
#else
      for (lt_u32 i = begin; i < end; i++)
        if (LT_TRACE_ONE(view, (lt_i32)i, &counters) != 0) __atomic_store_n(&launch->error, 1, __ATOMIC_RELAXED);
#endif

      /* Fold the 32-bit counters into 64-bit ones after every chunk. */
      steps += counters.traversal_steps, tests += counters.intersections;
      counters.traversal_steps = counters.intersections = 0;
    }
  }
  __atomic_fetch_add(&launch->traversal_steps, steps, __ATOMIC_RELAXED);
  __atomic_fetch_add(&launch->intersections, tests, __ATOMIC_RELAXED);
}
#endif

#undef LT_TRACE_ENTRY
#undef LT_TRACE_NATIVE
#undef LT_TRACE_VIEW
#undef LT_TRACE_ARGS
#undef LT_TRACE_ONE
#undef LT_TRACE_RANGE
#undef LT_TRACE_STATE
