/* Device buffers for either backend: host memory on native, a cl_mem on OpenCL. */
#ifndef LT_BUFFER_H
#define LT_BUFFER_H

#include <stddef.h>

#include "runtime/context_internal.h"

typedef struct lt__buffer {
  void *host; /* native backend */
  cl_mem mem; /* OpenCL backend */
  size_t bytes;
  int borrowed; /* native: host memory belongs to someone else (lt__buffer_wrap) */
} lt__buffer;

/* A fill value that leaves the contents undefined (zero on native, where calloc is lazy). */
#define LT_BUFFER_UNINIT ((int)0x7eadbeef)

/* Allocates `bytes` (at least 16), filled from `init` or with the 32-bit `fill` pattern. */
lt_status lt__buffer_create(lt_context *ctx, lt__buffer *buffer, size_t bytes, const void *init, int fill);
lt_status lt__buffer_write(lt_context *ctx, lt__buffer *buffer, size_t offset, size_t bytes, const void *src);
lt_status lt__buffer_read(lt_context *ctx, const lt__buffer *buffer, size_t offset, size_t bytes, void *dst);
lt_status lt__buffer_fill(lt_context *ctx, lt__buffer *buffer, int fill);
void lt__buffer_release(lt__buffer *buffer);
/* A read-only buffer over existing host memory: the native backend uses it in place (no
 * copy); OpenCL copies it once. The memory must outlive the buffer. */
lt_status lt__buffer_wrap(lt_context *ctx, lt__buffer *buffer, const void *host, size_t bytes);
/* A batch's rays and the room for its hits: on native the caller's arrays themselves (kernels
 * read the rays and write the hits in place, no copy), on OpenCL a copy of the rays and a hit
 * buffer. lt__batch_buffers_end reads the hits back (OpenCL, when status is LT_OK), releases
 * both and returns status. A batch of no rays may pass NULL arrays. */
lt_status lt__batch_buffers_begin(lt_context *ctx, lt__buffer *ray_buf, lt__buffer *hit_buf, const lt_ray *rays,
                                  int count, lt_hit *hits);
lt_status lt__batch_buffers_end(lt_context *ctx, lt__buffer *ray_buf, lt__buffer *hit_buf, lt_hit *hits, int count,
                                lt_status status);
/* Where to write a buffer's initial contents: the buffer itself on native, a staging copy on
 * OpenCL that lt__buffer_end_write uploads and frees. NULL when out of memory. */
void *lt__buffer_begin_write(lt_context *ctx, lt__buffer *buffer);
lt_status lt__buffer_end_write(lt_context *ctx, lt__buffer *buffer, void *staging);

/* Fault injection for tests: the buffer allocation this many allocations from now fails as an
 * out-of-memory device would (0: the next one); -1 for none. */
extern int lt__buffer_fail_after;

#endif
