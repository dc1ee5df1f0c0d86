/* The Morton top of the on-demand BVH: HLBVH (Pantaleoni and Luebke 2010, section 3) applied on
 * demand, with Karras's split rule (Karras, HPG 2012, section 4). The host sorts the triangles
 * by Morton code once (builders/host/morton.c); a node of the top then splits its sorted range
 * where the highest bit in which its first and last codes differ turns from 0 to 1 (a binary
 * search: no bins, no partition pass), and bounds its children from a pyramid of block boxes
 * over the sorted order. Nodes below the top are built by the binned SAH (builders/bvh_task.h). */
#ifndef LT_BVH_MORTON_H
#define LT_BVH_MORTON_H

#include "device/box.h"

/* Sorted positions per box at the pyramid's bottom level; each level above halves the count. */
#define LT_BVH_MORTON_BLOCK 16

/* The first position of [first, last] whose code has the highest bit in which codes[first] and
 * codes[last] differ; the middle when all codes in the range are equal. */
LT_DEVICE lt_i32 lt_morton_split(LT_GLOBAL const lt_u32 *codes, lt_i32 first, lt_i32 last) {
  lt_u32 a = codes[first], z = codes[last], diff = a ^ z, bit = 1u;
  if (diff == 0) return first + (last - first + 1) / 2;
  while (diff >> 1) diff >>= 1, bit <<= 1;

  /* The range's codes share every bit above `bit`, so those with it clear come first. */
  lt_i32 lo = first + 1, hi = last;
  while (lo < hi) {
    lt_i32 mid = lo + (hi - lo) / 2;
    if (codes[mid] & bit)
      hi = mid;
    else
      lo = mid + 1;
  }
  return lo;
}

/* The box of the triangles at sorted positions [lo, hi): the few positions outside whole blocks
 * read their own boxes (prim_boxes, 2 per triangle, through index); whole blocks come from the
 * pyramid (block_boxes, 2 per block, level after level, `blocks` at the bottom), at most two
 * boxes a level, as in a bottom-up segment tree. */
LT_DEVICE lt_box lt_morton_bounds(LT_GLOBAL const lt_v4 *prim_boxes, LT_GLOBAL const lt_i32 *index,
                                  LT_GLOBAL const lt_v4 *block_boxes, lt_i32 blocks, lt_i32 lo, lt_i32 hi) {
  lt_v4 blo = lt_v4_splat(INFINITY), bhi = lt_v4_splat(-INFINITY);
  lt_i32 first = (lo + LT_BVH_MORTON_BLOCK - 1) / LT_BVH_MORTON_BLOCK, end = hi / LT_BVH_MORTON_BLOCK;
  if (first >= end) first = end = 0; /* no whole block: every position on its own */

  /* Positions before the first whole block and after the last. */
  lt_i32 head = first < end ? first * LT_BVH_MORTON_BLOCK : hi, tail = first < end ? end * LT_BVH_MORTON_BLOCK : hi;
  for (lt_i32 i = lo; i < head; i++) {
    LT_GLOBAL const lt_v4 *p = prim_boxes + 2 * (long)index[i];
    blo = lt_v4_min(p[0], blo), bhi = lt_v4_max(p[1], bhi);
  }
  for (lt_i32 i = tail; i < hi; i++) {
    LT_GLOBAL const lt_v4 *p = prim_boxes + 2 * (long)index[i];
    blo = lt_v4_min(p[0], blo), bhi = lt_v4_max(p[1], bhi);
  }

  /* Whole blocks: an odd end of the range is a box of its own on this level, the rest pairs up. */
  lt_i32 level = 0, count = blocks;
  while (first < end) {
    if (first & 1) {
      LT_GLOBAL const lt_v4 *p = block_boxes + 2 * (long)(level + first++);
      blo = lt_v4_min(p[0], blo), bhi = lt_v4_max(p[1], bhi);
    }
    if (end & 1) {
      LT_GLOBAL const lt_v4 *p = block_boxes + 2 * (long)(level + --end);
      blo = lt_v4_min(p[0], blo), bhi = lt_v4_max(p[1], bhi);
    }
    first >>= 1, end >>= 1;
    level += count, count = (count + 1) >> 1;
  }
  return lt_box_of4(blo, bhi);
}

#endif
