/* Uniform grid build on the host (Thrane and Simonsen 2005, section 7.1). */
#ifndef LT_GRID_H
#define LT_GRID_H

#include <stddef.h>
#include <stdint.h>

#include "device/grid_cells.h"
#include "lazytrace.h"

/* Parameters with the thesis's defaults (after Pharr and Humphreys, pbrt 1, section 4.3). */
typedef struct lt__grid_config {
  float resolution_factor; /* 3: the longest axis gets round(3 * cbrt(N)) cells for N triangles,
                              the others as many as keep the cells near-cubical */
  int max_cells;           /* 1 << 24: the resolution shrinks evenly until all cells fit */
} lt__grid_config;

lt__grid_config lt__grid_config_default(void);

/* Cells per axis for n triangles in a box of these extents: the longest axis gets
 * round(factor * cbrt(n)), the others as many per unit length (at least one); over
 * max_cells, every axis shrinks by the same ratio. */
void lt__grid_resolution(const double extent[3], size_t n, const lt__grid_config *config, int dims[3]);

/* A grid as flat arrays (layout in device/grid_cells.h) and what it cost. */
typedef struct lt__grid {
  lt_grid_header header;
  lt_i32 *cell_begin;  /* header.dims.w + 1 offsets into refs */
  lt_i32 *refs;        /* ref_count triangle numbers */
  int64_t cell_count;  /* header.dims.w */
  int64_t ref_count;   /* references over all cells (each triangle once per cell its box meets) */
  int64_t empty_cells; /* cells without a reference */
  int max_cell_refs;   /* the most references one cell holds */
  size_t bytes;        /* header, offsets and references: what a device would hold */
} lt__grid;

/* Builds over n triangles of 9 floats each (triangle i is tris[9i .. 9i + 9)); a NULL config
 * means lt__grid_config_default(). LT_ERROR_INVALID_ARGUMENT for NULL arrays, n of 0 or above
 * INT32_MAX, a non-finite coordinate or a bad config; LT_ERROR_OUT_OF_MEMORY when an
 * allocation fails or the references would not fit 32-bit offsets. On failure *out is zeroed,
 * so that lt__grid_free is always safe. */
/* The references of a grid with this header over n triangles: each triangle once per cell its
 * box meets, decided against the planes as every builder decides. Stops counting once past
 * `stop` (the caller's limit). */
int64_t lt__grid_reference_count(const lt_grid_header *h, const float *tris, size_t n, int64_t stop);

lt_status lt__grid_build(const float *tris, size_t n, const lt__grid_config *config, lt__grid *out);
void lt__grid_free(lt__grid *grid);

#endif
