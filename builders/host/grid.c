/* The uniform grid of Thrane and Simonsen, "A Comparison of Acceleration Structures for GPU
 * Assisted Ray Tracing" (2005), section 7.1: round(3 * cbrt(N)) near-cubical cells along the
 * longest axis (after Pharr and Humphreys), each triangle referenced from every cell its box meets. */
#include "builders/host/grid.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

lt__grid_config lt__grid_config_default(void) {
  lt__grid_config config = {3.0f, 1 << 24};
  return config;
}

void lt__grid_free(lt__grid *grid) {
  if (!grid) return;
  free(grid->cell_begin);
  free(grid->refs);
  memset(grid, 0, sizeof *grid);
}

static int64_t product(const int dims[3]) { return (int64_t)dims[0] * dims[1] * dims[2]; }

/* Cells per axis: the longest axis gets round(factor * cbrt(n)), the others the same number per
 * unit length (at least one, so that an axis of zero extent gets exactly one). Too many cells
 * shrink every axis by the same ratio, which keeps the cells near-cubical. */
void lt__grid_resolution(const double extent[3], size_t n, const lt__grid_config *config, int dims[3]) {
  double longest = fmax(extent[0], fmax(extent[1], extent[2]));
  double per_unit = longest > 0.0 ? config->resolution_factor * cbrt((double)n) / longest : 0.0;
  for (int k = 0; k < 3; k++) {
    double d = floor(extent[k] * per_unit + 0.5);
    d = d < 1.0 ? 1.0 : d;
    d = d > LT_GRID_MAX_AXIS_CELLS ? LT_GRID_MAX_AXIS_CELLS : d;
    d = d > config->max_cells ? config->max_cells : d;
    dims[k] = (int)d;
  }

  /* Over the cap: scale all axes by the cube root of the excess, a few times at most because
   * axes clamped at one cell stop shrinking; then the longest alone, which always ends. */
  for (int round = 0; round < 16 && product(dims) > config->max_cells; round++) {
    double scale = cbrt((double)config->max_cells / (double)product(dims));
    for (int k = 0; k < 3; k++) dims[k] = (int)fmax(1.0, floor(dims[k] * scale));
  }
  while (product(dims) > config->max_cells) {
    int k = dims[0] >= dims[1] && dims[0] >= dims[2] ? 0 : dims[1] >= dims[2] ? 1 : 2;
    int64_t others = product(dims) / dims[k];
    dims[k] = (int)(config->max_cells / others > 0 ? config->max_cells / others : 1);
  }
}

/* The cells a triangle's box meets, per axis: first[k] .. last[k] (device/grid_cells.h decides
 * against the planes themselves, so that the traversal sees the same cells). */
static int64_t triangle_cells(const lt_grid_axis axes[3], const float *t, int first[3], int last[3]) {
  int64_t count = 1;
  for (int k = 0; k < 3; k++) {
    float a = t[k], b = t[3 + k], c = t[6 + k];
    float lo = a < b ? a : b, hi = a > b ? a : b;
    lo = c < lo ? c : lo, hi = c > hi ? c : hi;
    first[k] = lt_grid_first_cell(&axes[k], lo);
    last[k] = lt_grid_last_cell(&axes[k], hi);
    count *= last[k] - first[k] + 1;
  }
  return count;
}

/* Counts (fill = 0) or writes (fill = 1) the references of every triangle. Counting adds to
 * begin[c + 1] (at most n each, so no overflow); writing uses begin[c + 1] as the cursor of
 * cell c, so that afterwards it is where cell c ends, which is where cell c + 1 begins. */
static void scatter(const lt__grid *grid, const float *tris, size_t n, int fill) {
  const lt_grid_header *h = &grid->header;
  lt_grid_axis axes[3] = {lt_grid_axis_of(h, 0), lt_grid_axis_of(h, 1), lt_grid_axis_of(h, 2)};
  for (size_t i = 0; i < n; i++) {
    int first[3], last[3];
    triangle_cells(axes, tris + 9 * i, first, last);
    for (int z = first[2]; z <= last[2]; z++)
      for (int y = first[1]; y <= last[1]; y++)
        for (int x = first[0]; x <= last[0]; x++) {
          lt_i32 c = lt_grid_cell_index(h->dims.x, h->dims.y, x, y, z);
          if (fill)
            grid->refs[grid->cell_begin[c + 1]++] = (lt_i32)i;
          else
            grid->cell_begin[c + 1]++;
        }
  }
}

