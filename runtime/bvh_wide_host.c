/* The wide tree of an on-demand BVH, native backend (issue 16, point 2): before each launch
 * with rays, the host collapses the binary tree as far as the pool has built it into an 8-wide
 * tree (builders/host/bvh8_collapse.c; unbuilt links become exit lanes) and marks the root's
 * link wide (device/bvh_node.h), so that the launch's rays cross the built part with the AVX2
 * traversal of the full QBVH and go on in the binary tree only past its exits, where the pool
 * builds as before. The binary nodes stay as they were; the next launch collapses again, over
 * what this one built, into the same room.
 *
 * Between launches only: no ray and no task runs then, so the links are plain stores. (Inside
 * a launch the count would have to be published with release order behind the wide nodes and
 * read with acquire order; the binary traversal reads it relaxed.) */
#include <stdlib.h>
#include <string.h>

#include "builders/host/bvh8_collapse.h"
#include "runtime/bvh_ondemand_host.h"
#include "runtime/context_internal.h"
#include "runtime/error.h"
#include "runtime/stats_internal.h"

#if defined(__x86_64__)
#include "traversal/bvh8_traverse.h"
#endif

int lt__ondemand_wide_wanted(const lt_context *ctx, int pool_mode) {
  if (ctx->kind != LT_DEVICE_NATIVE || pool_mode == LT_POOL_FULL) return 0;
  const char *off = getenv("LT_BVH_WIDE");
  if (off && strcmp(off, "0") == 0) return 0;
#if defined(__x86_64__)
  return lt_bvh8_supported();
#else
  return 0;
#endif
}

int lt__ondemand_wide_stride(void) {
  const char *env = getenv("LT_BVH_WIDE_SAMPLE");
  return env ? atoi(env) : 16;
}

int lt__ondemand_wide_guesses(void) {
  const char *env = getenv("LT_BVH_GUESSES");
  return !(env && strcmp(env, "0") == 0);
}

int lt__ondemand_wide_sample(int stride, int count) { return stride > 1 && count / stride >= 1024 ? stride : 0; }

lt_status lt__ondemand_widen(lt__ondemand *od) {
  if (!od->wide_on) return LT_OK;
  /* Node 0 is the super-root; its left child is the scene's root, wide once it is inner. */
  lt_bvh_node *nodes = od->nodes.host;
  lt_i32 link, count;
  if (lt_bvh_child(&nodes[0], 0, &link, &count) != LT_CHILD_INNER) return LT_OK;
  double start = lt_now_ms();
  nodes[0].link[2] = 0; /* inner, binary, until the collapse is whole */
  int root;
  lt_status status = lt__bvh8_collapse_built(&od->wide, nodes, link, od->index.host, od->verts.host, &root);
  if (status) return lt__fail(status, "out of memory collapsing the on-demand BVH 8 wide");
  nodes[0].link[2] = lt_bvh_wide_count(root);
  od->wide_collapses++;
  od->wide_ms += lt_now_ms() - start;
  return LT_OK;
}
