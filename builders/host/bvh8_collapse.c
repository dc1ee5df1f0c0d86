/* Collapse of a binary BVH into an 8-ary one (Dammertz, Hanika and Keller, "Shallow Bounding
 * Volume Hierarchies for Fast SIMD Ray Tracing of Incoherent Rays", EGSR 2008, section 3, at
 * the width of an AVX2 register): siblings stored together, nodes in depth-first order. One
 * collapse serves both leaf formats of device/bvh_node.h: a host tree's (lt_tri in leaf order)
 * and a pool tree's (triangle numbers into the scene's vertices), built as far as it is. */
#include "builders/host/bvh8_collapse.h"

#include <stdlib.h>
#include <string.h>

#include "builders/host/qbvh_collapse.h"

typedef struct collapser {
  lt__bvh binary;        /* only its nodes are read */
  const lt_tri *tris;    /* leaves of a host tree, or NULL and */
  const lt_i32 *index;   /* a pool tree's leaves: triangle numbers */
  const float *verts;    /* into the scene's vertices, 9 floats a triangle */
  lt__bvh8 *out;         /* NULL while counting */
  int next;              /* nodes handed out */
  int slots;             /* triangle slots handed out */
} collapser;

/* Triangle i of a leaf from position `first`, in either format. */
static lt_tri leaf_triangle(const collapser *c, int first, int i) {
  if (c->tris) return c->tris[first + i];
  lt_i32 prim = c->index[first + i];
  const float *v = c->verts + 9 * (size_t)prim;
  lt_tri t = {{v[0], v[1], v[2], lt_int_as_float(prim)}, {v[3], v[4], v[5], 0.0f}, {v[6], v[7], v[8], 0.0f}};
  return t;
}

/* Puts triangle t in slot `slot` of the tree's own blocks. */
static void write_slot(lt__bvh8 *out, int slot, const lt_tri *t) {
  lt_tri4 *b = &out->blocks[slot / 4];
  const lt_float4 *v[3] = {&t->v0, &t->v1, &t->v2};
  for (int j = 0; j < 3; j++)
    b->v[3 * j][slot % 4] = v[j]->x, b->v[3 * j + 1][slot % 4] = v[j]->y, b->v[3 * j + 2][slot % 4] = v[j]->z;
  b->prim[slot % 4] = lt_float_as_int(t->v0.w);
}

/* Copies a leaf's `count` triangles from position `first` to slots `at` onwards. */
static void write_leaf(const collapser *c, int first, int count, int at) {
  for (int i = 0; i < count; i++) {
    lt_tri t = leaf_triangle(c, first, i);
    write_slot(c->out, at + i, &t);
  }
}

/* Closes the block that slot `slot` would open or continue: its lanes from there on get copies
 * of its lane 0 (already written), so that no lane the vector test computes holds garbage
 * (a denormal there would cost a microcode assist), though none of them is ever a hit. */
static void close_block(collapser *c, int slot) {
  if (!c->out || slot % 4 == 0) return;
  lt_tri4 *b = &c->out->blocks[slot / 4];
  for (int lane = slot % 4; lane < 4; lane++) {
    for (int k = 0; k < 9; k++) b->v[k][lane] = b->v[k][0];
    b->prim[lane] = b->prim[0];
  }
}

/* The first slot of a leaf of `count` triangles, handed out so that blocks are shared: a leaf
 * of at most four lies within one block, after whatever the block already holds if it fits
 * there; a longer one starts a block. So the four-triangle test reads a leaf's triangles from
 * as few blocks as before, and sibling leaves of one or two triangles share blocks instead of
 * each padding its own (half the slots were padding on the house scenes). */
static int leaf_slot(collapser *c, int count) {
  int used = c->slots % 4;
  if (used && (count > 4 || used + count > 4)) close_block(c, c->slots), c->slots += 4 - used;
  int slot = c->slots;
  c->slots += count;
  return slot;
}

/* Makes the node holding the children of binary inner node `link` at `depth` (node 0 is at
 * depth 1), then its inner children's nodes; returns its index and puts its children. An
 * unbuilt binary child (a tree still being built) becomes an exit lane (device/bvh8_node.h). */
