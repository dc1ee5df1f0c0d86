/* What a BVH traversal reads: the node array, the leaves' references in one of the two leaf
 * formats (device/bvh_node.h says why there are two), and, for a tree still being built, the
 * pool that builds the children it requests. */
#ifndef LT_BVH_VIEW_H
#define LT_BVH_VIEW_H

#include "device/bvh_node.h"
#include "device/pool.h"
#include "traversal/ray_box.h"

/* On the native backend of an x86 CPU, the part of a tree built on demand that the last
 * launches built may also exist as an 8-wide tree (device/bvh_node.h, the wide kind), which
 * the on-demand traversal hands to the AVX2 traversal of traversal/bvh8_traverse.h
 * (kernels/native_bvh_wide.c). The host collapses it only where the CPU has AVX2. Its exits
 * (unbuilt links) come back to the binary traversal's stack, which is larger there. */
#if !defined(__OPENCL_VERSION__) && defined(__x86_64__)
#define LT_BVH_WIDE 1
#define LT_BVH_RAY_STACK_SIZE 256
#include "device/bvh8_node.h"

/* The 8-wide tree of one on-demand tree: its nodes and its triangles in four-triangle blocks,
 * and the wide node whose lanes are the scene root's children (-1: the root is binary). */
typedef struct lt_bvh_wide_view {
  const lt_bvh8_node *nodes;
  const lt_tri4 *blocks;
  lt_i32 root;
  const float *verts; /* the scene's triangles, 9 floats each, */
  int guesses;        /* for any-hit queries' guesses, if on (kernels/native_bvh_wide.c) */
} lt_bvh_wide_view;

/* Traces a ray from the children of wide node `node`, starting from and updating its best hit
 * so far; the exits it enters go on the binary stack (stack, stack_t, *sp, at most `size`
 * entries), nearest on top. Returns 0, or 1 when they would not fit (the stack is then as it
 * was, and the caller traverses the binary subtree instead; the best hit found stays valid).
 * Hits are bit for bit the binary traversal's. */
int lt__bvh_wide_trace(const lt_bvh_wide_view *w, const lt_ray_setup *r, lt_hit_record *hit, lt_i32 node,
                       lt_i32 *stack, float *stack_t, lt_i32 *sp, lt_i32 size, lt_trace_counters *c);
/* At most this many exits a wide traversal (default LT_BVH_RAY_STACK_SIZE; tests lower it). */
extern int lt__bvh_wide_exit_limit;
#else
#define LT_BVH_WIDE 0
#define LT_BVH_RAY_STACK_SIZE LT_BVH_STACK_SIZE
#endif

typedef struct lt_bvh_view {
  LT_GLOBAL const lt_bvh_node *nodes;
  LT_GLOBAL const lt_tri *tris;   /* host-built trees: triangles in leaf order */
  LT_GLOBAL const lt_i32 *index;  /* pool-built trees: triangle numbers in leaf order, */
  LT_GLOBAL const float *verts;   /* and the scene's vertices, 9 floats a triangle */
  const lt_pool *pool;            /* on demand: where unbuilt children are requested */
#if LT_BVH_WIDE
  const lt_bvh_wide_view *wide;   /* on demand, native: the wide subtrees, or NULL */
#endif
} lt_bvh_view;

/* A ray in flight: enough state to suspend on an unbuilt child and resume. Stack entries are
 * node indices, or references to unbuilt links (-2 - address) in a tree still being built. */
typedef struct lt_bvh_ray {
  lt_ray_setup r;
  lt_hit_record hit;
  lt_i32 stack[LT_BVH_RAY_STACK_SIZE];
  float stack_t[LT_BVH_RAY_STACK_SIZE]; /* each far child's entry distance */
  lt_i32 sp;
  lt_i32 cur;      /* next node, a link reference (<= -2), or -1 when done */
  lt_i32 wait;     /* link address the ray is suspended on, or -1 */
  lt_i32 overflow; /* the stack would have overflowed: the answer is not to be trusted */
#if LT_BVH_WIDE
  lt_bvh8_occluders guesses; /* any hit on the wide tree: kept from ray to ray of a work-item */
#endif
} lt_bvh_ray;

/* A ray's traversal state as it starts: an empty stack, waiting for nothing, next node `cur`
 * (-1: done). */
LT_DEVICE void lt_bvh_ray_reset(lt_bvh_ray *q, lt_i32 cur) { q->sp = 0, q->wait = -1, q->overflow = 0, q->cur = cur; }

/* Starts a ray given in the ray file's layout (8 floats). */
LT_DEVICE void lt_bvh_ray_start(lt_bvh_ray *q, LT_GLOBAL const float *ray) {
  q->r = lt_ray_prepare(ray[0], ray[1], ray[2], ray[3], ray[4], ray[5], ray[6], ray[7]);
  q->hit.t = q->r.tmax, q->hit.u = q->hit.v = 0.0f, q->hit.prim = -1;
  lt_bvh_ray_reset(q, q->r.valid ? 0 : -1);
}

#if LT_BVH_WIDE
/* lt_bvh_ray_start for a launch whose tree's root is wide: the ray prepared as lt_ray_prepare
 * prepares it (lt_bvh8_ray_prepare), then traced through the wide tree from the root with
 * lt__bvh_wide_trace, so that the binary traversal sees it only if it entered exits (it goes on
 * from the nearest) or they would not fit (from the root, with the best hit so far). */
void lt__bvh_wide_start(const lt_bvh_wide_view *w, const float *ray, int flags, lt_bvh_ray *q, lt_trace_counters *c);
#endif

/* A finished ray's answer in the hit file's layout: a miss is t = +infinity, u = v = 0. */
LT_DEVICE lt_hit_record lt_bvh_ray_answer(const lt_bvh_ray *q) {
  lt_hit_record hit = q->hit;
  if (hit.prim < 0) hit.t = INFINITY, hit.u = hit.v = 0.0f;
  return hit;
}

/* The distance a box must be entered by to matter: the best hit so far, or the ray's end. */
LT_DEVICE float lt_bvh_ray_best(const lt_bvh_ray *q) { return q->hit.prim >= 0 ? q->hit.t : q->r.tmax; }

/* The next far child that the best hit so far has not ruled out: its entry distance against
 * the best is the box test it passed when it was pushed, redone with the best as it is now,
 * so a far child that a closer hit has since hidden is neither visited nor requested. */
LT_DEVICE lt_i32 lt_bvh_ray_pop(lt_bvh_ray *q) {
  float best = lt_bvh_ray_best(q);
  while (q->sp > 0) {
    q->sp--;
    if (q->stack_t[q->sp] <= best) return q->stack[q->sp];
  }
  return -1;
}

#endif
