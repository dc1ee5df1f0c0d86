/* The host half of a device heap (see heap_host.h and device/heap.h). */
#include "runtime/heap_host.h"

#include "runtime/error.h"

lt_status lt__heap_create(lt_context *ctx, lt__heap *heap, int capacity) {
  heap->capacity = capacity;
  if (capacity < 0) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "a device heap of %d units", capacity);
  return lt__buffer_create(ctx, &heap->top, sizeof(int), NULL, 0);
}

void lt__heap_release(lt__heap *heap) { lt__buffer_release(&heap->top); }

lt_status lt__heap_used(lt_context *ctx, const lt__heap *heap, int *used, int *exhausted) {
  int top = 0;
  lt_status status = lt__buffer_read(ctx, &heap->top, 0, sizeof top, &top);
  if (status) return status;
  *exhausted = top < 0 || top > heap->capacity;
  *used = *exhausted ? heap->capacity : top;
  return LT_OK;
}
