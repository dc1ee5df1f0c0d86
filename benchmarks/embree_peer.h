/* Embree 3 as the peer a CPU user would pick: the same triangles and rays, the same number of
 * threads. Only compiled where libembree-dev is installed (LT_HAVE_EMBREE). */
#ifndef LT_EMBREE_PEER_H
#define LT_EMBREE_PEER_H

#include "lazytrace.h"

typedef struct lt_embree_times {
  double build_ms, trace_ms;
} lt_embree_times;

/* Builds an Embree scene (robust flag: watertight-ish, as close to ours as Embree goes) over
 * the scene's triangles with `threads` threads, and traces the rays closest-hit on `threads`
 * threads; hits get the contract's layout. Returns nonzero if Embree failed. */
int lt_embree_run(const lt_scene *scene, const lt_ray *rays, size_t count, int threads, lt_hit *hits,
                  lt_embree_times *times);

/* An Embree scene kept across batches (build once, trace several). */
typedef struct lt_embree lt_embree;
lt_embree *lt_embree_build(const lt_scene *scene, int threads, double *build_ms);
/* Closest hit, or any hit (occlusion: prim 0 when occluded, -1 when not) when any is set. */
double lt_embree_trace(lt_embree *e, const lt_ray *rays, size_t count, int any, lt_hit *hits);
void lt_embree_release(lt_embree *e);

#endif
