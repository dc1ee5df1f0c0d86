/* OpenCL backend: device discovery, the program built from the embedded sources, and the
 * translation of every cl_int into an lt_status. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "runtime/context_internal.h"
#include "runtime/error.h"

/* Options that keep results bit-identical to the native backend: correctly rounded division
 * and square root (FP_CONTRACT OFF is set in the source itself). */
#define BUILD_OPTIONS "-cl-std=CL1.2 -cl-fp32-correctly-rounded-divide-sqrt -I."

lt_status lt__opencl_check(cl_int err, const char *what) {
  if (err == CL_SUCCESS) return LT_OK;
  if (err == CL_MEM_OBJECT_ALLOCATION_FAILURE || err == CL_OUT_OF_RESOURCES || err == CL_INVALID_BUFFER_SIZE)
    return lt__fail(LT_ERROR_DEVICE_MEMORY, "%s: device out of memory (OpenCL error %d)", what, err);
  return lt__fail(LT_ERROR_OPENCL, "%s failed with OpenCL error %d", what, err);
}

/* Every device of every platform, in platform order; returns how many were written. */
static int list_devices(cl_device_id *out, int max) {
  cl_platform_id platforms[16];
  cl_uint platform_count = 0;
  if (clGetPlatformIDs(16, platforms, &platform_count) != CL_SUCCESS) return 0;
  int n = 0;
  for (cl_uint p = 0; p < platform_count && p < 16; p++) {
    cl_uint count = 0;
    if (clGetDeviceIDs(platforms[p], CL_DEVICE_TYPE_ALL, (cl_uint)(max - n), out + n, &count) != CL_SUCCESS)
      continue;
    n += (int)count;
    if (n >= max) break;
  }
  return n;
}

int lt__opencl_device_count(void) {
  cl_device_id devices[64];
  return list_devices(devices, 64);
}

lt_status lt__opencl_open(lt_context *ctx, int index) {
  cl_device_id devices[64];
  int count = list_devices(devices, 64);
  if (count == 0) return lt__fail(LT_ERROR_NO_DEVICE, "no OpenCL device found (is an ICD such as pocl-opencl-icd installed?)");
  if (index < 0 || index >= count)
    return lt__fail(LT_ERROR_NO_DEVICE, "no OpenCL device %d (found %d)", index, count);
  ctx->device = devices[index];

  char device_name[128] = "";
  cl_uint units = 1;
  clGetDeviceInfo(ctx->device, CL_DEVICE_NAME, sizeof device_name, device_name, NULL);
  clGetDeviceInfo(ctx->device, CL_DEVICE_MAX_COMPUTE_UNITS, sizeof units, &units, NULL);
  snprintf(ctx->name, sizeof ctx->name, "opencl:%d (%s)", index, device_name);

  /* Persistent kernels launch only as many work-groups as run at once (DESIGN.md): on a CPU
   * device (PoCL) that is one per compute unit, and a work-group beyond them would wait for
   * one that never starts. A GPU runs several per compute unit, as many as the kernel's
   * registers allow, which OpenCL does not say. What always fits is 256 work-items a unit: an
   * NVIDIA SM holds 65536 registers and a thread at most 255 (an AMD CU, 4 SIMDs of at least
   * one 64-wide wave at the most registers). On an H100 (docs/results/nvidia_h100.md) 4 groups
   * of 64 or 2 of 128 a unit ran, and 4 of 128 hung: the persistent kernel uses that many
   * registers. More is refused (counting a group in whole 64-wide waves). */
  cl_device_type type = CL_DEVICE_TYPE_GPU;
  clGetDeviceInfo(ctx->device, CL_DEVICE_TYPE, sizeof type, &type, NULL);
  int cpu = (type & CL_DEVICE_TYPE_CPU) != 0;
  /* On a CPU a work-group's work-items run as a loop, and the persistent kernels measured
   * fastest with one work-item (docs/results/pool_scheduler.md); GPUs want wide groups. */
  if (ctx->local_size <= 0) ctx->local_size = cpu ? 1 : 64;
  int wide = (ctx->local_size + 63) / 64 * 64; /* whole 64-wide waves (two NVIDIA warps) */
  int per_unit = cpu || wide >= 256 ? 1 : 256 / wide;
  int most = per_unit * (int)units;
  if (ctx->work_groups > most)
    return lt__fail(LT_ERROR_INVALID_ARGUMENT,
                    "--work-groups %d: %s runs at most %d work-groups of %d at once, and the persistent kernels "
                    "need every one of theirs running (it would hang)",
                    ctx->work_groups, ctx->name, most, ctx->local_size);
  if (ctx->work_groups <= 0) ctx->work_groups = (int)units;

  cl_int err;
  ctx->cl = clCreateContext(NULL, 1, &ctx->device, NULL, NULL, &err);
  if (err != CL_SUCCESS) return lt__opencl_check(err, "clCreateContext");
  ctx->queue = clCreateCommandQueue(ctx->cl, ctx->device, 0, &err);
  return lt__opencl_check(err, "clCreateCommandQueue");
}

/* Keeps the build log for lt_context_build_log(). */
static void save_log(lt_context *ctx) {
  size_t size = 0;
  clGetProgramBuildInfo(ctx->program, ctx->device, CL_PROGRAM_BUILD_LOG, 0, NULL, &size);
  free(ctx->build_log);
  ctx->build_log = calloc(size + 1, 1);
  if (ctx->build_log && size)
    clGetProgramBuildInfo(ctx->program, ctx->device, CL_PROGRAM_BUILD_LOG, size, ctx->build_log, NULL);
}