int64_t lt__grid_reference_count(const lt_grid_header *h, const float *tris, size_t n, int64_t stop) {
  lt_grid_axis axes[3] = {lt_grid_axis_of(h, 0), lt_grid_axis_of(h, 1), lt_grid_axis_of(h, 2)};
  int64_t total = 0;
  for (size_t i = 0; i < n && total <= stop; i++) {
    int first[3], last[3];
    total += triangle_cells(axes, tris + 9 * i, first, last);
  }
  return total;
}

lt_status lt__grid_build(const float *tris, size_t n, const lt__grid_config *config, lt__grid *out) {
  lt__grid_config defaults = lt__grid_config_default();
  if (!config) config = &defaults;
  if (out) memset(out, 0, sizeof *out);
  if (!tris || !out || n == 0 || n > INT32_MAX) return LT_ERROR_INVALID_ARGUMENT;
  if (!(config->resolution_factor > 0.0f) || !isfinite(config->resolution_factor) || config->max_cells < 1 ||
      config->max_cells >= INT32_MAX)
    return LT_ERROR_INVALID_ARGUMENT;

  /* The box of all triangles; a coordinate that is not finite has no cell. */
  float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (size_t i = 0; i < n; i++)
    for (int v = 0; v < 3; v++)
      for (int k = 0; k < 3; k++) {
        float x = tris[9 * i + 3 * v + k];
        if (!isfinite(x)) return LT_ERROR_INVALID_ARGUMENT;
        lo[k] = x < lo[k] ? x : lo[k];
        hi[k] = x > hi[k] ? x : hi[k];
      }

  /* Resolution and cell size; the extents in double, since hi - lo may overflow a float. */
  double extent[3];
  int dims[3];
  for (int k = 0; k < 3; k++) extent[k] = (double)hi[k] - (double)lo[k];
  lt__grid_resolution(extent, n, config, dims);
  lt_grid_header *h = &out->header;
  h->lo = lt_make_float4(lo[0], lo[1], lo[2], 0.0f);
  h->hi = lt_make_float4(hi[0], hi[1], hi[2], 0.0f);
  h->size =
      lt_make_float4((float)(extent[0] / dims[0]), (float)(extent[1] / dims[1]), (float)(extent[2] / dims[2]), 0.0f);
  h->dims = lt_make_int4(dims[0], dims[1], dims[2], (lt_i32)product(dims));
  out->cell_count = h->dims.w;

  /* References in all, from the triangles' cell ranges alone: they must fit 32-bit offsets,
   * which is known before a pass over the cells that could take as long as there are refs. */
  int64_t total = lt__grid_reference_count(h, tris, n, INT32_MAX);
  if (total > INT32_MAX) return lt__grid_free(out), LT_ERROR_OUT_OF_MEMORY;

  /* First pass: references per cell. */
  out->cell_begin = calloc((size_t)out->cell_count + 1, sizeof *out->cell_begin);
  if (!out->cell_begin) return lt__grid_free(out), LT_ERROR_OUT_OF_MEMORY;
  scatter(out, tris, n, 0);

  /* Prefix sum: begin[c + 1] becomes where cell c begins, the cursor of the second pass. */
  int64_t run = 0;
  for (int64_t c = 0; c < out->cell_count; c++) {
    lt_i32 count = out->cell_begin[c + 1];
    out->cell_begin[c + 1] = (lt_i32)run;
    run += count;
    out->empty_cells += count == 0;
    out->max_cell_refs = count > out->max_cell_refs ? count : out->max_cell_refs;
  }

  /* Second pass: the references themselves, in triangle order within each cell. */
  out->ref_count = total;
  out->refs = malloc((size_t)(total > 0 ? total : 1) * sizeof *out->refs);
  if (!out->refs) return lt__grid_free(out), LT_ERROR_OUT_OF_MEMORY;
  scatter(out, tris, n, 1);
  out->bytes =
      sizeof(lt_grid_header) + (size_t)(out->cell_count + 1) * sizeof(lt_i32) + (size_t)out->ref_count * sizeof(lt_i32);
  return LT_OK;
}
