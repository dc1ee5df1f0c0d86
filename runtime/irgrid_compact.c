/* Compaction of a finished irregular grid (see irgrid_host.h): what a full build leaves behind
 * that no ray will read is given back.
 *
 * The build allocates from three heaps and never frees: the top lists the COUNT task filled,
 * the initial cells and lists that merging replaced, and their sub-map room stay where they
 * were. Once every top cell is built nothing changes any more, so the live part is copied out:
 * the cells some voxel maps to, renumbered in the order the voxel map first meets them (top
 * cells x fastest, then sub-voxels: cells near in space end up near in memory), each cell's
 * list copied after the previous one's (or sharing an earlier cell's equal list), and each sub-map
 * rewritten as an octree below its level (the finest top within LT_IRG_MAP_SLACK of the fewest
 * entries). When the fine grid is at most
 * LT_IRG_CELL16_MAX voxels a side (every Table 1 scene's is), the cells are written as
 * lt_irg_cell16, half the bytes, the lists packed (count first, then the steps between
 * triangles as varints: lt_irg_list_pack) and the sub-map entries in 3 bytes; larger fine grids
 * (or grids of more than 2^23 cells) keep lt_irg_cell, lists of 32-bit triangle numbers and
 * 32-bit entries, which only the trace kernel of a finished grid and the host copy
 * (lt__irgrid_read) tell apart. The build's scratch buffers and the task pool go too.
 * Done on the host: it runs once per full build, after the last launch, and keeps the device
 * kernel (which PoCL's LLVM already finds hard to compile) as it is. */
#include <stdlib.h>
#include <string.h>

#include "runtime/error.h"
#include "runtime/irgrid_host.h"

/* How many times the fewest entries a top cell's compacted sub-map may take to be one level
 * flatter: every octree level below the top is one more dependent load in each lookup, and
 * lookups are on the walk's critical path. Measured at 2 against 1 (the fewest), with the
 * fast walk (docs/notes/irgrid.md, "The fast walk"): sphere:6's primary trace 1.24x -> 1.09x
 * the SAH BVH's time, hairball:3000 1.17x -> 1.07x; the map 1.1-1.5x larger (hairball:3000
 * 11.29 -> 12.80 MB, teapot-stadium 10.60 -> 15.64 MB; docs/results/irgrid_compaction.md). */
#define LT_IRG_MAP_SLACK 2.0

/* The compact arrays, built on the host from a copy of the grid's. */
typedef struct compacted {
  lt_i32 *top_map, *sub_maps, *refs;
  lt_irg_cell *cells;     /* begin and end bound a list's triangles in refs */
  lt_irg_cell16 *cells16; /* narrow: the cells as uploaded */
  lt_u8 *packed;          /* narrow: the lists as uploaded, packed_words 32-bit words */
  lt_u8 *map24;           /* narrow: the sub-maps as uploaded (3 bytes an entry), map_words 32-bit words */
  int narrow;             /* cells16, packed and map24 made */
  int sub_count, cell_count, ref_count, packed_words, map_words;
} compacted;

static void compacted_free(compacted *c) {
  free(c->top_map), free(c->sub_maps), free(c->refs), free(c->cells), free(c->cells16), free(c->packed);
  free(c->map24);
}

/* Whether the cells of a fine grid of these dimensions fit lt_irg_cell16, and the triangle
 * numbers of a scene of count triangles a packed list. */
static int fits_cell16(lt_int4 dims, int count) {
  return dims.x <= LT_IRG_CELL16_MAX && dims.y <= LT_IRG_CELL16_MAX && dims.z <= LT_IRG_CELL16_MAX &&
         count <= LT_IRG_PACK_MAX;
}

/* Rewrites a top cell's sub-map map[] of the given level at the coarsest level that says the
 * same about every fine voxel: level l - 1 will do when each 2x2x2 block of sub-voxels maps to
 * one cell (merged cells cover whole blocks often, empty space most of all). Returns the level. */
static int coarsen(lt_i32 *map, int level) {
  for (; level > 0; level--) {
    int side = 1 << level, half = side / 2;
    for (int z = 0; z < side; z++)
      for (int y = 0; y < side; y++)
        for (int x = 0; x < side; x++)
          if (map[x + side * (y + side * z)] != map[(x & ~1) + side * ((y & ~1) + side * (z & ~1))]) return level;
    /* In place: each entry is read from at or after where it is written. */
    for (int z = 0; z < half; z++)
      for (int y = 0; y < half; y++)
        for (int x = 0; x < half; x++) map[x + half * (y + half * z)] = map[2 * x + side * (2 * y + side * 2 * z)];
  }
  return 0;
}

