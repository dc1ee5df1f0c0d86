/* A lock-free device heap: bump allocation over a buffer allocated up front. Structures built
 * through the pool take their nodes from one (the BVH's node array, the lazy sort's tree), and
 * the kd-tree's reference arrays and the irregular grid's cells will too. Nothing is freed
 * one piece at a time: a rebuild starts a new heap.
 *
 * Allocation is one atomic add on the heap's top, so any number of work-groups allocate at
 * once without a lock. An allocation that does not fit returns -1 and leaves the top past the
 * end; every later one fails as well, and the host sees the top beyond the capacity, reports
 * LT_ERROR_CAPACITY and retries with a larger heap (runtime/heap_host.c). The top is never
 * read back as an offset once it has passed the end, so it cannot wrap around in practice: it
 * would take 2^31 units of failed requests within one launch, and a failed request stops the
 * launch (the caller sets LT_POOL_ERROR_HEAP). */
#ifndef LT_DEVICE_HEAP_H
#define LT_DEVICE_HEAP_H

#include "device/compat.h"

typedef struct lt_heap {
  LT_GLOBAL lt_i32 *top; /* the first free unit; one word the host owns (atomic) */
  lt_i32 capacity;       /* units in the buffer the heap hands out */
} lt_heap;

/* The heap's kernel arguments, for a workload's argument list (device/kernel_args.h): V is the
 * path of the lt_heap inside the view, N a prefix for the parameter names. */
#define LT_HEAP_ARGS(X, V, N) X(BUF, lt_i32, V.top, N##_top) X(VAL, lt_i32, V.capacity, N##_capacity)

/* Takes n consecutive units; returns the first, or -1 when the heap is exhausted. */
LT_DEVICE lt_i32 lt_heap_alloc(const lt_heap *heap, lt_i32 n) {
  lt_i32 at = lt_atomic_add_i32(heap->top, n);
  return at >= 0 && at <= heap->capacity - n ? at : -1;
}

/* Units handed out so far (at most the capacity, whatever failed requests added). */
LT_DEVICE lt_i32 lt_heap_used(const lt_heap *heap) {
  lt_i32 top = lt_atomic_load_i32(heap->top);
  return top < 0 || top > heap->capacity ? heap->capacity : top;
}

#endif
