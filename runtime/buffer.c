/* Device buffers for either backend (see buffer.h). */
#include "runtime/buffer.h"

#include <stdlib.h>
#include <string.h>

#include "runtime/error.h"

int lt__buffer_fail_after = -1;

/* Fault injection: whether this allocation is the one tests asked to fail. */
static int injected_failure(void) {
  if (lt__buffer_fail_after < 0) return 0;
  return lt__buffer_fail_after-- == 0;
}

lt_status lt__buffer_create(lt_context *ctx, lt__buffer *buffer, size_t bytes, const void *init, int fill) {
  memset(buffer, 0, sizeof *buffer);
  if (injected_failure()) return lt__fail(LT_ERROR_DEVICE_MEMORY, "a %zu-byte buffer could not be allocated (injected)", bytes);
  buffer->bytes = bytes < 16 ? 16 : (bytes + 15) / 16 * 16;
  if (ctx->kind == LT_DEVICE_NATIVE) {
    /* calloc leaves untouched pages unmapped: a big zeroed array costs only what is used. An
     * uninitialised buffer skips even that: calloc must clear memory the heap hands back (a
     * memset of every per-frame array), while malloc's untouched pages stay unmapped too. */
    if (fill == 0 && !init) {
      buffer->host = calloc(1, buffer->bytes);
      if (!buffer->host) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory for a %zu-byte buffer", bytes);
      return LT_OK;
    }
    buffer->host = aligned_alloc(64, (buffer->bytes + 63) / 64 * 64);
    if (!buffer->host) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory for a %zu-byte buffer", bytes);
  } else {
    cl_int err;
    buffer->mem = clCreateBuffer(ctx->cl, CL_MEM_READ_WRITE, buffer->bytes, NULL, &err);
    if (err != CL_SUCCESS) return lt__opencl_check(err, "clCreateBuffer");
  }
  lt_status status = fill == LT_BUFFER_UNINIT ? LT_OK : lt__buffer_fill(ctx, buffer, fill);
  if (!status && init && bytes) status = lt__buffer_write(ctx, buffer, 0, bytes, init);
  return status;
}

lt_status lt__buffer_fill(lt_context *ctx, lt__buffer *buffer, int fill) {
  if (ctx->kind == LT_DEVICE_NATIVE) {
    int *p = buffer->host;
    for (size_t i = 0; i < buffer->bytes / sizeof(int); i++) p[i] = fill;
    return LT_OK;
  }
  cl_int err = clEnqueueFillBuffer(ctx->queue, buffer->mem, &fill, sizeof fill, 0, buffer->bytes, 0, NULL, NULL);
  return lt__opencl_check(err, "clEnqueueFillBuffer");
}

lt_status lt__buffer_write(lt_context *ctx, lt__buffer *buffer, size_t offset, size_t bytes, const void *src) {
  if (ctx->kind == LT_DEVICE_NATIVE) {
    memcpy((char *)buffer->host + offset, src, bytes);
    return LT_OK;
  }
  cl_int err = clEnqueueWriteBuffer(ctx->queue, buffer->mem, CL_TRUE, offset, bytes, src, 0, NULL, NULL);
  return lt__opencl_check(err, "clEnqueueWriteBuffer");
}

lt_status lt__buffer_read(lt_context *ctx, const lt__buffer *buffer, size_t offset, size_t bytes, void *dst) {
  if (ctx->kind == LT_DEVICE_NATIVE) {
    memcpy(dst, (const char *)buffer->host + offset, bytes);
    return LT_OK;
  }
  cl_int err = clEnqueueReadBuffer(ctx->queue, buffer->mem, CL_TRUE, offset, bytes, dst, 0, NULL, NULL);
  return lt__opencl_check(err, "clEnqueueReadBuffer");
}

lt_status lt__buffer_wrap(lt_context *ctx, lt__buffer *buffer, const void *host, size_t bytes) {
  memset(buffer, 0, sizeof *buffer);
  if (injected_failure()) return lt__fail(LT_ERROR_DEVICE_MEMORY, "a %zu-byte buffer could not be allocated (injected)", bytes);
  buffer->bytes = bytes;
  if (ctx->kind == LT_DEVICE_NATIVE) {
    buffer->host = (void *)host;
    buffer->borrowed = 1;
    return LT_OK;
  }
  cl_int err;
  buffer->mem = clCreateBuffer(ctx->cl, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, bytes < 16 ? 16 : bytes, (void *)host, &err);
  return lt__opencl_check(err, "clCreateBuffer");
}

lt_status lt__batch_buffers_begin(lt_context *ctx, lt__buffer *ray_buf, lt__buffer *hit_buf, const lt_ray *rays,
                                  int count, lt_hit *hits) {
  size_t ray_bytes = (size_t)count * sizeof(lt_ray), hit_bytes = (size_t)count * sizeof(lt_hit);
  memset(hit_buf, 0, sizeof *hit_buf);
  /* OpenCL cannot copy from no memory: an empty batch gets a small buffer instead. */
  lt_status status = count > 0 || ctx->kind == LT_DEVICE_NATIVE ? lt__buffer_wrap(ctx, ray_buf, rays, ray_bytes)
                                                               : lt__buffer_create(ctx, ray_buf, 16, NULL, 0);
  if (status) return status;
  if (ctx->kind == LT_DEVICE_NATIVE) status = lt__buffer_wrap(ctx, hit_buf, hits, hit_bytes);
  else status = lt__buffer_create(ctx, hit_buf, hit_bytes, NULL, LT_BUFFER_UNINIT);
  if (status) lt__buffer_release(ray_buf);
  return status;
}

lt_status lt__batch_buffers_end(lt_context *ctx, lt__buffer *ray_buf, lt__buffer *hit_buf, lt_hit *hits, int count,
                                lt_status status) {
  if (!status && count > 0 && ctx->kind == LT_DEVICE_OPENCL)
    status = lt__buffer_read(ctx, hit_buf, 0, (size_t)count * sizeof(lt_hit), hits);
  lt__buffer_release(ray_buf);
  lt__buffer_release(hit_buf);
  return status;
}

void *lt__buffer_begin_write(lt_context *ctx, lt__buffer *buffer) {
  return ctx->kind == LT_DEVICE_NATIVE ? buffer->host : malloc(buffer->bytes);
}

lt_status lt__buffer_end_write(lt_context *ctx, lt__buffer *buffer, void *staging) {
  if (ctx->kind == LT_DEVICE_NATIVE) return LT_OK;
  lt_status status = lt__buffer_write(ctx, buffer, 0, buffer->bytes, staging);
  free(staging);
  return status;
}

void lt__buffer_release(lt__buffer *buffer) {
  if (!buffer->borrowed) free(buffer->host);
  if (buffer->mem) clReleaseMemObject(buffer->mem);
  memset(buffer, 0, sizeof *buffer);
}
