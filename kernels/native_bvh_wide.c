/* The on-demand traversal's way into the wide tree of its built part (traversal/bvh_view.h):
 * the 8-wide AVX2 traversal of traversal/bvh8_traverse.h from the ray's best hit so far, its
 * exits handed to the binary stack; and a ray's start on the wide tree, so that a ray that
 * meets no exit never enters the binary traversal. Kept out of line: the persistent kernel is
 * baseline x86-64, these functions AVX2, and only CPUs with AVX2 have wide trees (the host
 * checks lt_bvh8_supported before it makes one). */
#include "kernels/native_kernels.h"

#if defined(__x86_64__)
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

/* Guesses: an any-hit query is answered by any triangle of the scene hit within [tmin, tmax],
 * so a work-item first tries copies of the triangles that answered its last eight any-hit
 * queries on the wide tree (device/bvh8_node.h, lt_bvh8_occluders), as two blocks of the wide
 * tree's four-triangle test, and traverses only when none is hit. The test is the traversal's
 * own, on the scene's own floats, so a hit there is one the traversal would accept: occlusion
 * is the same as without guesses, only which triangle answers may differ (as between any two
 * any-hit traversals). Coherent queries (a point's ambient-occlusion rays, neighbouring points'
 * shadow rays) are often answered so, with no node visited. Where that does not pay (the share
 * of tries answered, times the node visits a traversal made after a failed try, below one node
 * visit, about a block test's cost) only every 32nd query tries, to learn whether it would
 * again. LT_BVH_GUESSES=0 in the environment turns guesses off. */
LT_BVH8_TARGET __attribute__((noinline)) static int guess(const lt_ray_setup *r, lt_bvh8_occluders *o,
                                                         lt_hit_record *hit, lt_trace_counters *c) {
  lt_bvh8_ray q;
  q.tri = lt_watertight4_prepare(r); /* all the block test reads */
  int first = o->filled < 4 ? o->filled : 4;
  c->intersections += (lt_u32)first;
  int answered = lt_bvh8_tri4_watertight(r, &q, &o->recent[0], (1 << first) - 1, 1, 1, hit);
  if (!answered && o->filled > 4) {
    c->intersections += (lt_u32)(o->filled - 4);
    answered = lt_bvh8_tri4_watertight(r, &q, &o->recent[1], (1 << (o->filled - 4)) - 1, 1, 1, hit);
  }
  o->odds += ((answered ? 4096 : 0) - o->odds) >> 4;
  o->worth = (long long)o->odds * o->work >= 4096 * 16;
  return answered;
}

/* After a traversal: its node visits go into the average (when a guess was tried first), its
 * answer becomes a guess in place of the oldest. */
static inline void learn(const lt_bvh_wide_view *w, lt_bvh8_occluders *o, lt_i32 prim, int tried, lt_u32 steps) {
  if (tried) {
    lt_i32 visits = steps < (1u << 20) ? (lt_i32)steps : 1 << 20;
    o->work += (visits * 16 - o->work) >> 4;
    o->worth = (long long)o->odds * o->work >= 4096 * 16;
  }
  if (prim < 0) return;
  const float *v = w->verts + 9 * (size_t)prim;
  int slot = o->next;
  lt_tri4 *b = &o->recent[slot >> 2];
  for (int k = 0; k < 9; k++) b->v[k][slot & 3] = v[k];
  b->prim[slot & 3] = prim;
  o->next = (slot + 1) & 7;
  o->filled += o->filled < 8;
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
    if (guessing) {
      lt_bvh8_occluders *o = &q->guesses;
      tried = o->filled > 0 && ((o->rays++ & 31) == 0 || o->worth);
      if (tried && guess(&q->r, o, &hit, c)) {
        q->hit = hit;
        return;
      }
      o->mark = c->traversal_steps;
    }
    if (wide_trace(w, &q->r, &hit, w->root, q->stack, q->stack_t, &q->sp, LT_BVH_RAY_STACK_SIZE, c, form) != 0)
      q->cur = 0; /* exits that would not fit: the binary tree from the super-root */
    else if (q->sp > 0 && !((flags & LT_QUERY_FLAG_ANY) && hit.prim >= 0))
      q->hit = hit, q->cur = lt_bvh_ray_pop(q);
    if (guessing) learn(w, &q->guesses, hit.prim, tried, c->traversal_steps - q->guesses.mark);
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
