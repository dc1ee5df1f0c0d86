/* Device buffers for either backend: host memory on native, a cl_mem on OpenCL. */
#ifndef LT_BUFFER_H
#define LT_BUFFER_H

#include <stddef.h>

#include "runtime/context_internal.h"

typedef struct lt__buffer {
  void *host; /* native backend */
  cl_mem mem; /* OpenCL backend */
  size_t bytes;
} lt__buffer;

/* Allocates `bytes` (at least 16), filled from `init` or with the 32-bit `fill` pattern. */
lt_status lt__buffer_create(lt_context *ctx, lt__buffer *buffer, size_t bytes, const void *init, int fill);
lt_status lt__buffer_write(lt_context *ctx, lt__buffer *buffer, size_t offset, size_t bytes, const void *src);
lt_status lt__buffer_read(lt_context *ctx, const lt__buffer *buffer, size_t offset, size_t bytes, void *dst);
lt_status lt__buffer_fill(lt_context *ctx, lt__buffer *buffer, int fill);
void lt__buffer_release(lt__buffer *buffer);

#endif
