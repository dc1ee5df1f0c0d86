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

/* No triangles: one inner node that no ray enters. */
static void one_empty_node(lt__escape_bvh *out) {
  float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  write_box(&out->nodes[0], lo, hi);
  out->nodes[0].link = 1, out->nodes[0].count = 0;
  out->node_count = 1;
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
  if (out->node_count == 0) one_empty_node(out);
  return LT_OK;
}

lt_status lt__escape_bvh_from_tree(const lt__tree *tree, const float *tris, lt__escape_bvh *out, lt_tri **tris_out) {
  memset(out, 0, sizeof *out);
  size_t cap = (size_t)(tree->node_count > 0 ? tree->node_count : 0) + 1;
  int tri_total = 0;
  for (int i = 0; i < tree->node_count; i++) tri_total += tree->nodes[i].count;
  out->nodes = calloc(cap, sizeof *out->nodes);
  int *parent = malloc(cap * sizeof *parent), *size = malloc(cap * sizeof *size);
  int(*stack)[3] = malloc(cap * sizeof *stack); /* tree node, depth, parent's position */
  lt_tri *copy = aligned_alloc(16, ((size_t)tri_total * sizeof(lt_tri) + 16) / 16 * 16);
  if (!out->nodes || !parent || !size || !stack || !copy) {
    free(parent), free(size), free(stack), free(copy), lt__escape_bvh_free(out);
    return LT_ERROR_OUT_OF_MEMORY;
  }
  /* Depth first, left to right: a node's next sibling waits below its first child. */
  int sp = 0, placed = 0;
  if (tree->root >= 0) {
    const lt__tree_node *root = &tree->nodes[tree->root];
    stack[sp][0] = root->count > 0 ? tree->root : root->first_child, stack[sp][1] = 1, stack[sp][2] = -1, sp++;
  }
  while (sp > 0) {
    sp--;
    int node = stack[sp][0], depth = stack[sp][1], up = stack[sp][2];
    const lt__tree_node *n = &tree->nodes[node];
    int at = out->node_count++;
    write_box(&out->nodes[at], n->box.lo, n->box.hi);
    parent[at] = up, size[at] = 1;
    if (depth > out->max_depth) out->max_depth = depth;
    if (n->next_sibling >= 0) stack[sp][0] = n->next_sibling, stack[sp][1] = depth, stack[sp][2] = up, sp++;
    if (n->count > 0) {
      out->nodes[at].link = placed, out->nodes[at].count = n->count;
      for (int i = n->first; i < n->first + n->count; i++, placed++) {
        int t = tree->index[i];
        const float *v = tris + 9 * (size_t)t;
        copy[placed].v0 = lt_make_float4(v[0], v[1], v[2], lt_int_as_float(t));
        copy[placed].v1 = lt_make_float4(v[3], v[4], v[5], 0.0f);
        copy[placed].v2 = lt_make_float4(v[6], v[7], v[8], 0.0f);
      }
      out->leaf_count++;
    } else if (n->first_child >= 0) {
      stack[sp][0] = n->first_child, stack[sp][1] = depth + 1, stack[sp][2] = at, sp++;
    }
  }
  /* Subtree sizes from the last node back (children come after their parent); an inner node
   * escapes to the node after its subtree. */
  for (int i = out->node_count - 1; i >= 0; i--) {
    if (out->nodes[i].count == 0) out->nodes[i].link = i + size[i];
    if (parent[i] >= 0) size[parent[i]] += size[i];
  }
  free(parent), free(size), free(stack);
  if (out->node_count == 0) one_empty_node(out);
  *tris_out = copy;
  return LT_OK;
}

void lt__escape_bvh_free(lt__escape_bvh *e) {
  free(e->nodes);
  memset(e, 0, sizeof *e);
}
