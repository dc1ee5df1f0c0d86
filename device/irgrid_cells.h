/* The irregular grid (Perard-Gayot, Kalojanov and Slusallek 2017): its cells and its voxel map,
 * and the one way every side finds the cell of a voxel.
 *
 * Everything is placed on a fine virtual grid (an lt_grid_header, device/grid_cells.h): the
 * top-level grid's cells are blocks of 2^shift fine voxels per axis, and a top cell of level
 * l is cut into 2^l sub-voxels per axis, each 2^(shift - l) fine voxels wide. Cells are boxes of
 * fine voxels, so the planes between any two cells are the fine grid's plane floats
 * (lt_grid_plane), which the builder decides references against and the traversal computes
 * its crossings from: both agree bit for bit about where a cell ends, as in the uniform grid.
 *
 *   top_map    one entry per top cell, x fastest:
 *                >= 0   built: level (bits 28..30) and the index of its sub-map (bits 0..27)
 *                -1     the top level is still being counted (wait)
 *                <= -2  not built yet: -2 - slot, the pool slot of the task that builds it
 *   sub_maps   per built top cell, 8^level cell numbers, sub-voxels x fastest; once a full
 *              build is compacted, an entry at index i may instead be -k: the sub-voxel is cut
 *              in eight, whose entries (of the same two kinds) are sub_maps[i + k .. i + k + 8),
 *              x fastest (k is below 2^15: a top cell's octree is smaller);
 *              behind lt_irg_cell16 the entries are packed in 3 bytes each (lt_irg_map_entry)
 *   cells      lt_irg_cell: the box the traversal leaves through and the cell's references; a
 *              compacted grid whose fine grid fits 16 bits a side holds lt_irg_cell16 instead
 *   refs       triangle numbers, ascending within a cell; behind lt_irg_cell16 the lists are
 *              packed instead: bytes, each list its count and then the steps between its
 *              triangles (lt_irg_list_pack below), the cell holding the byte offset
 *
 * A cell's box may be larger than the voxels that map to it: expansion grows it over
 * neighbouring voxels all of whose triangles the cell already references (see
 * builders/irgrid_task.h), so that a ray leaves it later and skips what it would test again. */
#ifndef LT_DEVICE_IRGRID_CELLS_H
#define LT_DEVICE_IRGRID_CELLS_H

#include "device/grid_cells.h"

/* The deepest subdivision of a top cell: 2^5 = 32 sub-voxels per axis. The fine grid is the
 * top grid refined this many times, whatever the levels of the top cells turn out to be. */
#define LT_IRG_MAX_LEVEL 5

#define LT_IRG_COUNTING (-1)
#define LT_IRG_UNBUILT(slot) (-2 - (slot))
#define LT_IRG_UNBUILT_SLOT(entry) (-2 - (entry))
#define LT_IRG_ENTRY(level, base) (((level) << 28) | (base))
#define LT_IRG_ENTRY_LEVEL(entry) ((entry) >> 28)
#define LT_IRG_ENTRY_BASE(entry) ((entry) & 0x0fffffff)
#define LT_IRG_MAX_MAP 0x0fffffff

/* One cell as the builders write it and traversal reads it: 32 bytes. */
typedef struct lt_irg_cell {
  lt_i32 lo[3], hi[3]; /* 24 bytes: the box, fine voxels [lo, hi) on each axis */
  lt_i32 begin, end;   /* 8 bytes: its references, refs[begin .. end) */
} lt_irg_cell;

/* One cell of a compacted grid whose fine grid is at most LT_IRG_CELL16_MAX voxels a side:
 * 16 bytes. Its list is packed (lt_irg_list_pack): the count comes first, so the cell needs no
 * end, and cells with equal lists still share one. Compaction keeps lt_irg_cell, 32-bit lists
 * and map entries for larger fine grids (the builder allows 2^24 a side), and for grids of more
 * than LT_IRG_MAP24_MAX cells. */
typedef struct lt_irg_cell16 {
  lt_u16 lo[3], hi[3]; /* 12 bytes: the box, fine voxels [lo, hi) on each axis */
  lt_i32 list;         /* 4 bytes: the byte offset of its packed list in refs */
} lt_irg_cell16;

/* The largest fine grid side whose boxes lt_irg_cell16 holds (hi is at most the side). */
#define LT_IRG_CELL16_MAX 65535

#ifndef __OPENCL_VERSION__
_Static_assert(sizeof(lt_irg_cell) == 32, "lt_irg_cell is 32 bytes on both sides");
_Static_assert(sizeof(lt_irg_cell16) == 16, "lt_irg_cell16 is 16 bytes on both sides");
#endif