/* FNV-1a over a reference list's triangle numbers. */
static size_t list_hash(const lt_i32 *list, int length) {
  size_t h = 2166136261u;
  for (int i = 0; i < length; i++) h = (h ^ (size_t)(lt_u32)list[i]) * 16777619u;
  return h ^ (size_t)length;
}

/* Whether a compacted cell's list (in refs) is the given list. */
static int same_list(const lt_irg_cell *cell, const lt_i32 *refs, const lt_i32 *list, int length) {
  return cell->end - cell->begin == length && !memcmp(refs + cell->begin, list, (size_t)length * sizeof *list);
}

/* The map being compacted: one top cell's sub-map of side 2^level (x fastest), the cells
 * renumbered so far and the compact arrays they go to. */
typedef struct octree {
  const lt_i32 *map;
  int side;
  lt_i32 *renumber;
  const lt__irgrid_arrays *a;
  compacted *c;
  size_t refs;
} octree;

/* Whether the block of the map at (x, y, z), width wide, maps to one cell. */
static int uniform(const octree *o, int x, int y, int z, int width) {
  lt_i32 first = o->map[x + o->side * (y + o->side * z)];
  for (int k = 0; k < width; k++)
    for (int j = 0; j < width; j++)
      for (int i = 0; i < width; i++)
        if (o->map[x + i + o->side * (y + j + o->side * (z + k))] != first) return 0;
  return 1;
}

/* The entries the octree below one block takes (0 when it is one cell). */
static size_t octree_size(const octree *o, int x, int y, int z, int width) {
  if (uniform(o, x, y, z, width)) return 0;
  size_t size = 8;
  int half = width / 2;
  for (int oct = 0; oct < 8; oct++)
    size += octree_size(o, x + (oct & 1) * half, y + (oct >> 1 & 1) * half, z + (oct >> 2) * half, half);
  return size;
}

/* The entry for one block, to be written at sub-map index at: its cell's new number, or -k, its
 * eight halves going at at + k. They go after every entry written so far, within the top cell's
 * own entries, which are never more than its flat sub-map's (at most 8^5): k is below 2^15. */
static lt_i32 octree_entry(octree *o, lt_i32 at, int x, int y, int z, int width) {
  if (uniform(o, x, y, z, width)) {
    lt_i32 old = o->map[x + o->side * (y + o->side * z)];
    if (o->renumber[old] < 0) {
      o->renumber[old] = o->c->cell_count;
      o->c->cells[o->c->cell_count++] = o->a->cells[old];
      o->refs += (size_t)(o->a->cells[old].end - o->a->cells[old].begin);
    }
    return o->renumber[old];
  }
  lt_i32 node = o->c->sub_count;
  o->c->sub_count += 8;
  int half = width / 2;
  for (int oct = 0; oct < 8; oct++)
    o->c->sub_maps[node + oct] =
        octree_entry(o, node + oct, x + (oct & 1) * half, y + (oct >> 1 & 1) * half, z + (oct >> 2) * half, half);
  return at - node;
}

/* Packs the lists of c's cells (laid end to end in c->refs, a cell whose list an earlier one
 * holds pointing at that one's, owner[i] the cell whose list cell i reads) and makes the 16-byte
 * cells. *fits is 0 when the packed lists pass what a cell's offset holds: the cells stay wide. */
static lt_status pack_lists(compacted *c, const lt_i32 *owner, int *fits) {
  size_t room = 4 * ((size_t)c->cell_count + (size_t)c->ref_count) + 4;
  c->packed = calloc(room, 1);
  c->cells16 = malloc(((size_t)c->cell_count + 1) * sizeof *c->cells16);
  if (!c->packed || !c->cells16)
    return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory packing %d cells", c->cell_count);
  size_t size = 0;
  *fits = 1;
  for (int i = 0; i < c->cell_count && *fits; i++) {
    const lt_irg_cell *cell = &c->cells[i];
    lt_irg_cell16 *n = &c->cells16[i];
    /* Each box's coordinates are at most the fine grid's side. */
    for (int k = 0; k < 3; k++) n->lo[k] = (lt_u16)cell->lo[k], n->hi[k] = (lt_u16)cell->hi[k];
    if (owner[i] < i) {
      n->list = c->cells16[owner[i]].list;
      continue;
    }
    n->list = (lt_i32)size;
    size += (size_t)lt_irg_list_pack(c->refs + cell->begin, cell->end - cell->begin, c->packed + size);
    *fits = size <= (size_t)0x7ffffffc;
  }
  c->packed_words = (int)((size + 3) / 4);
  return LT_OK;
}

