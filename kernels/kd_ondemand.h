/* The on-demand kd-tree workload (the on-demand paper, Algorithm 1 and section 3.5):
 * work-groups trace rays through the tree (traversal/kd_traverse.h) and build the cells they
 * wait for, or, out of rays, the cells nobody asked for yet (builders/kd_task.h), in one
 * persistent loop. A full build is the same launch without rays. */
#ifndef LT_KERNEL_KD_ONDEMAND_H
#define LT_KERNEL_KD_ONDEMAND_H

#include "builders/kd_task.h"
#include "device/kernel_args.h"
#include "traversal/kd_stackless.h"

/* The task kinds this workload runs, numbered for its pool. */
enum { LT_KD_KIND_NODE = 0 };

typedef struct lt_kd_args {
  lt_kd_build build;
  LT_GLOBAL const float *rays; /* 8 floats a ray */
  LT_GLOBAL lt_hit_record *hits;
  lt_i32 ray_count;
  lt_i32 flags;     /* query flags (LT_QUERY_FLAG_*) */
  lt_i32 max_idle_polls;
  lt_i32 speculate; /* whether work-groups out of rays build what nobody asked for */
  lt_i32 traversal; /* LT_KD_TRAVERSE_*: the stackless ones on a finished tree only */
  lt_i32 prim_count;
  lt_float4 root_lo, root_hi; /* the scene's bounds: the root cell */
} lt_kd_args;


/* The kernel's arguments, in order (device/kernel_args.h). */
#define LT_KD_ARGS(X)                            \
  LT_KD_BUILD_ARGS(X, build)                     \
  X(BUF, float, rays, rays)                      \
  X(BUF, lt_hit_record, hits, hits)              \
  X(VAL, lt_i32, ray_count, ray_count)           \
  X(VAL, lt_i32, flags, flags)                   \
  X(VAL, lt_i32, max_idle_polls, max_idle_polls) \
  X(VAL, lt_i32, speculate, speculate)           \
  X(VAL, lt_i32, traversal, traversal)           \
  X(VAL, lt_i32, prim_count, prim_count)         \
  X(VAL, lt_float4, root_lo, root_lo)            \
  X(VAL, lt_float4, root_hi, root_hi)

LT_DEVICE lt_box lt_kd_root_cell(const lt_kd_args *a) {
  lt_box cell;
  cell.lo[0] = a->root_lo.x, cell.lo[1] = a->root_lo.y, cell.lo[2] = a->root_lo.z;
  cell.hi[0] = a->root_hi.x, cell.hi[1] = a->root_hi.y, cell.hi[2] = a->root_hi.z;
  return cell;
}

LT_DEVICE lt_kd_view lt_kd_args_view(const lt_kd_args *a) {
  lt_kd_view v;
  v.nodes = a->build.nodes, v.refs = a->build.refs, v.verts = a->build.verts;
  v.parents = a->build.parents, v.cells = a->build.cells;
  v.pool = &a->build.pool;
  v.bounds = lt_kd_root_cell(a);
  return v;
}

LT_DEVICE void lt_kd_start(const lt_kd_args *a, lt_kd_ray *q, lt_i32 i) {
  lt_box cell = lt_kd_root_cell(a);
  lt_kd_ray_start(q, a->rays + 8 * (long)i, &cell);
}

/* Out of line on the native backend: inlined into the persistent loop, the traversal ran the
 * plain trace kernel's instructions 1.13-1.25x slower (the time piled up on its node loads);
 * compiled as a function of its own, as the plain kernel's is, it costs what it costs there,
 * for one call a ray. docs/notes/kdtree.md ("The persistent kernel's tax") has what was
 * measured. OpenCL inlines it as before. */
LT_DEVICE_OUTLINE int lt_kd_args_advance(const lt_kd_args *a, lt_kd_ray *q, lt_trace_counters *c) {
  lt_kd_view v = lt_kd_args_view(a);
  if (a->traversal == LT_KD_TRAVERSE_STACK) return lt_kd_advance(&v, q, a->flags, c);
  lt_kd_advance_stackless(&v, q, a->flags, a->traversal == LT_KD_TRAVERSE_BACKTRACK, c);
  return 1;
}

LT_DEVICE void lt_kd_flush(const lt_kd_args *a, const lt_trace_counters *c) {
  lt_kd_count(&a->build, LT_KD_STAT_STEPS, c->traversal_steps);
  lt_kd_count(&a->build, LT_KD_STAT_TESTS, c->intersections);
}

/* Only speculative and full builds look for work that no ray of the group waits for. */
#define LT_LOOP_NAME lt_kd_run
#define LT_LOOP_ARGS lt_kd_args
#define LT_LOOP_POOL(a) (&(a)->build.pool)
#define LT_LOOP_ITEM lt_kd_ray
#define LT_LOOP_ITEMS_PER_WORK_ITEM LT_LOOP_RAYS_PER_WORK_ITEM
#define LT_LOOP_ITEM_COUNT(a) ((a)->ray_count)
#define LT_LOOP_START(a, q, i, c) lt_kd_start(a, q, i)
#define LT_LOOP_ADVANCE(a, q, c) lt_kd_args_advance(a, q, c)
#define LT_LOOP_FINISH(a, i, q) ((a)->hits[i] = lt_kd_ray_answer(q))
#define LT_LOOP_BUILD(a) ((a)->speculate || (a)->build.pool.mode == LT_POOL_FULL)
#define LT_LOOP_MAX_IDLE(a) ((a)->max_idle_polls)
#define LT_LOOP_FLUSH(a, c) lt_kd_flush(a, c)
#define LT_LOOP_TASK_KINDS(X) X(LT_KD_KIND_NODE, lt_kd_chunk, lt_kd_end_phase, &a->build)
#include "kernels/persistent_loop_body.h"

/* Both backends' entry: the set-up launch (work-item 0 of work-group 0) makes the super-root
 * and the root's task; a normal launch runs the persistent loop. */
LT_DEVICE void lt_kd_kernel(lt_kd_args *a, int setup, LT_LOCAL lt_loop_shared *sh) {
  a->build.task_kind = LT_KD_KIND_NODE;
  if (!setup) {
    lt_kd_run(a, sh);
  } else if (lt_group_id() == 0 && lt_local_id() == 0) {
    lt_box cell = lt_kd_root_cell(a);
    lt_kd_setup(&a->build, a->prim_count, &cell);
  }
}

#endif
