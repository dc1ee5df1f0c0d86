/* The host half of the irregular grid: the top grid's resolution, buffers and heaps, launches
 * of its persistent kernel (kernels/irgrid_ondemand.h) and of its trace kernel on a finished
 * grid (kernels/irgrid_trace.h), and its counters. */
#ifndef LT_IRGRID_HOST_H
#define LT_IRGRID_HOST_H

#include "builders/irgrid_task.h"
#include "runtime/heap_host.h"
#include "runtime/pool_host.h"

typedef struct lt__irgrid_config {
  float top_density;    /* lambda1: top cells per triangle */
  float cell_density;   /* lambda2: sub-voxels per reference of a top cell */
  float merge_alpha;    /* merging stops when a round merges fewer than 1 - alpha of the cells */
  int merge;            /* 0: no merge passes (the two-level grid) */
  int global_merge;     /* merge across top cells once all are built (full builds) */
  int expansion_passes;
  float traversal_cost, intersection_cost; /* Ct, Ci of the merge cost */
  float uniform;        /* > 0: a uniform grid of this resolution factor (builders/host/grid.h), top
                           cells never cut: the COUNT task alone builds it */
} lt__irgrid_config;

/* What the heaps hold room for. */
typedef struct lt__irgrid_room {
  int pool, cells, refs, maps;
} lt__irgrid_room;

typedef struct lt__irgrid {
  lt_context *ctx;
  lt__pool pool;
  lt__heap cell_heap, ref_heap, map_heap;
  lt__buffer verts, prim_boxes, header, top_map, top_begin, top_fill, sub_maps, cells, refs, scratch, counters;
  lt__buffer control, cell_scratch;
  lt_grid_header fine; /* the fine grid */
  int top_dims[3], top_count, count;
  int shift; /* fine voxels per top cell: 2^shift per axis (0 for a uniform grid) */
  int compacted; /* lt__irgrid_compact ran: the top lists and the build's scratch are gone */
  int narrow;    /* compacted into lt_irg_cell16 (the fine grid fits 16 bits a side), lists and map packed */
  lt__irgrid_config config;
  double totals[LT_IRG_STAT_COUNT]; /* the build's counters over all launches */
} lt__irgrid;

/* Top cells per axis for a scene of n triangles with these extents at density lambda1: about
 * lambda1 * n near-cubical cells (an axis of zero extent gets one), at most 2^22 in all. */
void lt__irgrid_top_dims(const double extent[3], size_t n, float density, int dims[3]);
/* An irregular grid over the scene with nothing built: the COUNT task waits in its pool. */
lt_status lt__irgrid_create(lt_context *ctx, const lt_scene *scene, const lt__irgrid_config *config, int mode,
                            const lt__irgrid_room *room, lt__irgrid *g);
void lt__irgrid_release(lt__irgrid *g);
/* One launch of the persistent kernel: traces count rays (none: a full build builds all) and
 * writes hits; speculate: work-groups out of rays build top cells nobody asked for. */
lt_status lt__irgrid_launch(lt__irgrid *g, const lt_ray *rays, int count, int flags, lt_hit *hits, int speculate,
                            lt_stats *stats);
/* After a full build's launch, with global merging: the merge passes across the grid and the
 * expansion passes after them, in a launch of their own (kernels/irgrid_ondemand.h). */
lt_status lt__irgrid_merge(lt__irgrid *g, lt_stats *stats);
/* Traces a batch through the plain trace kernel; every top cell must be built. */
lt_status lt__irgrid_trace_finished(lt__irgrid *g, const lt_ray *rays, int count, int flags, lt_hit *hits,
                                    lt_stats *stats);
/* Gives back what a finished grid no longer needs (runtime/irgrid_compact.c): cells and
 * lists that merging replaced, the top lists, the build's scratch, the task pool; the lists
 * that equal an earlier cell's shared, the sub-maps made octrees, and the cells made 16 bytes
 * (lt_irg_cell16, lists packed: lt_irg_list_pack, sub-map entries in 3 bytes) when the fine
 * grid is at most LT_IRG_CELL16_MAX a side (else they keep lt_irg_cell). Every top cell must be
 * built; traversal finds the same cells' contents at the same voxels. On failure the grid is
 * left as it was. */
lt_status lt__irgrid_compact(lt__irgrid *g);
/* Which heap the last launch ran out of, if any: 1 cells, 2 references, 3 sub-maps, 0 none. */
int lt__irgrid_heap_full(lt__irgrid *g);
/* Device bytes in use: cells, references (top lists and cells' lists), voxel map (top map
 * and sub-maps), pool; the total adds the triangles' boxes and the build's scratch. */
double lt__irgrid_bytes(lt__irgrid *g, double *cell_bytes, double *reference_bytes, double *map_bytes,
                        double *pool_bytes);
/* A host copy of a grid's arrays (for tests that check cells and compare grids); free with
 * lt__irgrid_arrays_free. A compacted grid has no top lists: top_begin is all zero. Cells are
 * copied as lt_irg_cell whatever their layout, and lists as 32-bit triangle numbers: a
 * compacted grid's packed lists are decoded, each once (cells that share a list share its
 * copy), and ref_count counts the triangles decoded; its packed sub-maps are read as lt_i32. */
typedef struct lt__irgrid_arrays {
  lt_i32 *top_map, *top_begin, *sub_maps, *refs;
  lt_irg_cell *cells;
  int sub_count, cell_count, ref_count;
} lt__irgrid_arrays;
lt_status lt__irgrid_read(lt__irgrid *g, lt__irgrid_arrays *out);
void lt__irgrid_arrays_free(lt__irgrid_arrays *a);
/* The irregular grid behind a structure, or NULL (for tests). */
lt__irgrid *lt__irgrid_of(lt_structure *structure);
/* The uniform grid behind a structure (runtime/structure_grid.c builds it as a grid of top
 * cells only), or NULL (for tests). */
lt__irgrid *lt__uniform_grid_of(lt_structure *structure);

#endif
