/* The stackless kd-tree traversals of Thrane and Simonsen's thesis (2005), after Foley and
 * Sugerman ("KD-Tree Acceleration Structures for a GPU Raytracer", 2005), on a fully built
 * tree:
 *
 *   restart    after each leaf, descend again from the root to the next cell
 *   backtrack  after each leaf, climb the parent links to the node where the next cell hangs,
 *              take the ray's stretch in that node's cell from its box, and descend from there
 *
 * Foley and Sugerman find the next cell by moving the ray's start to the end of the leaf just
 * left. Under rounding that can skip a thin cell or land in the same leaf again, so here the
 * next cell is found by a restart trail instead (Laine, "Restart Trail for Stackless BVH
 * Traversal", 2010): one bit per level says whether the level still has a second child to
 * visit. The descent's decisions are those of the stack traversal (lt_kd_decide, with the same
 * rounding margins), so both stackless traversals visit the cells the stack traversal visits,
 * in the same order, and return the same hits; what differs is the steps they take, which the
 * traversal-step counter shows: the nodes re-descended (restart) or climbed (backtrack). */
#ifndef LT_KD_STACKLESS_H
#define LT_KD_STACKLESS_H

#include "traversal/kd_traverse.h"

/* The restart trail: bit `depth` set when that level has nothing more to visit. */
typedef struct lt_kd_trail {
  lt_u32 w[2];
} lt_kd_trail;

LT_DEVICE int lt_kd_trail_bit(const lt_kd_trail *t, int depth) { return (int)(t->w[depth >> 5] >> (depth & 31)) & 1; }
LT_DEVICE void lt_kd_trail_set(lt_kd_trail *t, int depth) { t->w[depth >> 5] |= 1u << (depth & 31); }
/* Clears the bits of the levels below `depth` (depth + 1 and deeper). */
LT_DEVICE void lt_kd_trail_clear_below(lt_kd_trail *t, int depth) {
  int from = depth + 1; /* the first bit cleared */
  if (from < 32) {
    t->w[0] &= (1u << from) - 1u;
    t->w[1] = 0;
  } else if (from < 64) {
    t->w[1] &= (1u << (from - 32)) - 1u;
  }
}

/* The ray's stretch in a node's cell (lt_kd_box_stretch); 0 when the ray misses the cell. */
LT_DEVICE int lt_kd_cell_stretch(const lt_kd_view *v, const lt_ray_setup *r, lt_i32 node, float *t_near, float *t_far) {
  float lo[3], hi[3];
  for (int k = 0; k < 3; k++) lo[k] = v->cells[6 * (long)node + k], hi[k] = v->cells[6 * (long)node + 3 + k];
  return lt_kd_box_stretch(r, lo, hi, t_near, t_far);
}

/* Traces a ray started with lt_kd_ray_start through a finished tree to its answer, without a
 * stack: restarting from the root after each leaf, or with `backtrack`, climbing parent links. */
LT_DEVICE void lt_kd_advance_stackless(const lt_kd_view *v, lt_kd_ray *q, int flags, int backtrack,
                                       lt_trace_counters *c) {
  LT_GLOBAL const lt_kd_node *nodes = v->nodes;
  int any_hit = flags & LT_QUERY_FLAG_ANY;
  q->r.flags = flags;
  const lt_ray_setup *r = &q->r;
  lt_hit_record hit = q->hit;
  if (q->cur.address < 0) return;
  lt_kd_trail trail;
  trail.w[0] = trail.w[1] = 0;

  /* The descent: `address` is the link to follow, into a cell at `depth` whose parent is
   * `above`, with the ray's stretch [t_near, t_far] in it. */
  lt_i32 address = 0, depth = 0, above = 0;
  float t_near = q->t_near, t_far = q->t_far;
  for (;;) {
    lt_i32 end_depth = -1; /* set when the cell at that depth is finished */
    lt_i32 link = lt_kd_read_link(nodes, address);
    if (link < 0) {
      end_depth = depth; /* empty (a finished tree has no unbuilt links) */
    } else {
      c->traversal_steps++;
      LT_GLOBAL const lt_kd_node *n = &nodes[link];
      lt_i32 meta = n->meta;
      int axis = lt_kd_axis(meta);
      if (axis == LT_KD_LEAF_AXIS) {
        lt_kd_leaf(v, r, &hit, n->link[0], lt_kd_leaf_count(meta), c);
        end_depth = depth;
      } else {
        lt_kd_step st = lt_kd_decide(r, axis, n->split, t_near, t_far);
        int both = st.visit_first && st.visit_second, second;
        if (!both) {
          second = !st.visit_first;
          lt_kd_trail_set(&trail, depth);
        } else {
          second = lt_kd_trail_bit(&trail, depth);
        }
        if (both && second) {
          float near2 = st.t_split - st.margin > t_near ? st.t_split - st.margin : t_near;
          if (near2 > lt_kd_reach(q, &hit)) end_depth = depth + 1; /* cannot beat the best: done with it */
          t_near = near2;
        } else if (both && r->dir[axis] != 0.0f && st.t_split + st.margin < t_far) {
          t_far = st.t_split + st.margin;
        }
        if (end_depth < 0) {
          int side = second ? 1 - st.first_side : st.first_side;
          address = link * 2 + side, above = link, depth++;
          continue;
        }
        above = link;
      }
    }

    /* A cell at end_depth is finished: the next is the second child at the deepest level above
     * it that still has one. */
    if (any_hit && hit.prim >= 0) break;
    lt_i32 node = above, node_depth = end_depth - 1, level = end_depth - 1;
    for (;;) {
      while (level >= 0 && lt_kd_trail_bit(&trail, level)) level--;
      if (level < 0) break;
      lt_kd_trail_set(&trail, level);
      lt_kd_trail_clear_below(&trail, level);
      if (!backtrack) break;

      /* Backtrack: climb to the node at `level` and take its second child, with the ray's
       * stretch in its cell from the cell's box, unless it begins beyond the best hit. */
      for (; node_depth > level; node_depth--) {
        node = v->parents[node];
        c->traversal_steps++;
      }
      float tn, tf;
      if (!lt_kd_cell_stretch(v, r, node, &tn, &tf)) tn = q->t_near, tf = q->t_far;
      tn = tn > q->t_near ? tn : q->t_near;
      tf = tf < q->t_far ? tf : q->t_far;
      LT_GLOBAL const lt_kd_node *n = &nodes[node];
      lt_kd_step st = lt_kd_decide(r, lt_kd_axis(n->meta), n->split, tn, tf);
      float near2 = st.t_split - st.margin > tn ? st.t_split - st.margin : tn;
      if (near2 <= lt_kd_reach(q, &hit)) {
        address = node * 2 + 1 - st.first_side, above = node, depth = level + 1;
        t_near = near2, t_far = tf;
        break;
      }
      level--; /* that second child is done too: the next level up */
    }
    if (level < 0) break;
    if (!backtrack) {
      address = 0, depth = 0, above = 0;
      t_near = q->t_near, t_far = q->t_far;
    }
  }
  q->hit = hit;
  q->cur.address = -1, q->sp = 0;
}

#endif
