/* Wide subtrees of an on-demand BVH, native backend (issue 16, point 2): between launches the
 * host collapses the largest finished subtrees of the binary tree the pool has built into
 * 8-wide trees (builders/host/bvh8_collapse.c) and marks their links wide (device/bvh_node.h),
 * so that the next launch's rays cross them with the AVX2 traversal of the full QBVH. A
 * subtree is finished when no unbuilt link lies below it: the pool will never touch it again,
 * and its binary nodes stay as they were (readers that know no wide trees still follow them).
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

/* The fewest triangles a finished subtree holds to be collapsed: entering a wide subtree costs
 * a ray the 8-wide set-up (about 40 instructions), which a subtree of a few leaves does not
 * repay. Tests lower it to 1 to collapse everything finished. */
int lt__ondemand_wide_min = 64;

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

typedef struct widener {
  lt_bvh_node *nodes;
  const lt_i32 *index;
  const float *verts;
  lt__bvh8 *wide;
  int made; /* subtrees collapsed by this pass */
  lt_status status;
} widener;

/* Collapses the subtree under inner node `link`, the `side` child of `parent`, and marks the
 * link wide. */
static lt_status widen(widener *w, lt_bvh_node *parent, int side, int link) {
  int root;
  lt_status status = lt__bvh8_append_subtree(w->wide, w->nodes, link, w->index, w->verts, &root);
  if (status) return w->status = lt__fail(status, "out of memory collapsing an on-demand subtree 8 wide");
  parent->link[2 + side] = lt_bvh_wide_count(root);
  w->made++;
  return LT_OK;
}

/* Walks the subtree under inner node `node`; returns 1 when no unbuilt link lies below it
 * (*tris then holds its triangles, a wide child counting as large enough), 0 when one does,
 * -1 on error. The finished inner children of an unfinished node, and of node 0 (the
 * super-root, never collapsed itself), are the largest finished subtrees: those of at least
 * lt__ondemand_wide_min triangles are collapsed. */
static int walk(widener *w, int node, long *tris, int depth) {
  lt_bvh_node *n = &w->nodes[node];
  int finished[2] = {1, 1}, inner[2] = {0, 0};
  long below[2] = {0, 0};
  for (int side = 0; side < 2; side++) {
    lt_i32 link, count;
    int kind = lt_bvh_child(n, side, &link, &count);
    if (kind == LT_CHILD_UNBUILT) finished[side] = 0;
    else if (kind == LT_CHILD_LEAF) below[side] = count;
    else if (kind == LT_CHILD_INNER && lt_bvh_child_is_wide(count)) below[side] = lt__ondemand_wide_min;
    else if (kind == LT_CHILD_INNER) {
      inner[side] = 1;
      finished[side] = depth < LT_BVH_MAX_DEPTH ? walk(w, link, &below[side], depth + 1) : 0;
      if (finished[side] < 0) return -1;
    }
  }
  *tris = below[0] + below[1];
  if (finished[0] && finished[1] && node != 0) return 1;
  for (int side = 0; side < 2; side++)
    if (inner[side] && finished[side] && below[side] >= lt__ondemand_wide_min &&
        widen(w, n, side, n->link[side]) != LT_OK)
      return -1;
  return 0;
}

lt_status lt__ondemand_widen(lt__ondemand *od) {
  if (!od->wide_on) return LT_OK;
  double start = lt_now_ms();
  widener w = {od->nodes.host, od->index.host, od->verts.host, &od->wide, 0, LT_OK};
  long tris;
  if (walk(&w, 0, &tris, 0) < 0) return w.status;
  od->wide_subtrees += w.made;
  od->wide_ms += lt_now_ms() - start;
  return LT_OK;
}
