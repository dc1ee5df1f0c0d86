/* A query of the lazy sort walks the sort tree from the root like a ray, and requests the
 * unbuilt node it reaches from the pool (builders/sort_task.h makes the nodes). */
#ifndef LT_SORT_WALK_H
#define LT_SORT_WALK_H

#include "device/pool.h"
#include "device/sort_node.h"

/* Walks query `pos` from node *node; returns 1 with *answer set, or 0 when it stops at an
 * unbuilt node (left in *node, where the walk restarts). A walk that starts suspended on a
 * node still unbuilt has requested it already and just stays. */
LT_DEVICE int lt_sort_walk(const lt_sort_tree *s, const lt_pool *pool, lt_i32 pos, lt_i32 *node, int suspended, lt_u32 *answer) {
  lt_i32 id = *node;
  for (int depth = 0; depth < LT_SORT_MAX_DEPTH; depth++) {
    lt_i32 state = lt_atomic_load_i32(&s->state[id]);
    if (state == LT_SORT_LEAF_STATE) {
      *answer = s->keys[pos];
      return 1;
    }
    if (state <= -2) {
      if (!suspended || id != *node) {
        lt_pool_request(pool, -2 - state, id);
        lt_pool_count(pool, LT_POOL_STAT_STALLS, 1);
      }
      *node = id;
      return 0;
    }
    lt_int4 n = s->nodes[id];
    if (pos >= n.x && pos < n.y) {
      *answer = (lt_u32)n.z;
      return 1;
    }
    id = pos < n.x ? state : state + 1;
  }
  lt_pool_fail(pool, LT_POOL_ERROR_STACK);
  *answer = 0;
  return 1;
}

#endif
