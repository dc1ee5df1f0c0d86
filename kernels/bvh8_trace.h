/* The trace kernel of the QBVH's native 8-wide path (device/bvh8_node.h,
 * traversal/bvh8_traverse.h): one ray at a time through the eight-box AVX2 traversal, a chunk
 * of rays a call; leaves are blocks of four triangles. Native backend only:
 * runtime/structure_qbvh.c takes it where the CPU has AVX2. */
#ifndef LT_KERNEL_BVH8_TRACE_H
#define LT_KERNEL_BVH8_TRACE_H

#include "kernels/trace_kernel.h"
#include "traversal/bvh8_guess.h"
#include "traversal/bvh8_traverse.h"

typedef struct lt_bvh8_trace_view {
  lt_trace_batch batch;
  const lt_bvh8_node *nodes;
  const lt_tri4 *blocks;
  const float *verts; /* the scene's triangles, 9 floats each, for any-hit guesses (NULL: none) */
} lt_bvh8_trace_view;

#define LT_BVH8_TRACE_ARGS(X)           \
  LT_TRACE_BATCH_ARGS(X, batch)         \
  X(BUF, lt_bvh8_node, nodes, nodes)    \
  X(BUF, lt_tri4, blocks, blocks)       \
  X(BUF, float, verts, verts)

/* Rays [begin, end) of the batch, each prepared and traced, its hit written; 0, or -1 when a
 * traversal would overflow its stack. The common ray (valid, no zero direction component,
 * the batch's flags the default's but for the query) runs the traversal loop inlined here, for
 * the query form `form` (lt_bvh8_query_form; none for LT_BVH8_QUERY_OTHER); any other ray
 * takes lt_bvh8_traverse_with. */
LT_BVH8_TARGET __attribute__((always_inline)) static inline int lt_bvh8_trace_rays(const lt_bvh8_trace_view *v,
                                                                                   lt_i32 begin, lt_i32 end,
                                                                                   lt_trace_counters *c,
                                                                                   lt_bvh8_occluders *o, int form) {
  int status = 0, flags = v->batch.flags;
  for (lt_i32 i = begin; i < end; i++) {
    lt_ray_setup r;
    lt_bvh8_ray_prepare(v->batch.rays + 8 * (long)i, flags, &r);
    lt_hit_record hit = {r.tmax, 0.0f, 0.0f, -1};
    if (form == LT_BVH8_QUERY_ANY && v->verts && r.valid && !r.parallel) {
      /* Any hit: the thread's recent answers first (traversal/bvh8_guess.h). */
      int tried = lt_bvh8_guess_tries(o);
      if (!(tried && lt_bvh8_guess(&r, o, &hit, c))) {
        lt_u32 steps = c->traversal_steps;
        status |= lt_bvh8_traverse_query(v->nodes, v->blocks, &r, 0, &hit, c, LT_BVH8_COMMON, NULL, 0, NULL, 1);
        lt_bvh8_guess_learn(v->verts, o, hit.prim, tried, c->traversal_steps - steps);
      }
    } else if (form != LT_BVH8_QUERY_OTHER && __builtin_expect(!r.parallel, 1))
      status |= lt_bvh8_traverse_query(v->nodes, v->blocks, &r, 0, &hit, c, LT_BVH8_COMMON, NULL, 0, NULL,
                                       form == LT_BVH8_QUERY_ANY);
    else
      status |= lt_bvh8_traverse_with(v->nodes, v->blocks, &r, &hit, c, LT_BVH8_VECTOR);
    lt_trace_batch_put(&v->batch, i, hit);
  }
  return status;
}

/* lt_bvh8_trace_rays for each form, each compiled (and its registers allocated) for its own
 * loop. One call a chunk where there were two a ray and a dispatch. */
LT_BVH8_TARGET __attribute__((noinline)) static int lt_bvh8_trace_any(const lt_bvh8_trace_view *v, lt_i32 begin,
                                                                     lt_i32 end, lt_trace_counters *c, lt_bvh8_occluders *o) {
  return lt_bvh8_trace_rays(v, begin, end, c, o, LT_BVH8_QUERY_ANY);
}
LT_BVH8_TARGET __attribute__((noinline)) static int lt_bvh8_trace_closest(const lt_bvh8_trace_view *v, lt_i32 begin,
                                                                         lt_i32 end, lt_trace_counters *c, lt_bvh8_occluders *o) {
  return lt_bvh8_trace_rays(v, begin, end, c, o, LT_BVH8_QUERY_CLOSEST);
}
LT_BVH8_TARGET __attribute__((noinline)) static int lt_bvh8_trace_other(const lt_bvh8_trace_view *v, lt_i32 begin,
                                                                       lt_i32 end, lt_trace_counters *c, lt_bvh8_occluders *o) {
  return lt_bvh8_trace_rays(v, begin, end, c, o, LT_BVH8_QUERY_OTHER);
}

/* The kernel's chunk of rays (kernels/trace_kernel_body.h, LT_TRACE_RANGE): baseline x86-64
 * code that picks one of the AVX2 functions above for the batch; o is the thread's guesses, kept
 * across its chunks (LT_TRACE_STATE). */
static inline int lt_bvh8_trace_range(const lt_bvh8_trace_view *v, lt_i32 begin, lt_i32 end, lt_trace_counters *c,
                                      lt_bvh8_occluders *o) {
  int form = lt_bvh8_query_form(v->batch.flags);
  if (form == LT_BVH8_QUERY_OTHER) return lt_bvh8_trace_other(v, begin, end, c, o);
  if (form == LT_BVH8_QUERY_ANY) return lt_bvh8_trace_any(v, begin, end, c, o);
  return lt_bvh8_trace_closest(v, begin, end, c, o);
}

#endif
