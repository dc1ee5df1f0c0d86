/* The uniform grid (Thrane and Simonsen 2005, section 7): its layout, and every way to find a
 * cell or read what it holds. The host builder (builders/host/grid.c) and the traversal
 * (traversal/grid_traverse.h) both go through this header, so that the planes between cells
 * are written down once.
 *
 * A grid is three flat arrays:
 *
 *   header       one lt_grid_header: the box, the cell size and the resolution
 *   cell_begin   dims.w + 1 offsets: cell c holds refs[cell_begin[c] .. cell_begin[c + 1])
 *   refs         triangle numbers, ascending within a cell
 *
 * Triangles are not copied: traversal reads them through their numbers from the scene's own
 * vertex array (9 floats per triangle, in triangle-number order), as the pool-built BVH does,
 * because a triangle is referenced from every cell its box overlaps and copies would multiply.
 * Cells are numbered x fastest: c = x + dims.x * (y + dims.y * z).
 *
 * The plane between cells j - 1 and j on an axis is the float lt_grid_plane(axis, j): exactly
 * lo for j = 0 and exactly hi for j = dims, lo + j * size (float arithmetic, clamped to hi) in
 * between. The builder decides which cells a triangle's box overlaps against these floats and
 * the traversal computes its crossing distances from the very same floats, so that both agree
 * bit for bit about where a cell ends. Planes never decrease with j, which is all the
 * traversal's argument needs (see grid_traverse.h); a cell of zero width is allowed. */
#ifndef LT_DEVICE_GRID_CELLS_H
#define LT_DEVICE_GRID_CELLS_H

#include "device/types.h"

/* The most cells along one axis: cell numbers along an axis are then exact as floats. */
#define LT_GRID_MAX_AXIS_CELLS (1 << 24)

typedef struct lt_grid_header {
  lt_float4 lo;   /* 16 bytes: lower corner x, y, z (the bounds of the triangles), w 0 */
  lt_float4 hi;   /* 16 bytes: upper corner x, y, z, w 0 */
  lt_float4 size; /* 16 bytes: cell size along x, y, z (0 on an axis of zero extent), w 0 */
  lt_int4 dims;   /* 16 bytes: cells along x, y, z (each at least 1), w = all cells */
} lt_grid_header;

#ifndef __OPENCL_VERSION__
_Static_assert(sizeof(lt_grid_header) == 64, "lt_grid_header is 64 bytes on both sides");
_Static_assert(_Alignof(lt_grid_header) == 16, "lt_grid_header is 16-byte aligned on both sides");
#endif

/* One axis of the grid, unpacked into private memory for the loops that walk it. */
typedef struct lt_grid_axis {
  float lo, hi, size;
  int n; /* cells along the axis */
} lt_grid_axis;

/* Axis k (0, 1, 2) of a header. */
LT_DEVICE lt_grid_axis lt_grid_axis_of(LT_GLOBAL const lt_grid_header *g, int k) {
  lt_grid_axis a;
  a.lo = k == 0 ? g->lo.x : k == 1 ? g->lo.y : g->lo.z;
  a.hi = k == 0 ? g->hi.x : k == 1 ? g->hi.y : g->hi.z;
  a.size = k == 0 ? g->size.x : k == 1 ? g->size.y : g->size.z;
  a.n = k == 0 ? g->dims.x : k == 1 ? g->dims.y : g->dims.z;
  return a;
}

/* The plane below cell j (0 <= j <= n): the one float every side uses for it. The clamp keeps
 * the planes non-decreasing when lo + j * size rounds past hi. */
LT_DEVICE float lt_grid_plane(const lt_grid_axis *a, int j) {
  if (j <= 0) return a->lo;
  if (j >= a->n) return a->hi;
  float p = a->lo + (float)j * a->size;
  return p < a->hi ? p : a->hi;
}

/* A first guess at the cell holding coordinate x, always in [0, n - 1]; the exact answer is
 * found from it by comparing with the planes, so it may be off by rounding. A NaN or a
 * coordinate off the grid gives the nearest end. */
LT_DEVICE int lt_grid_cell_guess(const lt_grid_axis *a, float x) {
  float f = (x - a->lo) / a->size;
  if (!(f >= 0.0f)) return 0;
  if (f >= (float)(a->n - 1)) return a->n - 1;
  return (int)f;
}

/* The lowest cell j whose upper plane is at or above x (so that [plane j, plane j + 1] can
 * hold x, when x is not below lo); n when x is above hi. */
LT_DEVICE int lt_grid_first_cell(const lt_grid_axis *a, float x) {
  int j = lt_grid_cell_guess(a, x);
  while (j > 0 && lt_grid_plane(a, j) >= x) j--;
  while (j < a->n && lt_grid_plane(a, j + 1) < x) j++;
  return j;
}

/* The highest cell j whose lower plane is at or below x; -1 when x is below lo. Cells
 * lt_grid_first_cell(lo_x) .. lt_grid_last_cell(hi_x) are exactly those whose closed slab
 * meets [lo_x, hi_x], and with lo_x = hi_x = x, those whose closed slab holds x. */
LT_DEVICE int lt_grid_last_cell(const lt_grid_axis *a, float x) {
  int j = lt_grid_cell_guess(a, x);
  while (j < a->n - 1 && lt_grid_plane(a, j + 1) <= x) j++;
  while (j >= 0 && lt_grid_plane(a, j) > x) j--;
  return j;
}

/* The number of the cell at (x, y, z) in a grid of nx by ny by any cells. */
LT_DEVICE lt_i32 lt_grid_cell_index(int nx, int ny, int x, int y, int z) { return x + nx * (y + ny * z); }

/* The references of one cell: refs[*begin .. *end). */
LT_DEVICE void lt_grid_cell_range(LT_GLOBAL const lt_i32 *cell_begin, lt_i32 cell, lt_i32 *begin, lt_i32 *end) {
  *begin = cell_begin[cell];
  *end = cell_begin[cell + 1];
}

#endif
