/* Contexts: choosing a backend (OpenCL, or native when there is none) and listing devices. */
#include <stdlib.h>
#include <string.h>

#include "kernels/persistent_loop.h"
#include "runtime/context_internal.h"
#include "runtime/error.h"

lt_status lt_context_create(const lt_context_config *config, lt_context **out) {
  lt_context_config defaults = {0};
  if (!out) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt_context_create: NULL out");
  if (!config) config = &defaults;
  if (config->work_groups < 0 || config->local_size < 0)
    return lt__fail(LT_ERROR_INVALID_ARGUMENT, "work-groups and local size must be positive (0 for the default)");
  if (config->work_groups > LT__MAX_NATIVE_GROUPS)
    return lt__fail(LT_ERROR_INVALID_ARGUMENT, "--work-groups %d: at most %d", config->work_groups, LT__MAX_NATIVE_GROUPS);
  if (config->local_size > LT_MAX_LOCAL_SIZE)
    return lt__fail(LT_ERROR_INVALID_ARGUMENT,
                    "--local-size %d exceeds %d, the widest work-group the persistent kernels hold in local memory",
                    config->local_size, LT_MAX_LOCAL_SIZE);
  lt_context *ctx = calloc(1, sizeof *ctx);
  if (!ctx) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory for a context");
  ctx->work_groups = config->work_groups;
  ctx->local_size = config->local_size;
  ctx->quiet = config->quiet;

  /* OpenCL when asked or available; auto falls back to native and says why. */
  lt_status status = LT_OK;
  if (config->device == LT_DEVICE_OPENCL || config->device == LT_DEVICE_AUTO) {
    ctx->kind = LT_DEVICE_OPENCL;
    status = lt__opencl_open(ctx, config->opencl_index);
    if (status != LT_OK && config->device == LT_DEVICE_AUTO) {
      if (!ctx->quiet) fprintf(stderr, "lazytrace: %s; using the native backend\n", lt_last_error());
      lt__opencl_close(ctx);
      memset(ctx, 0, sizeof *ctx);
      ctx->work_groups = config->work_groups;
      ctx->quiet = config->quiet;
      status = LT_OK;
      ctx->kind = LT_DEVICE_NATIVE;
    }
  } else {
    ctx->kind = LT_DEVICE_NATIVE;
  }
  if (status != LT_OK) {
    lt_context_destroy(ctx);
    return status;
  }
  if (ctx->kind == LT_DEVICE_NATIVE) {
    if (ctx->work_groups <= 0) ctx->work_groups = lt__native_threads();
    ctx->local_size = 1;
    snprintf(ctx->name, sizeof ctx->name, "native (%d threads)", ctx->work_groups);
  }
  *out = ctx;
  return LT_OK;
}

void lt_context_destroy(lt_context *ctx) {
  if (!ctx) return;
  lt__opencl_close(ctx);
  free(ctx->build_log);
  for (size_t i = 0; i < sizeof ctx->kept / sizeof ctx->kept[0]; i++) free(ctx->kept[i].host);
  free(ctx);
}

void *lt__context_take(lt_context *ctx, int slot, size_t bytes, size_t *capacity) {
  void *host = ctx->kept[slot].host;
  *capacity = ctx->kept[slot].bytes;
  ctx->kept[slot].host = NULL, ctx->kept[slot].bytes = 0;
  if (host && *capacity >= bytes) return host;
  free(host);
  *capacity = (bytes + 15) / 16 * 16;
  host = aligned_alloc(16, *capacity > 0 ? *capacity : 16);
  if (!host) *capacity = 0;
  return host;
}

void lt__context_give(lt_context *ctx, int slot, void *host, size_t capacity) {
  if (!host) return;
  if (ctx->kept[slot].bytes > capacity) {
    free(host);
    return;
  }
  free(ctx->kept[slot].host);
  ctx->kept[slot].host = host, ctx->kept[slot].bytes = capacity;
}

const char *lt_context_device_name(const lt_context *ctx) { return ctx->name; }
lt_device_kind lt_context_device_kind(const lt_context *ctx) { return ctx->kind; }
int lt_context_work_groups(const lt_context *ctx) { return ctx->work_groups; }
double lt_context_compile_ms(const lt_context *ctx) { return ctx->compile_ms; }
const char *lt_context_build_log(const lt_context *ctx) { return ctx->build_log ? ctx->build_log : ""; }

lt_status lt_devices_print(FILE *out) {
  cl_platform_id platforms[16];
  cl_uint platform_count = 0;
  int index = 0;
  if (clGetPlatformIDs(16, platforms, &platform_count) != CL_SUCCESS) platform_count = 0;
  for (cl_uint p = 0; p < platform_count && p < 16; p++) {
    char platform_name[128] = "";
    clGetPlatformInfo(platforms[p], CL_PLATFORM_NAME, sizeof platform_name, platform_name, NULL);
    cl_device_id devices[16];
    cl_uint count = 0;
    if (clGetDeviceIDs(platforms[p], CL_DEVICE_TYPE_ALL, 16, devices, &count) != CL_SUCCESS) continue;
    for (cl_uint d = 0; d < count && d < 16; d++, index++) {
      char name[128] = "", version[128] = "";
      cl_uint units = 0;
      cl_ulong memory = 0;
      clGetDeviceInfo(devices[d], CL_DEVICE_NAME, sizeof name, name, NULL);
      clGetDeviceInfo(devices[d], CL_DEVICE_VERSION, sizeof version, version, NULL);
      clGetDeviceInfo(devices[d], CL_DEVICE_MAX_COMPUTE_UNITS, sizeof units, &units, NULL);
      clGetDeviceInfo(devices[d], CL_DEVICE_GLOBAL_MEM_SIZE, sizeof memory, &memory, NULL);
      fprintf(out, "opencl:%d  %s  [%s; %s; %u compute units; %.1f GiB]\n", index, name, platform_name, version,
              units, memory / 1073741824.0);
    }
  }
  if (index == 0) fprintf(out, "(no OpenCL device found)\n");
  fprintf(out, "native    %d threads (one work-group each, local size 1)\n", lt__native_threads());
  return LT_OK;
}