/* A native trace kernel built for 16-byte cells only (kernels/native_irgrid_trace.c) defines
 * this to 1 before anything includes this header: the layout is then chosen once a launch, by
 * which kernel runs, instead of at every cell read (about 1.5% of the instructions on
 * hairball:3000). */
#ifndef LT_IRG_CELL16_ONLY
#define LT_IRG_CELL16_ONLY 0
#endif

/* Cell i in the layout traversal reads, from cells16 when it is given (a compacted grid's
 * 16-byte cells, whose lists are packed: begin is then the list's byte offset, and end is not
 * used; lt_irg_list_open reads either), else from cells. */
LT_DEVICE lt_irg_cell lt_irg_cell_get(LT_GLOBAL const lt_irg_cell *cells, LT_GLOBAL const lt_irg_cell16 *cells16,
                                      lt_i32 i) {
  if (!LT_IRG_CELL16_ONLY && !cells16) return cells[i];
  LT_GLOBAL const lt_irg_cell16 *n = &cells16[i];
  lt_irg_cell c;
  for (int k = 0; k < 3; k++) c.lo[k] = n->lo[k], c.hi[k] = n->hi[k];
  c.begin = c.end = n->list;
  return c;
}

/* Packed lists. A list of n ascending triangles is written as n, then as tokens: a token stands
 * for a triangle and up to LT_IRG_RUN - 1 more that follow it one by one (t, t + 1, ...), and
 * holds (t - p - 1) * LT_IRG_RUN + (how many follow), p being the last triangle of the token
 * before (-1 for the first). Every number is a varint: 7 bits a byte, low bits first, the high
 * bit set on every byte but the last; the fourth byte, if any, is the last and holds 8 bits, so a
 * number is below 2^29. Hair and other thin geometry reference short runs of triangles with small
 * steps between them (hairball:3000: 7.09M references in 3.08M runs, 58% one after the one
 * before): 0.9 bytes a reference there (1.0 with the counts), and a token decodes a run at a
 * time. Runs of up to four take the fewest bytes on sphere:6; up to eight would take 5% fewer
 * on hairball:3000 and 8% fewer on hairball:10000 but 5% more on sphere:6; up to two, 13% more
 * on hairball:3000. */
#define LT_IRG_RUN 4
/* Triangle numbers (and counts) a packed list holds: t * LT_IRG_RUN + 3 must stay below 2^29. */
#define LT_IRG_PACK_MAX (1 << 26)

/* A cell's list being read, triangle by triangle, in either layout. */
typedef struct lt_irg_list {
  lt_i32 at;   /* the next reference's index in refs, or, packed, the next byte's offset */
  lt_i32 left; /* triangles not read yet */
  lt_i32 prim; /* packed: the last triangle read (-1 before the first) */
  lt_i32 run;  /* packed: triangles left in the token being read, each the last + 1 */
} lt_irg_list;

/* The varint at bytes[*at], *at moved past it. */
LT_DEVICE lt_u32 lt_irg_varint(LT_GLOBAL const lt_u8 *bytes, lt_i32 *at) {
  lt_u32 b = bytes[(*at)++], v = b & 127;
  if (b >= 128) {
    b = bytes[(*at)++], v |= (b & 127) << 7;
    if (b >= 128) {
      b = bytes[(*at)++], v |= (b & 127) << 14;
      if (b >= 128) b = bytes[(*at)++], v |= b << 21;
    }
  }
  return v;
}

/* The list of a cell read by lt_irg_cell_get; packed: the grid's lists are packed (16-byte
 * cells). */
LT_DEVICE lt_irg_list lt_irg_list_open(LT_GLOBAL const lt_i32 *refs, int packed, const lt_irg_cell *cell) {
  lt_irg_list l;
  l.at = cell->begin, l.left = cell->end - cell->begin, l.prim = -1, l.run = 0;
  if (packed) l.left = (lt_i32)lt_irg_varint((LT_GLOBAL const lt_u8 *)refs, &l.at);
  return l;
}

/* The list's next triangle (l->left must be positive). */
LT_DEVICE lt_i32 lt_irg_list_next(LT_GLOBAL const lt_i32 *refs, int packed, lt_irg_list *l) {
  l->left--;
  if (!packed) return refs[l->at++];
  if (l->run > 0) {
    l->run--;
    return ++l->prim;
  }
  lt_u32 token = lt_irg_varint((LT_GLOBAL const lt_u8 *)refs, &l->at);
  l->run = (lt_i32)(token % LT_IRG_RUN);
  l->prim += 1 + (lt_i32)(token / LT_IRG_RUN);
  return l->prim;
}