static int collapse(collapser *c, int link, int depth, int *children) {
  lt__bvh_child kids[LT_BVH8_WIDTH];
  int n = lt__bvh_open_children(&c->binary, link, LT_BVH8_WIDTH, kids);
  *children = n;
  int at = c->next++;
  if (c->out && depth > c->out->max_depth) c->out->max_depth = depth;
  for (int lane = 0; lane < LT_BVH8_WIDTH; lane++) {
    /* An unbuilt child: the binary traversal's reference to its link. */
    if (lane < n && kids[lane].link <= -2) {
      if (c->out) lt_bvh8_write_child(&c->out->nodes[at], lane, &kids[lane].box, -2 - kids[lane].address, -1);
      continue;
    }
    /* Empty lanes get the far point box and count 0; a leaf's triangles go to the next slots. */
    if (lane >= n || !lt__bvh_child_is_inner(&kids[lane])) {
      int slot = lane < n ? leaf_slot(c, kids[lane].count) : 0;
      if (!c->out) continue;
      if (lane >= n) {
        lt_box empty = LT_BVH8_EMPTY_LANE_BOX;
        lt_bvh8_write_child(&c->out->nodes[at], lane, &empty, -1, 0);
        continue;
      }
      write_leaf(c, kids[lane].link, kids[lane].count, slot);
      lt_bvh8_write_child(&c->out->nodes[at], lane, &kids[lane].box, slot, kids[lane].count);
      c->out->leaf_count++;
      continue;
    }
    /* Depth first: a node's first inner child's node follows it in memory. */
    int grand;
    int below = collapse(c, kids[lane].link, depth + 1, &grand);
    if (c->out) lt_bvh8_write_child(&c->out->nodes[at], lane, &kids[lane].box, below, -grand);
  }
  return at;
}

/* Room for `nodes` more nodes and `slots` more triangle slots, keeping what is there. A node
 * is 256 bytes: aligned to cache lines, one visit reads four whole lines. */
static lt_status reserve(lt__bvh8 *w, int nodes, int slots) {
  size_t need_nodes = (size_t)w->node_count + (size_t)nodes, need_slots = (size_t)w->tri_slots + (size_t)slots;
  if (need_nodes > (size_t)w->node_capacity) {
    size_t cap = need_nodes > 2 * (size_t)w->node_capacity ? need_nodes : 2 * (size_t)w->node_capacity;
    lt_bvh8_node *grown = aligned_alloc(64, cap * sizeof *grown);
    if (!grown) return LT_ERROR_OUT_OF_MEMORY;
    if (w->node_count) memcpy(grown, w->nodes, (size_t)w->node_count * sizeof *grown);
    free(w->nodes);
    w->nodes = grown, w->node_capacity = (int)cap;
  }
  if (need_slots > (size_t)w->slot_capacity) {
    size_t cap = need_slots > 2 * (size_t)w->slot_capacity ? need_slots : 2 * (size_t)w->slot_capacity;
    cap = cap < 4 ? 4 : cap;
    lt_tri4 *blocks = aligned_alloc(64, (cap / 4 * sizeof *blocks + 63) / 64 * 64);
    if (!blocks) return LT_ERROR_OUT_OF_MEMORY;
    if (w->tri_slots) memcpy(blocks, w->blocks, (size_t)w->tri_slots / 4 * sizeof *blocks);
    free(w->blocks);
    w->blocks = blocks, w->slot_capacity = (int)cap;
  }
  return LT_OK;
}

/* Counts, makes room, then collapses for real, appending to out; *root gets the new root. */
static lt_status append(collapser *c, lt__bvh8 *out, int link, int *root) {
  int children;
  c->out = NULL, c->next = out->node_count, c->slots = out->tri_slots;
  collapse(c, link, 1, &children);
  c->slots = (c->slots + 3) / 4 * 4;
  lt_status status = reserve(out, c->next - out->node_count, c->slots - out->tri_slots);
  if (status) return status;
  memset(out->nodes + out->node_count, 0, (size_t)(c->next - out->node_count) * sizeof *out->nodes);
  c->out = out, c->next = out->node_count, c->slots = out->tri_slots;
  *root = collapse(c, link, 1, &children);
  close_block(c, c->slots);
  c->slots = (c->slots + 3) / 4 * 4;
  out->node_count = c->next;
  out->tri_slots = c->slots;
  return LT_OK;
}

lt_status lt__bvh8_collapse(const lt__bvh *bvh, lt__bvh8 *out) {
  memset(out, 0, sizeof *out);
  if (!bvh || !bvh->nodes || bvh->node_count < 1) return LT_ERROR_INVALID_ARGUMENT;
  collapser c = {*bvh, bvh->tris, NULL, NULL, NULL, 0, 0};
  int root;
  lt_status status = append(&c, out, 0, &root);
  if (status) lt__bvh8_free(out);
  return status;
}

lt_status lt__bvh8_collapse_built(lt__bvh8 *out, const lt_bvh_node *nodes, int link, const lt_i32 *index,
                                  const float *verts, int *root) {
  if (!out || !nodes || link < 0 || !index || !verts) return LT_ERROR_INVALID_ARGUMENT;
  collapser c = {{0}, NULL, index, verts, NULL, 0, 0};
  c.binary.nodes = (lt_bvh_node *)nodes; /* read only: the collapse never writes the binary tree */
  out->node_count = out->tri_slots = out->leaf_count = out->max_depth = 0; /* the room stays */
  return append(&c, out, link, root);
}

void lt__bvh8_free(lt__bvh8 *bvh8) {
  free(bvh8->nodes);
  free(bvh8->blocks);
  memset(bvh8, 0, sizeof *bvh8);
}
