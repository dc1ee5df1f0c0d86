/* The on-demand BVH workload (the on-demand paper, Algorithm 1): work-groups trace rays
 * through the tree (traversal/bvh_traverse.h) and build the nodes they wait for, or, out of
 * rays, the nodes nobody asked for yet (builders/bvh_task.h), in one persistent loop. A full
 * build is the same launch without rays. */
#ifndef LT_KERNEL_BVH_ONDEMAND_H
#define LT_KERNEL_BVH_ONDEMAND_H

#include "builders/bvh_task.h"
#include "device/kernel_args.h"
#include "traversal/bvh_traverse.h"

/* The task kinds this workload runs, numbered for its pool. */
enum { LT_OD_KIND_BVH_NODE = 0 };

typedef struct lt_od_args {
  lt_bvh_build build;
  LT_GLOBAL const float *rays; /* 8 floats a ray */
  LT_GLOBAL lt_hit_record *hits;
  lt_i32 ray_count;
  lt_i32 flags;     /* query flags (LT_QUERY_FLAG_*) */
  lt_i32 max_idle_polls;
  lt_i32 speculate; /* whether work-groups out of rays build what nobody asked for */
  lt_i32 prim_count;
  lt_float4 root_lo, root_hi; /* the scene's bounds, for the set-up launch */
#if LT_BVH_WIDE
  const lt_bvh_wide_view *wide; /* native only, not a kernel argument: the wide subtrees */
  lt_i32 answered;              /* native only: rays i with i % answered == 0 already hold their
                                   answer in hits (a sample traced before); 0: none */
#endif
} lt_od_args;

/* The kernel's arguments, in order (device/kernel_args.h). */
#define LT_OD_ARGS(X)                                  \
  LT_BVH_BUILD_ARGS(X, build)                          \
  X(BUF, float, rays, rays)                            \
  X(BUF, lt_hit_record, hits, hits)                    \
  X(VAL, lt_i32, ray_count, ray_count)                 \
  X(VAL, lt_i32, flags, flags)                         \
  X(VAL, lt_i32, max_idle_polls, max_idle_polls)       \
  X(VAL, lt_i32, speculate, speculate)                 \
  X(VAL, lt_i32, prim_count, prim_count)               \
  X(VAL, lt_float4, root_lo, root_lo)                  \
  X(VAL, lt_float4, root_hi, root_hi)

LT_DEVICE lt_bvh_view lt_od_view(const lt_od_args *a) {
  lt_bvh_view v;
  v.nodes = a->build.nodes, v.tris = 0, v.index = a->build.index, v.verts = a->build.verts;
  v.pool = &a->build.pool;
#if LT_BVH_WIDE
  v.wide = a->wide;
#endif
  return v;
}

/* Starts ray i: natively, where the launch has a wide tree, the ray crosses it at once
 * (lt__bvh_wide_start), and only a ray left at an exit goes on in the binary traversal; a ray
 * of a sample answered before this launch is done at once. */
LT_DEVICE void lt_od_start(const lt_od_args *a, lt_bvh_ray *q, lt_i32 i, lt_trace_counters *c) {
#if LT_BVH_WIDE
  if (a->answered > 0 && i % a->answered == 0) {
    /* Done already: its answer stays as it is (the loop writes it back). */
    q->hit = a->hits[i];
    lt_bvh_ray_reset(q, -1);
    return;
  }
  if (a->wide && a->wide->root >= 0) {
    lt__bvh_wide_start(a->wide, a->rays + 8 * (long)i, a->flags, q, c);
    return;
  }
#endif
  (void)c;
  lt_bvh_ray_start(q, a->rays + 8 * (long)i);
}

LT_DEVICE int lt_od_advance(const lt_od_args *a, lt_bvh_ray *q, lt_trace_counters *c) {
  /* Done in its start (most rays on a wide tree): nothing to advance. */
  if (q->cur == -1) return 1;
  lt_bvh_view v = lt_od_view(a);
  return lt_bvh_advance_ondemand(&v, q, a->flags, c);
}

LT_DEVICE void lt_od_flush(const lt_od_args *a, const lt_trace_counters *c) {
  lt_bvh_count(&a->build, LT_BVH_STAT_STEPS, c->traversal_steps);
  lt_bvh_count(&a->build, LT_BVH_STAT_TESTS, c->intersections);
}

/* Only speculative and full builds look for work that no ray of the group waits for. */
#define LT_LOOP_NAME lt_od_run
#define LT_LOOP_ARGS lt_od_args
#define LT_LOOP_POOL(a) (&(a)->build.pool)
#define LT_LOOP_ITEM lt_bvh_ray
#define LT_LOOP_ITEMS_PER_WORK_ITEM LT_LOOP_RAYS_PER_WORK_ITEM
#define LT_LOOP_ITEM_COUNT(a) ((a)->ray_count)
#define LT_LOOP_START(a, q, i, c) lt_od_start(a, q, i, c)
#define LT_LOOP_ADVANCE(a, q, c) lt_od_advance(a, q, c)
#define LT_LOOP_FINISH(a, i, q) ((a)->hits[i] = lt_bvh_ray_answer(q))
#define LT_LOOP_BUILD(a) ((a)->speculate || (a)->build.pool.mode == LT_POOL_FULL)
#define LT_LOOP_MAX_IDLE(a) ((a)->max_idle_polls)
#define LT_LOOP_FLUSH(a, c) lt_od_flush(a, c)
#define LT_LOOP_TASK_KINDS(X) X(LT_OD_KIND_BVH_NODE, lt_bvh_chunk, lt_bvh_end_phase, &a->build)
#include "kernels/persistent_loop_body.h"

/* Both backends' entry: the set-up launch (work-item 0 of work-group 0) makes the super-root and the root's
 * task; a normal launch runs the persistent loop. */
LT_DEVICE void lt_od_kernel(lt_od_args *a, int setup, LT_LOCAL lt_loop_shared *sh) {
  a->build.task_kind = LT_OD_KIND_BVH_NODE;
  if (!setup) {
    lt_od_run(a, sh);
  } else if (lt_group_id() == 0 && lt_local_id() == 0) {
    lt_box bounds;
    bounds.lo[0] = a->root_lo.x, bounds.lo[1] = a->root_lo.y, bounds.lo[2] = a->root_lo.z;
    bounds.hi[0] = a->root_hi.x, bounds.hi[1] = a->root_hi.y, bounds.hi[2] = a->root_hi.z;
    lt_bvh_setup(&a->build, a->prim_count, &bounds);
  }
}

#endif
