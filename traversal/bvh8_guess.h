/* Any-hit queries' guesses on the native 8-wide trees: recent answers tried before a traversal. */
#ifndef LT_BVH8_GUESS_H
#define LT_BVH8_GUESS_H

#include "traversal/bvh8_traverse.h"

/* Guesses: an any-hit query is answered by any triangle of the scene hit within [tmin, tmax],
 * so a work-item first tries copies of the triangles that answered its last eight any-hit
 * queries, as two blocks of the wide trees' four-triangle test, and traverses only when none is
 * hit. The test is the traversal's
 * own, on the scene's own floats, so a hit there is one the traversal would accept: occlusion
 * is the same as without guesses, only which triangle answers may differ (as between any two
 * any-hit traversals). Coherent queries (a point's ambient-occlusion rays, neighbouring points'
 * shadow rays) are often answered so, with no node visited. Where that does not pay (the share
 * of tries answered, times the node visits a traversal made after a failed try, below one node
 * visit, about a block test's cost) only every 32nd query tries, to learn whether it would
 * again. The on-demand BVH's wide tree (kernels/native_bvh_wide.c; LT_BVH_GUESSES=0 in the
 * environment turns them off there) and the full QBVH's native trace kernel (kernels/bvh8_trace.h)
 * use them; the state is lt_bvh8_occluders (device/bvh8_node.h), one per work-item or thread. */
/* worth, from odds and work: whether a try saves more on average than it costs. */
static inline void lt_bvh8_guess_weigh(lt_bvh8_occluders *o) { o->worth = (long long)o->odds * o->work >= 4096 * 16; }

LT_BVH8_TARGET __attribute__((noinline, unused)) static int lt_bvh8_guess(const lt_ray_setup *r, lt_bvh8_occluders *o,
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
  lt_bvh8_guess_weigh(o);
  return answered;
}

/* Whether this query tries the guesses: when they pay, and every 32nd query anyway. */
static inline int lt_bvh8_guess_tries(lt_bvh8_occluders *o) {
  return o->filled > 0 && ((o->rays++ & 31) == 0 || o->worth);
}

/* After a traversal: its node visits go into the average (when a guess was tried first), its
 * answer becomes a guess in place of the oldest. */
static inline void lt_bvh8_guess_learn(const float *verts, lt_bvh8_occluders *o, lt_i32 prim, int tried,
                                       lt_u32 steps) {
  if (tried) {
    lt_i32 visits = steps < (1u << 20) ? (lt_i32)steps : 1 << 20;
    o->work += (visits * 16 - o->work) >> 4;
    lt_bvh8_guess_weigh(o);
  }
  if (prim < 0) return;
  const float *v = verts + 9 * (size_t)prim;
  int slot = o->next;
  lt_tri4 *b = &o->recent[slot >> 2];
  for (int k = 0; k < 9; k++) b->v[k][slot & 3] = v[k];
  b->prim[slot & 3] = prim;
  o->next = (slot + 1) & 7;
  o->filled += o->filled < 8;
}

#endif
