/* What a context holds: the chosen backend and, for OpenCL, the device and built program. */
#ifndef LT_CONTEXT_INTERNAL_H
#define LT_CONTEXT_INTERNAL_H

#include <CL/cl.h>

#include "lazytrace.h"

/* An OpenCL entry point of the program, created on first use. */
#define LT__MAX_KERNELS 16
typedef struct lt__kernel {
  const char *name; /* the entry point; NULL for an unused entry of the table */
  cl_kernel kernel;
  int warm;         /* launched once: PoCL has compiled its work-group function */
} lt__kernel;

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
  lt__kernel kernels[LT__MAX_KERNELS]; /* created on first use, by entry-point name */

  /* Host arrays kept between structures (lt__context_take), one per slot. */
  struct {
    void *host;
    size_t bytes;
  } kept[8];
};

/* What the kept arrays hold: the on-demand BVH's per-frame arrays on the native backend, and the
 * Morton sort's working memory. */
enum { LT__KEEP_SORT, LT__KEEP_BOXES, LT__KEEP_INDEX, LT__KEEP_SCRATCH, LT__KEEP_CODES, LT__KEEP_BLOCKS };

/* Host memory of at least `bytes` (16-byte aligned) for a structure that rebuilds every frame:
 * the array last given back to this slot when it is large enough, so that its pages are mapped
 * already (a fresh array of hundreds of megabytes faults in every page, every frame), else a new
 * one. *capacity says how large it is. NULL when out of memory. The caller owns it until it gives
 * it back with lt__context_give; a second structure alive at the same time gets a new array. */
void *lt__context_take(lt_context *ctx, int slot, size_t bytes, size_t *capacity);
/* Keeps `host` (capacity bytes, from lt__context_take) in the slot for the next taker, freeing
 * the smaller of it and what the slot held; freed with the context. */
void lt__context_give(lt_context *ctx, int slot, void *host, size_t capacity);

/* OpenCL backend (runtime/opencl.c). */
lt_status lt__opencl_open(lt_context *ctx, int index);
void lt__opencl_close(lt_context *ctx);
/* Builds the program from the embedded sources on first use. */
lt_status lt__opencl_program(lt_context *ctx);
lt_status lt__opencl_check(cl_int err, const char *what);
/* The entry point `name` of the program (built first if need be). Refuses a local size larger
 * than the kernel supports on this device. */
lt_status lt__opencl_kernel(lt_context *ctx, const char *name, lt__kernel **out);
/* Runs a kernel over `groups` work-groups of the context's local size and waits for it. The
 * first launch of a kernel is counted as compile time (PoCL compiles a work-group function at
 * its first launch): callers make it one with nothing to do (a set-up launch, or no rays). */
lt_status lt__opencl_run(lt_context *ctx, lt__kernel *kernel, size_t groups, const char *what);
int lt__opencl_device_count(void);

/* The embedded kernel source of entry file `path` with its includes expanded, and a hash of
 * that text for cache keys (runtime/source.c). Returns a malloc'ed string or NULL. */
char *lt__kernel_source(const char *path, uint64_t *hash);

/* Native backend (runtime/native.c): runs fn(arg) on `groups` threads, each with its
 * lt_group_id() set, and waits for all. The threads start together: if one cannot be
 * created, none runs fn and the launch fails. */
#define LT__MAX_NATIVE_GROUPS 1024
lt_status lt__native_run(int groups, void (*fn)(void *arg), void *arg);
/* Tests set it to a work-group number whose thread then fails to start; -1 otherwise. */
extern int lt__native_fail_group;
/* A persistent launch watched for stalls (lt__native_run_watched): the pool's progress counter
 * and error word, the error to write, and how long nothing may move. */
typedef struct lt__native_watch {
  int *progress, *error;
  int stall_error;
  double seconds;
} lt__native_watch;
lt_status lt__native_run_watched(int groups, void (*fn)(void *arg), void *arg, const lt__native_watch *watch);
int lt__native_threads(void);

#endif
