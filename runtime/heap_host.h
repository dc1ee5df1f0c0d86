/* The host half of a device heap (device/heap.h): its top word, its capacity, and what a
 * launch left of it. The units themselves live in a buffer the structure owns. */
#ifndef LT_HEAP_HOST_H
#define LT_HEAP_HOST_H

#include "runtime/buffer.h"

typedef struct lt__heap {
  lt__buffer top; /* one word: the first free unit */
  int capacity;
} lt__heap;

/* A heap of `capacity` units, none handed out. */
lt_status lt__heap_create(lt_context *ctx, lt__heap *heap, int capacity);
void lt__heap_release(lt__heap *heap);
/* Units handed out (at most the capacity); *exhausted is set when a request did not fit. */
lt_status lt__heap_used(lt_context *ctx, const lt__heap *heap, int *used, int *exhausted);

/* Fills the heap's entries of a kernel's host arguments (runtime/kernel_args_host.h), whose
 * names start with `prefix` (LT_HEAP_ARGS). */
#define LT__HEAP_HOST_ARGS(args, prefix, heap) \
  ((args)->prefix##_top = &(heap)->top, (args)->prefix##_capacity = (heap)->capacity)

#endif
