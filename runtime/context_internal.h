/* What a context holds: the chosen backend and, for OpenCL, the device and built program. */
#ifndef LT_CONTEXT_INTERNAL_H
#define LT_CONTEXT_INTERNAL_H

#include <CL/cl.h>

#include "lazytrace.h"

struct lt_context {
  lt_device_kind kind; /* OPENCL or NATIVE once created */
  char name[256];
  int work_groups;     /* persistent work-groups: what runs concurrently */
  int local_size;
  int quiet;
  double compile_ms;
  char *build_log;

  /* OpenCL state; unused on native. */
  cl_device_id device;
  cl_context cl;
  cl_command_queue queue;
  cl_program program;
  cl_kernel trace_kernel;
  cl_kernel sort_kernel;
  cl_kernel ondemand_kernel;
  int ondemand_warm; /* the on-demand kernel has run once (PoCL compiled it) */
};

/* OpenCL backend (runtime/opencl.c). */
lt_status lt__opencl_open(lt_context *ctx, int index);
void lt__opencl_close(lt_context *ctx);
/* Builds the program from the embedded sources on first use. */
lt_status lt__opencl_program(lt_context *ctx);
lt_status lt__opencl_check(cl_int err, const char *what);
int lt__opencl_device_count(void);

/* The embedded kernel source of entry file `path` with its includes expanded, and a hash of
 * that text for cache keys (runtime/source.c). Returns a malloc'ed string or NULL. */
char *lt__kernel_source(const char *path, uint64_t *hash);

/* Native backend (runtime/native.c): runs fn(arg) on `groups` threads, each with its
 * lt_group_id() set, and waits for all. */
lt_status lt__native_run(int groups, void (*fn)(void *arg), void *arg);
int lt__native_threads(void);

#endif