/* LT_OPENCL_BINARY=FILE writes the built program's binary (PTX on NVIDIA's driver) to FILE, to
 * read what the device compiler made of the fences and the arithmetic. */
static void save_binary(lt_context *ctx) {
  const char *path = getenv("LT_OPENCL_BINARY");
  size_t size = 0;
  if (!path || clGetProgramInfo(ctx->program, CL_PROGRAM_BINARY_SIZES, sizeof size, &size, NULL) != CL_SUCCESS) return;
  unsigned char *binary = malloc(size);
  FILE *f = binary ? fopen(path, "wb") : NULL;
  if (f && clGetProgramInfo(ctx->program, CL_PROGRAM_BINARIES, sizeof binary, &binary, NULL) == CL_SUCCESS)
    fwrite(binary, 1, size, f);
  if (f) fclose(f);
  free(binary);
}

lt_status lt__opencl_program(lt_context *ctx) {
  if (ctx->program) return LT_OK;
  double start = lt_now_ms();
  uint64_t hash = 0;
  char *source = lt__kernel_source("kernels/program.cl", &hash);
  if (!source) return lt__fail(LT_ERROR_PROGRAM_BUILD, "kernel sources are incomplete in this build");

  /* The hash goes into the source as a comment, so any driver cache keyed on text sees changes
   * to included files too. */
  char header[64];
  snprintf(header, sizeof header, "/* lazytrace kernel source %016llx */\n", (unsigned long long)hash);
  const char *parts[2] = {header, source};
  /* The fences the device needs (device/compat_opencl.h): NVIDIA's are PTX. LT_OPENCL_OPTIONS
   * adds build options for experiments (another -D, or -cl-std=CL3.0 -DLT_FENCE_CL20). */
  char vendor[128] = "", options[512];
  clGetDeviceInfo(ctx->device, CL_DEVICE_VENDOR, sizeof vendor, vendor, NULL);
  const char *extra = getenv("LT_OPENCL_OPTIONS");
  snprintf(options, sizeof options, "%s%s %s", BUILD_OPTIONS, strstr(vendor, "NVIDIA") ? " -DLT_FENCE_PTX" : "",
           extra ? extra : "");
  cl_int err;
  ctx->program = clCreateProgramWithSource(ctx->cl, 2, parts, NULL, &err);
  free(source);
  if (err != CL_SUCCESS) return lt__opencl_check(err, "clCreateProgramWithSource");
  err = clBuildProgram(ctx->program, 1, &ctx->device, options, NULL, NULL);
  save_log(ctx);
  if (err == CL_SUCCESS) save_binary(ctx);
  if (err != CL_SUCCESS)
    return lt__fail(LT_ERROR_PROGRAM_BUILD, "kernel build failed (OpenCL error %d):\n%s", err,
                    ctx->build_log ? ctx->build_log : "");
  ctx->compile_ms += lt_now_ms() - start;
  return LT_OK;
}

lt_status lt__opencl_kernel(lt_context *ctx, const char *name, lt__kernel **out) {
  lt_status status = lt__opencl_program(ctx);
  if (status) return status;
  int i = 0;
  for (; i < LT__MAX_KERNELS && ctx->kernels[i].name; i++)
    if (strcmp(ctx->kernels[i].name, name) == 0) return *out = &ctx->kernels[i], LT_OK;
  if (i == LT__MAX_KERNELS) return lt__fail(LT_ERROR_CAPACITY, "more than %d kernel entry points", LT__MAX_KERNELS);

  /* A new entry point: created once, and checked against the local size asked for. */
  cl_int err;
  cl_kernel kernel = clCreateKernel(ctx->program, name, &err);
  if (err != CL_SUCCESS) return lt__opencl_check(err, name);
  size_t max_local = 0;
  clGetKernelWorkGroupInfo(kernel, ctx->device, CL_KERNEL_WORK_GROUP_SIZE, sizeof max_local, &max_local, NULL);
  if (max_local > 0 && (size_t)ctx->local_size > max_local) {
    clReleaseKernel(kernel);
    return lt__fail(LT_ERROR_INVALID_ARGUMENT, "--local-size %d exceeds the %zu work-items kernel %s supports on %s",
                    ctx->local_size, max_local, name, ctx->name);
  }
  ctx->kernels[i] = (lt__kernel){name, kernel, 0};
  *out = &ctx->kernels[i];
  return LT_OK;
}

lt_status lt__opencl_run(lt_context *ctx, lt__kernel *kernel, size_t groups, const char *what) {
  double start = lt_now_ms();
  size_t local = (size_t)ctx->local_size, global = local * groups;
  cl_int err = clEnqueueNDRangeKernel(ctx->queue, kernel->kernel, 1, NULL, &global, &local, 0, NULL, NULL);
  if (err == CL_SUCCESS) err = clFinish(ctx->queue);
  if (!kernel->warm) ctx->compile_ms += lt_now_ms() - start;
  kernel->warm = 1;
  return lt__opencl_check(err, what);
}

void lt__opencl_close(lt_context *ctx) {
  for (int i = 0; i < LT__MAX_KERNELS && ctx->kernels[i].name; i++) clReleaseKernel(ctx->kernels[i].kernel);
  if (ctx->program) clReleaseProgram(ctx->program);
  if (ctx->queue) clReleaseCommandQueue(ctx->queue);
  if (ctx->cl) clReleaseContext(ctx->cl);
}