/* The sub-maps' entries in 3 bytes each (lt_irg_map_entry), with a byte after the last; every
 * entry, a cell number or minus the step to an octree node (below 2^15), fits 24 bits when
 * cells number at most LT_IRG_MAP24_MAX. */
static lt_status pack_map(compacted *c) {
  size_t bytes = 3 * (size_t)c->sub_count + 1;
  c->map_words = (int)((bytes + 3) / 4);
  c->map24 = calloc((size_t)c->map_words, 4);
  if (!c->map24) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory packing %d voxel map entries", c->sub_count);
  for (int i = 0; i < c->sub_count; i++) {
    lt_u32 e = (lt_u32)c->sub_maps[i];
    for (int b = 0; b < 3; b++) c->map24[3 * (size_t)i + (size_t)b] = (lt_u8)(e >> (8 * b));
  }
  return LT_OK;
}

/* Renumbers the live cells of a (every top cell built; its sub-maps are coarsened in place)
 * and lays out the compact arrays, narrow (lt_irg_cell16, lists and map entries packed) or not
 * (nor where they do not fit). */
static lt_status compact_arrays(const lt__irgrid *g, lt__irgrid_arrays *a, int narrow, compacted *c) {
  memset(c, 0, sizeof *c);
  c->narrow = narrow;
  lt_i32 *renumber = malloc(((size_t)a->cell_count + 1) * sizeof *renumber);
  c->top_map = malloc((size_t)g->top_count * sizeof *c->top_map);
  c->sub_maps = malloc(((size_t)a->sub_count + 1) * sizeof *c->sub_maps);
  c->cells = malloc(((size_t)a->cell_count + 1) * sizeof *c->cells);
  if (!renumber || !c->top_map || !c->sub_maps || !c->cells) {
    free(renumber), compacted_free(c);
    return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory compacting an irregular grid of %d cells", a->cell_count);
  }
  for (int i = 0; i < a->cell_count; i++) renumber[i] = -1;

  /* Cells in the order the voxel map meets them; sub-maps one after another, each as an
   * octree whose top is the finest level that takes at most LT_IRG_MAP_SLACK times the fewest
   * entries, at or below the level whose sub-voxels the top map's entry names. */
  octree o = {NULL, 0, renumber, a, c, 0};
  for (int t = 0; t < g->top_count; t++) {
    lt_i32 entry = a->top_map[t];
    if (entry < 0) {
      free(renumber), compacted_free(c);
      return lt__fail(LT_ERROR_INVALID_ARGUMENT, "compacting an irregular grid whose top cell %d is not built", t);
    }
    int level = LT_IRG_ENTRY_LEVEL(entry);
    lt_i32 *sub = a->sub_maps + LT_IRG_ENTRY_BASE(entry);
    level = coarsen(sub, level);
    o.map = sub, o.side = 1 << level;
    size_t sizes[LT_IRG_MAX_LEVEL + 1], best = (size_t)1 << (3 * level);
    sizes[level] = best;
    for (int l = level - 1; l >= 0; l--) {
      int width = 1 << (level - l), side = 1 << l;
      size_t size = (size_t)1 << (3 * l);
      for (int s = 0; s < side * side * side; s++)
        size += octree_size(&o, s % side * width, s / side % side * width, s / (side * side) * width, width);
      sizes[l] = size;
      if (size < best) best = size;
    }
    int top = level;
    while (top > 0 && (double)sizes[top] > LT_IRG_MAP_SLACK * (double)best) top--;
    int width = 1 << (level - top), side = 1 << top;
    lt_i32 base = c->sub_count;
    c->top_map[t] = LT_IRG_ENTRY(top, base);
    c->sub_count += side * side * side;
    for (int s = 0; s < side * side * side; s++)
      c->sub_maps[base + s] =
          octree_entry(&o, base + s, s % side * width, s / side % side * width, s / (side * side) * width, width);
  }
  free(renumber);
  size_t refs = o.refs;

  /* Each live cell's list after the previous one's, or, when an earlier cell holds the very
   * same list, that cell's: readers only read it, never write it. */
  c->refs = malloc((refs + 1) * sizeof *c->refs);
  size_t slots = 1;
  while (slots < 2 * (size_t)c->cell_count + 2) slots *= 2;
  lt_i32 *table = malloc(slots * sizeof *table);
  lt_i32 *owner = malloc(((size_t)c->cell_count + 1) * sizeof *owner);
  if (!c->refs || !table || !owner) {
    free(table), free(owner), compacted_free(c);
    return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory compacting %zu references", refs);
  }
  for (size_t s = 0; s < slots; s++) table[s] = -1;
  for (int i = 0; i < c->cell_count; i++) {
    lt_irg_cell *cell = &c->cells[i];
    const lt_i32 *list = a->refs + cell->begin;
    int length = cell->end - cell->begin;
    size_t s = list_hash(list, length) & (slots - 1);
    while (table[s] >= 0 && !same_list(&c->cells[table[s]], c->refs, list, length)) s = (s + 1) & (slots - 1);
    owner[i] = table[s] >= 0 ? table[s] : i;
    if (table[s] >= 0) {
      cell->begin = c->cells[table[s]].begin, cell->end = c->cells[table[s]].end;
      continue;
    }
    memcpy(c->refs + c->ref_count, list, (size_t)length * sizeof *c->refs);
    cell->begin = c->ref_count, cell->end = c->ref_count + length;
    c->ref_count += length;
    table[s] = i;
  }
  free(table);
  if (!narrow || c->cell_count > LT_IRG_MAP24_MAX) {
    free(owner);
    c->narrow = 0;
    return LT_OK;
  }

  /* The 16-byte cells, packed lists and 3-byte map entries, unless the lists pass 2^31 bytes. */
  lt_status status = pack_lists(c, owner, &c->narrow);
  free(owner);
  if (!status && c->narrow) status = pack_map(c);
  if (status) compacted_free(c);
  return status;
}

