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

/* Embree's build qualities: LOW is its Morton (linear) build, the one a user rebuilding every
 * frame picks; MEDIUM is its default binned SAH build; HIGH adds spatial splits. */
typedef enum lt_embree_quality {
  LT_EMBREE_LOW,
  LT_EMBREE_MEDIUM,
  LT_EMBREE_HIGH,
} lt_embree_quality;

/* The quality's short name ("low", "medium", "high") for tables. */
const char *lt_embree_quality_name(lt_embree_quality quality);

/* An Embree scene kept across batches (build once, trace several). lt_embree_build uses
 * Embree's default (medium) quality. */
typedef struct lt_embree lt_embree;
lt_embree *lt_embree_build(const lt_scene *scene, int threads, double *build_ms);
lt_embree *lt_embree_build_quality(const lt_scene *scene, int threads, lt_embree_quality quality, double *build_ms);
/* Closest hit, or any hit (occlusion: prim 0 when occluded, -1 when not) when any is set. */
double lt_embree_trace(lt_embree *e, const lt_ray *rays, size_t count, int any, lt_hit *hits);
void lt_embree_release(lt_embree *e);

#endif