#ifndef __OPENCL_VERSION__
/* Writes n as a varint at out; returns the bytes written (at most 4; n below 2^29). */
static inline int lt_irg_varint_put(lt_u32 n, lt_u8 *out) {
  int k = 0;
  for (; k < 3 && n >= 128; k++, n >>= 7) out[k] = (lt_u8)(n | 128);
  out[k] = (lt_u8)n;
  return k + 1;
}

/* Packs the list of n ascending triangles (each below LT_IRG_PACK_MAX, n too) at out, which has
 * room for 4 + 4 * n bytes; returns the bytes written. */
static inline int lt_irg_list_pack(const lt_i32 *list, int n, lt_u8 *out) {
  int size = lt_irg_varint_put((lt_u32)n, out);
  lt_i32 last = -1;
  for (int i = 0; i < n;) {
    int follow = 0;
    while (i + follow + 1 < n && follow < LT_IRG_RUN - 1 && list[i + follow + 1] == list[i + follow] + 1) follow++;
    size += lt_irg_varint_put((lt_u32)(list[i] - last - 1) * LT_IRG_RUN + (lt_u32)follow, out + size);
    last = list[i + follow];
    i += follow + 1;
  }
  return size;
}
#endif

/* The top cell holding fine voxel (x, y, z), for a fine grid of fine_dims and a given shift. */
LT_DEVICE lt_i32 lt_irg_top_of(lt_int4 fine_dims, int shift, int x, int y, int z) {
  int tx = fine_dims.x >> shift, ty = fine_dims.y >> shift;
  return lt_grid_cell_index(tx, ty, x >> shift, y >> shift, z >> shift);
}

/* A compacted grid with 16-byte cells (whose cells number at most LT_IRG_MAP24_MAX) holds its
 * sub-map entries in 3 bytes each, little-endian, as two's
 * complement 24-bit numbers, with one byte after the last: entry i is at byte 3 * i. Elsewhere
 * an entry is an lt_i32. */
#define LT_IRG_MAP24_MAX (1 << 23)

/* Entry i of the sub-maps, packed (3 bytes an entry) or not. */
LT_DEVICE lt_i32 lt_irg_map_entry(LT_GLOBAL const lt_i32 *sub_maps, int packed, lt_i32 i) {
  if (!packed) return sub_maps[i];
  LT_GLOBAL const lt_u8 *p = (LT_GLOBAL const lt_u8 *)sub_maps + 3 * (long)i;
#if !defined(__OPENCL_VERSION__) && defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
  /* Natively one unaligned load of four bytes (the byte after the last entry is there for it). */
  lt_u32 w;
  __builtin_memcpy(&w, p, 4);
#else
  lt_u32 w = (lt_u32)p[0] | (lt_u32)p[1] << 8 | (lt_u32)p[2] << 16;
#endif
  return (lt_i32)(w << 8) >> 8;
}

/* The cell of fine voxel (x, y, z): its number (>= 0), or the top map's entry when the top
 * cell is not built (< 0); packed: the sub-map entries are 3 bytes (lt_irg_map_entry). The entry
 * is read with acquire ordering: a built entry is published after the sub-map and the cells it
 * leads to. */
LT_DEVICE lt_i32 lt_irg_lookup(LT_GLOBAL const lt_i32 *top_map, LT_GLOBAL const lt_i32 *sub_maps, int packed,
                               lt_int4 fine_dims, int shift, int x, int y, int z) {
  lt_i32 entry = lt_atomic_load_acquire_i32((LT_GLOBAL lt_i32 *)&top_map[lt_irg_top_of(fine_dims, shift, x, y, z)]);
  if (entry < 0) return entry;
  int level = LT_IRG_ENTRY_LEVEL(entry), down = shift - level, mask = (1 << level) - 1;
  int sx = (x >> down) & mask, sy = (y >> down) & mask, sz = (z >> down) & mask;
  lt_i32 at = LT_IRG_ENTRY_BASE(entry) + sx + ((sy + (sz << level)) << level);
  lt_i32 cell = lt_irg_map_entry(sub_maps, packed, at);
  /* A compacted sub-map is an octree below its own level: a negative entry -k at index at leads
   * to the eight sub-voxels of half the width that make up its sub-voxel, at sub_maps[at + k],
   * x fastest. */
  while (cell < 0) {
    down--;
    at += -cell + ((x >> down) & 1) + 2 * ((y >> down) & 1) + 4 * ((z >> down) & 1);
    cell = lt_irg_map_entry(sub_maps, packed, at);
  }
  return cell;
}

#endif
