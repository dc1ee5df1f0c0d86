/* The lazy sort's tree (the task pool's own workload): one state word per node, and for each
 * partitioned node its bounds and pivot. Its tasks (builders/sort_task.h) make nodes; its
 * queries (traversal/sort_walk.h) read them. */
#ifndef LT_DEVICE_SORT_NODE_H
#define LT_DEVICE_SORT_NODE_H

#include "device/compat.h"

/* Node states: a leaf is sorted; an unbuilt node points at its task; a built node holds the
 * id of its first child (the second is first + 1). */
#define LT_SORT_LEAF_STATE (-1)
#define LT_SORT_UNBUILT(slot) (-2 - (slot))

/* The arrays a query walks. */
typedef struct lt_sort_tree {
  LT_GLOBAL const lt_i32 *state;  /* per node: leaf, unbuilt or built */
  LT_GLOBAL const lt_int4 *nodes; /* per built node: less_end, greater_begin, pivot, first child */
  LT_GLOBAL const lt_u32 *keys;   /* the keys, sorted where the sort got to */
} lt_sort_tree;

#endif
