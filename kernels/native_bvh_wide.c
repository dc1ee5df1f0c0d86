/* The on-demand traversal's way into the wide tree of its built part (traversal/bvh_view.h):
 * the 8-wide AVX2 traversal of traversal/bvh8_traverse.h from the ray's best hit so far, its
 * exits handed to the binary stack; and a ray's start on the wide tree, so that a ray that
 * meets no exit never enters the binary traversal. Kept out of line: the persistent kernel is
 * baseline x86-64, these functions AVX2, and only CPUs with AVX2 have wide trees (the host
 * checks lt_bvh8_supported before it makes one). */
#include "kernels/native_kernels.h"

#if defined(__x86_64__)
#include "traversal/bvh8_guess.h"
#include "traversal/bvh8_traverse.h"
#include "traversal/bvh_view.h"

/* The most exits one wide traversal may hand over (besides the room on the stack): tests lower
 * it to send rays down the fallback, the binary subtree. */
int lt__bvh_wide_exit_limit = LT_BVH_RAY_STACK_SIZE;

/* lt__bvh_wide_trace's body, inlined in each entry: for LT_BVH8_QUERY_OTHER the dispatch of
 * lt_bvh8_traverse_from, else the common ray's loop for that query form inlined (the caller
 * has checked that the ray is common). */
LT_BVH8_TARGET __attribute__((always_inline)) static inline int wide_trace(const lt_bvh_wide_view *w,
                                                                          const lt_ray_setup *r, lt_hit_record *hit,
                                                                          lt_i32 node, lt_i32 *stack, float *stack_t,
                                                                          lt_i32 *sp, lt_i32 size,
                                                                          lt_trace_counters *c, int form) {
  lt_bvh8_item exits[LT_BVH_RAY_STACK_SIZE];
  int count = 0;
  int room = size - *sp < lt__bvh_wide_exit_limit ? size - *sp : lt__bvh_wide_exit_limit;
  int status = form == LT_BVH8_QUERY_OTHER
                   ? lt_bvh8_traverse_from(w->nodes, w->blocks, r, node, hit, c, LT_BVH8_VECTOR, exits, room, &count)
                   : lt_bvh8_traverse_query(w->nodes, w->blocks, r, node, hit, c, LT_BVH8_COMMON, exits, room, &count,
                                            form == LT_BVH8_QUERY_ANY);
  if (status != 0) return 1;

  /* Far to near, so that the nearest exit is popped first (insertion sort: exits are few). */
  for (int i = 1; i < count; i++) {
    lt_bvh8_item item = exits[i];
    int j = i;
    while (j > 0 && exits[j - 1].t < item.t) exits[j] = exits[j - 1], j--;
    exits[j] = item;
  }
  for (int i = 0; i < count; i++) stack[*sp] = exits[i].first, stack_t[*sp] = exits[i].t, (*sp)++;
  return 0;
}

LT_BVH8_TARGET __attribute__((noinline)) int lt__bvh_wide_trace(const lt_bvh_wide_view *w, const lt_ray_setup *r,
                                                                lt_hit_record *hit, lt_i32 node, lt_i32 *stack,
                                                                float *stack_t, lt_i32 *sp, lt_i32 size,
                                                                lt_trace_counters *c) {
  return wide_trace(w, r, hit, node, stack, stack_t, sp, size, c, LT_BVH8_QUERY_OTHER);
}

/* lt__bvh_wide_start for one form. The binary traversal would box-test the root's box at the
 * super-root first; the wide tree starts at the root's children, whose boxes lie inside it (a
 * ray that misses the root's box misses theirs too, bit for bit: traversal/ray.h), so the
 * hits are the same. */
LT_BVH8_TARGET __attribute__((always_inline)) static inline void wide_start(const lt_bvh_wide_view *w,
                                                                           const float *ray, int flags,
                                                                           lt_bvh_ray *q, lt_trace_counters *c,
                                                                           int form) {
  lt_bvh8_ray_prepare(ray, flags, &q->r);
  lt_hit_record hit = {q->r.tmax, 0.0f, 0.0f, -1};
  lt_bvh_ray_reset(q, -1);
  if (q->r.valid) {
    if (q->r.parallel) form = LT_BVH8_QUERY_OTHER; /* not a common ray */
    int tried = 0, guessing = form == LT_BVH8_QUERY_ANY && w->guesses;
    if (guessing) { /* traversal/bvh8_guess.h */
      lt_bvh8_occluders *o = &q->guesses;
      tried = lt_bvh8_guess_tries(o);
      if (tried && lt_bvh8_guess(&q->r, o, &hit, c)) {
        q->hit = hit;
        return;
      }
      o->mark = c->traversal_steps;
    }
    if (wide_trace(w, &q->r, &hit, w->root, q->stack, q->stack_t, &q->sp, LT_BVH_RAY_STACK_SIZE, c, form) != 0)
      q->cur = 0; /* exits that would not fit: the binary tree from the super-root */
    else if (q->sp > 0 && !((flags & LT_QUERY_FLAG_ANY) && hit.prim >= 0))
      q->hit = hit, q->cur = lt_bvh_ray_pop(q);
    if (guessing) lt_bvh8_guess_learn(w->verts, &q->guesses, hit.prim, tried, c->traversal_steps - q->guesses.mark);
  }
  q->hit = hit;
}

/* Each form compiled (and its registers allocated) for its own loop, as the plain 8-wide kernel's. */
LT_BVH8_TARGET __attribute__((noinline)) static void wide_start_any(const lt_bvh_wide_view *w, const float *ray,
                                                                    int flags, lt_bvh_ray *q, lt_trace_counters *c) {
  wide_start(w, ray, flags, q, c, LT_BVH8_QUERY_ANY);
}
LT_BVH8_TARGET __attribute__((noinline)) static void wide_start_closest(const lt_bvh_wide_view *w, const float *ray,
                                                                        int flags, lt_bvh_ray *q,
                                                                        lt_trace_counters *c) {
  wide_start(w, ray, flags, q, c, LT_BVH8_QUERY_CLOSEST);
}
LT_BVH8_TARGET __attribute__((noinline)) static void wide_start_other(const lt_bvh_wide_view *w, const float *ray,
                                                                      int flags, lt_bvh_ray *q, lt_trace_counters *c) {
  wide_start(w, ray, flags, q, c, LT_BVH8_QUERY_OTHER);
}

void lt__bvh_wide_start(const lt_bvh_wide_view *w, const float *ray, int flags, lt_bvh_ray *q, lt_trace_counters *c) {
  int form = lt_bvh8_query_form(flags);
  if (form == LT_BVH8_QUERY_OTHER) wide_start_other(w, ray, flags, q, c);
  else if (form == LT_BVH8_QUERY_ANY) wide_start_any(w, ray, flags, q, c);
  else wide_start_closest(w, ray, flags, q, c);
}
#endif