lt_status lt__irgrid_compact(lt__irgrid *g) {
  lt__irgrid_arrays a;
  lt_status status = lt__irgrid_read(g, &a);
  if (status) return status;
  compacted c;
  status = compact_arrays(g, &a, fits_cell16(g->fine.dims, g->count), &c);
  lt__irgrid_arrays_free(&a);
  if (status) return status;

  /* New buffers first: should one fail, the grid is left whole as it was. */
  lt__buffer fresh[4];
  const void *data[4] = {c.top_map, c.narrow ? (const void *)c.map24 : c.sub_maps,
                         c.narrow ? (const void *)c.cells16 : c.cells, c.narrow ? (const void *)c.packed : c.refs};
  size_t cell_size = c.narrow ? sizeof *c.cells16 : sizeof *c.cells;
  int map_words = c.narrow ? c.map_words : c.sub_count, ref_words = c.narrow ? c.packed_words : c.ref_count;
  size_t bytes[4] = {(size_t)g->top_count * sizeof *c.top_map, (size_t)map_words * sizeof *c.sub_maps,
                     (size_t)c.cell_count * cell_size, (size_t)ref_words * sizeof *c.refs};
  int made = 0;
  while (!status && made < 4) {
    status = lt__buffer_create(g->ctx, &fresh[made], bytes[made], data[made], 0);
    if (!status) made++;
  }
  if (status) {
    while (made > 0) lt__buffer_release(&fresh[--made]);
    compacted_free(&c);
    return status;
  }
  lt__buffer *old[4] = {&g->top_map, &g->sub_maps, &g->cells, &g->refs};
  for (int i = 0; i < 4; i++) lt__buffer_release(old[i]), *old[i] = fresh[i];
  g->narrow = c.narrow;

  /* The heaps say what they hold now. */
  lt__heap *heaps[3] = {&g->map_heap, &g->cell_heap, &g->ref_heap};
  int units[3] = {map_words, c.cell_count, ref_words};
  compacted_free(&c);
  for (int i = 0; i < 3 && !status; i++) {
    heaps[i]->capacity = units[i];
    status = lt__buffer_fill(g->ctx, &heaps[i]->top, units[i]);
  }
  if (status) return status;

  /* What only the build read: the top lists' offsets, triangle boxes and scratch. */
  lt__buffer *build_only[] = {&g->top_begin, &g->top_fill, &g->prim_boxes, &g->scratch, &g->cell_scratch};
  for (size_t i = 0; i < sizeof build_only / sizeof build_only[0]; i++) lt__buffer_release(build_only[i]);
  /* And the task pool: a compacted grid is traced by the plain kernel, which takes no tasks. */
  lt__pool_release(&g->pool);
  g->compacted = 1;
  return LT_OK;
}
