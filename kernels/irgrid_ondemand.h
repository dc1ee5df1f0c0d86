/* The irregular grid's workload (Perard-Gayot et al. 2017, with cells on demand): work-groups
 * trace rays through the grid (traversal/irgrid_traverse.h) and build the top cells they wait
 * for, or, out of rays, the top cells nobody asked for yet (builders/irgrid_task.h), in one
 * persistent loop. A full build is the same launch without rays, and, merging across the grid,
 * a second launch of the merge passes (lt_irg_merge_kernel). */
#ifndef LT_KERNEL_IRGRID_ONDEMAND_H
#define LT_KERNEL_IRGRID_ONDEMAND_H

#include "builders/irgrid_global.h"
#include "device/kernel_args.h"
#include "traversal/irgrid_traverse.h"

typedef struct lt_irg_args {
  lt_irg_build build;
  LT_GLOBAL const float *rays; /* 8 floats a ray */
  LT_GLOBAL lt_hit_record *hits;
  lt_i32 ray_count;
  lt_i32 flags; /* query flags (LT_QUERY_FLAG_*) */
  lt_i32 max_idle_polls;
  lt_i32 speculate; /* whether work-groups out of rays build what nobody asked for */
} lt_irg_args;

/* The kernel's arguments, in order (device/kernel_args.h). */
#define LT_IRG_ARGS(X)                           \
  LT_IRG_BUILD_ARGS(X, build)                    \
  X(BUF, float, rays, rays)                      \
  X(BUF, lt_hit_record, hits, hits)              \
  X(VAL, lt_i32, ray_count, ray_count)           \
  X(VAL, lt_i32, flags, flags)                   \
  X(VAL, lt_i32, max_idle_polls, max_idle_polls) \
  X(VAL, lt_i32, speculate, speculate)

LT_DEVICE lt_irg_view lt_irg_args_view(const lt_irg_args *a) {
  lt_irg_view v;
  v.header = a->build.header, v.top_map = a->build.top_map, v.sub_maps = a->build.sub_maps;
  v.refs = a->build.refs, v.cells = a->build.cells, v.cells16 = 0, v.verts = a->build.verts;
  v.pool = &a->build.pool, v.fine_dims = a->build.fine_dims, v.shift = a->build.shift;
  return v;
}

LT_DEVICE int lt_irg_args_advance(const lt_irg_args *a, lt_irg_ray *q, lt_trace_counters *c) {
  lt_irg_view v = lt_irg_args_view(a);
  return lt_irg_advance(&v, q, a->flags, c);
}

LT_DEVICE void lt_irg_flush(const lt_irg_args *a, const lt_trace_counters *c) {
  lt_irg_count(&a->build, LT_IRG_STAT_STEPS, c->traversal_steps);
  lt_irg_count(&a->build, LT_IRG_STAT_TESTS, c->intersections);
}

/* The persistent loop, once with the kinds that build top cells (and trace), once with the
 * kinds of the merge passes across the grid that a full build runs after them. Two kernels
 * instead of one loop over all five kinds: PoCL with LLVM 15 crashes (in InstCombine) while
 * compiling the loop with all of them inlined into one work-group function, and the merge
 * passes can only start once every top cell is built anyway. */
#define LT_LOOP_NAME lt_irg_run
#define LT_LOOP_ARGS lt_irg_args
#define LT_LOOP_POOL(a) (&(a)->build.pool)
#define LT_LOOP_ITEM lt_irg_ray
#define LT_LOOP_ITEMS_PER_WORK_ITEM LT_LOOP_RAYS_PER_WORK_ITEM
#define LT_LOOP_ITEM_COUNT(a) ((a)->ray_count)
#define LT_LOOP_START(a, q, i, c) lt_irg_ray_start(q, (a)->rays + 8 * (long)(i), (a)->flags)
#define LT_LOOP_ADVANCE(a, q, c) lt_irg_args_advance(a, q, c)
#define LT_LOOP_FINISH(a, i, q) ((a)->hits[i] = lt_irg_ray_answer(q))
#define LT_LOOP_BUILD(a) ((a)->speculate || (a)->build.pool.mode == LT_POOL_FULL)
#define LT_LOOP_MAX_IDLE(a) ((a)->max_idle_polls)
#define LT_LOOP_FLUSH(a, c) lt_irg_flush(a, c)
#define LT_LOOP_TASK_KINDS(X)                                                         \
  X(LT_IRG_KIND_COUNT, lt_irg_count_chunk, lt_irg_count_end, &a->build)              \
  X(LT_IRG_KIND_CELL, lt_irg_cell_chunk, lt_irg_cell_end, &a->build)                \
  X(LT_IRG_KIND_VOXEL_MAP, lt_irg_voxel_map_chunk, lt_irg_voxel_map_end, &a->build) \
  X(LT_IRG_KIND_EXPAND, lt_irg_expand_chunk, lt_irg_expand_end, &a->build)
#include "kernels/persistent_loop_body.h"

/* The merge launch: no rays (a full build), the MERGE passes and the EXPAND passes after them. */
#define LT_LOOP_NAME lt_irg_merge_run
#define LT_LOOP_ARGS lt_irg_args
#define LT_LOOP_POOL(a) (&(a)->build.pool)
#define LT_LOOP_ITEM lt_irg_ray
#define LT_LOOP_ITEMS_PER_WORK_ITEM LT_LOOP_RAYS_PER_WORK_ITEM
#define LT_LOOP_ITEM_COUNT(a) 0
#define LT_LOOP_START(a, q, i, c) lt_irg_ray_start(q, (a)->rays + 8 * (long)(i), (a)->flags)
#define LT_LOOP_ADVANCE(a, q, c) lt_irg_args_advance(a, q, c)
#define LT_LOOP_FINISH(a, i, q) ((a)->hits[i] = lt_irg_ray_answer(q))
#define LT_LOOP_BUILD(a) 1
#define LT_LOOP_MAX_IDLE(a) ((a)->max_idle_polls)
#define LT_LOOP_FLUSH(a, c) lt_irg_flush(a, c)
#define LT_LOOP_TASK_KINDS(X)                                           \
  X(LT_IRG_KIND_MERGE, lt_irg_merge_chunk, lt_irg_merge_end, &a->build) \
  X(LT_IRG_KIND_EXPAND, lt_irg_expand_chunk, lt_irg_expand_end, &a->build)
#include "kernels/persistent_loop_body.h"

/* Both backends' entries: the set-up launch (work-item 0 of work-group 0) inserts the first
 * task (COUNT, or the first MERGE pass); a normal launch runs the persistent loop. */
LT_DEVICE void lt_irg_kernel(lt_irg_args *a, int setup, LT_LOCAL lt_loop_shared *sh) {
  if (!setup) lt_irg_run(a, sh);
  else if (lt_group_id() == 0 && lt_local_id() == 0) lt_irg_setup(&a->build);
}

LT_DEVICE void lt_irg_merge_kernel(lt_irg_args *a, int setup, LT_LOCAL lt_loop_shared *sh) {
  if (!setup) lt_irg_merge_run(a, sh);
  else if (lt_group_id() == 0 && lt_local_id() == 0) lt_irg_merge_setup(&a->build);
}

#endif
