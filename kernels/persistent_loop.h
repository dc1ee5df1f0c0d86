/* The persistent loop every pool workload runs (the on-demand paper, Algorithm 1): each
 * work-group advances its own items (rays, queries) and, when one waits for an unbuilt node or
 * it has none left, works chunks of tasks from the pool; a restart re-checks the waiting items
 * after each chunk and after each search that found nothing. The loop owns the work-group's
 * decisions, its local memory, the local-size limit and termination; a workload brings its
 * item hooks and the task kinds it runs.
 *
 * One body, instantiated per workload ("template by include", as Cycles makes its kernels):
 *
 *   #define LT_LOOP_NAME        the function to define: void NAME(const ARGS *a, LT_LOCAL lt_loop_shared *sh)
 *   #define LT_LOOP_ARGS        the workload's view struct
 *   #define LT_LOOP_POOL(a)     a const lt_pool * from it
 *   #define LT_LOOP_ITEM        the state of one item in flight (kept across suspensions)
 *   #define LT_LOOP_ITEMS_PER_WORK_ITEM  items a work-item takes per batch (one counter update each)
 *   #define LT_LOOP_ITEM_COUNT(a)        items of this launch
 *   #define LT_LOOP_START(a, q, i, c)    begins item i in *q (c: the counters, for a start
 *                                        that already advances it)
 *   #define LT_LOOP_ADVANCE(a, q, c)     advances *q; 1 when done, 0 while it waits for a node
 *   #define LT_LOOP_FINISH(a, i, q)      writes item i's answer
 *   #define LT_LOOP_BUILD(a)    whether to take chunks no item of the group waits for
 *   #define LT_LOOP_MAX_IDLE(a) the stall cap (lt_pool_decide)
 *   #define LT_LOOP_FLUSH(a, c) adds the work-group's lt_trace_counters to its statistics
 *   #define LT_LOOP_TASK_KINDS(X)  one X(KIND, CHUNK, END_PHASE, CONTEXT) per task kind: CHUNK(ctx,
 *                       slot, chunk, lid, lsize) runs a chunk on every work-item, END_PHASE(ctx,
 *                       slot) runs on work-item 0 of the group that finished a phase's last
 *                       chunk; CONTEXT is an expression of `a` giving their first argument
 *   #include "kernels/persistent_loop_body.h"
 *
 * Every barrier sits in the loop's straight-line body, never under a condition: OpenCL
 * implementations that run a work-group as loops over its work-items (PoCL) need it so. */
#ifndef LT_PERSISTENT_LOOP_H
#define LT_PERSISTENT_LOOP_H

#include "device/pool.h"
#include "device/types.h"

/* The widest work-group a persistent kernel runs: the group's local memory holds one flag per
 * work-item. The host refuses a larger --local-size before any launch. */
#define LT_MAX_LOCAL_SIZE 256

/* Rays a work-item of a tracing workload takes at a time (its LT_LOOP_ITEMS_PER_WORK_ITEM): one
 * update of the shared counter a batch, not a ray. On OpenCL a work-group's work-items take
 * every lsize-th ray of lsize * 64. On the native backend a work-group is one thread: with 64
 * rays a batch, neighbouring stretches of the image went to different cores, and the any-hit
 * guesses (traversal/bvh8_guess.h), which learn from the thread's last rays, and the caches
 * lost much of that coherence; 512 traced house-grid:3x3@close's primary + 8 AO rows about a
 * quarter faster on two threads (docs/notes/trace_speed.md, "Rays handed out in shares"). */
#ifdef __OPENCL_VERSION__
#define LT_LOOP_RAYS_PER_WORK_ITEM 64
#else
#define LT_LOOP_RAYS_PER_WORK_ITEM 512
#endif

/* What a work-group shares in local memory. */
typedef struct lt_loop_shared {
  lt_pool_round round;
  lt_i32 pending[LT_MAX_LOCAL_SIZE]; /* whether each work-item's item waits */
} lt_loop_shared;

#endif
