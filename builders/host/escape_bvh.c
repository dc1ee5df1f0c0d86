/* The escape-index layout of a binary host BVH (builders/host/escape_bvh.h). */
#include "builders/host/escape_bvh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void write_box(lt_escape_node *n, const float lo[3], const float hi[3]) {
  for (int k = 0; k < 3; k++) n->lo[k] = lo[k], n->hi[k] = hi[k];
}

/* Appends child `side` of binary node `node` and its subtree in depth-first order. */
static void emit(const lt__bvh *bvh, int node, int side, int depth, lt__escape_bvh *out) {
  lt_i32 link, count;
  int kind = lt_bvh_child(&bvh->nodes[node], side, &link, &count);
  if (kind == LT_CHILD_EMPTY) return;
  float lo[3], hi[3];
  lt_bvh_child_box(&bvh->nodes[node], side, lo, hi);
  int at = out->node_count++;
  write_box(&out->nodes[at], lo, hi);
  if (depth > out->max_depth) out->max_depth = depth;
  if (kind == LT_CHILD_LEAF) {
    out->nodes[at].link = link, out->nodes[at].count = count;
    out->leaf_count++;
    return;
  }
  emit(bvh, link, 0, depth + 1, out);
  emit(bvh, link, 1, depth + 1, out);
  out->nodes[at].link = out->node_count, out->nodes[at].count = 0;
}

lt_status lt__escape_bvh_from_bvh(const lt__bvh *bvh, lt__escape_bvh *out) {
  memset(out, 0, sizeof *out);
  /* Every binary node has at most two children, and a top node more. */
  size_t capacity = 2 * (size_t)(bvh->node_count > 0 ? bvh->node_count : 0) + 1;
  out->nodes = calloc(capacity, sizeof *out->nodes);
  if (!out->nodes) return LT_ERROR_OUT_OF_MEMORY;
  if (bvh->node_count > 0) {
    emit(bvh, 0, 0, 1, out);
    emit(bvh, 0, 1, 1, out);
  }
  if (out->node_count == 0) {
    /* No triangles: one inner node that no ray enters. */
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    write_box(&out->nodes[0], lo, hi);
    out->nodes[0].link = 1, out->nodes[0].count = 0;
    out->node_count = 1;
  }
  return LT_OK;
}

void lt__escape_bvh_free(lt__escape_bvh *e) {
  free(e->nodes);
  memset(e, 0, sizeof *e);
}
