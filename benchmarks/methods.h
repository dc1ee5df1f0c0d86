/* The methods the benchmarks compare: the SAH BVH built in full, on request or speculatively,
 * the LBVH, the SAH kd-tree in the same three modes, and (where a benchmark has it) Embree with
 * its default build and with its low-quality (Morton) build; last, the QBVH (built in full on the
 * host from the SAH BVH: the fastest layout to trace a finished tree); then the on-demand BVH
 * with its Morton top (requested, speculative). */
#ifndef LT_BENCH_METHODS_H
#define LT_BENCH_METHODS_H

#include "lazytrace.h"

enum {
  LT_BENCH_FULL,
  LT_BENCH_REQUESTED,
  LT_BENCH_SPECULATIVE,
  LT_BENCH_LBVH,
  LT_BENCH_KD_FULL,
  LT_BENCH_KD_REQUESTED,
  LT_BENCH_KD_SPECULATIVE,
  LT_BENCH_EMBREE,
  LT_BENCH_EMBREE_LOW,
  LT_BENCH_QBVH,
  LT_BENCH_REQUESTED_MORTON,   /* the BVH on request with its Morton top (--top morton) */
  LT_BENCH_SPECULATIVE_MORTON, /* speculatively with its Morton top */
  LT_BENCH_METHODS
};

extern const char *const lt_bench_method_names[LT_BENCH_METHODS];

/* The structure of a lazytrace method (not Embree), with the default parameters. */
lt_structure_config lt_bench_method_config(int method);

/* A batch of rays traced on one structure: closest hit, or any hit. */
typedef struct lt_bench_batch {
  const lt_ray *rays;
  size_t count;
  int any;
} lt_bench_batch;

/* Builds lazytrace method `method` (not Embree) over the scene on lt_bench_context() and traces
 * the batches in order on it, the last batch's hits in `hits`, build and trace statistics added
 * to stats; on failure says on stderr which method failed and why. */
lt_status lt_bench_build_and_trace(const lt_scene *scene, int method, const lt_bench_batch *batches, int count,
                                   lt_hit *hits, lt_stats *stats);

/* The native backend with as many work-groups as threads run concurrently, quiet; made once,
 * NULL (with lt_last_error() saying why) if it cannot be. */
lt_context *lt_bench_native_context(void);

/* Table 1's ambient-occlusion rays: `ao` rays from every hit of the primary rays (found with a
 * full SAH BVH on the native context), up to 5% of the scene's diagonal; returns how many it
 * wrote to ao_rays (room for n * ao). */
size_t lt_bench_table1_ao_rays(const lt_scene *scene, const lt_ray *primary, size_t n, int ao, lt_ray *ao_rays);

/* The context the lazytrace methods run on: the native one, or the first OpenCL device where the
 * environment says LT_BENCH_DEVICE=opencl (Embree keeps the native context's thread count); NULL,
 * said on stderr or by lt_last_error(), if it cannot be made. */
lt_context *lt_bench_context(void);

#endif
