/* The host half of the irregular grid (see irgrid_host.h). */
#include "runtime/irgrid_host.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "builders/host/grid.h"
#include "kernels/irgrid_ondemand.h"
#include "kernels/irgrid_trace.h"
#include "kernels/native_kernels.h"
#include "runtime/error.h"
#include "runtime/kernel_args_host.h"
#include "runtime/persistent_launch.h"
#include "runtime/stats_internal.h"
#include "runtime/trace_launch.h"
#include "runtime/triangle_boxes.h"

/* The most top cells: the COUNT task's phase ends walk them on one work-item. */
#define MAX_TOP_CELLS (1 << 22)

void lt__irgrid_top_dims(const double extent[3], size_t n, float density, int dims[3]) {
  double longest = fmax(extent[0], fmax(extent[1], extent[2]));
  /* Flat scenes: an axis far thinner than the longest counts as 1/64 of it for the volume. */
  double volume = 1.0;
  for (int k = 0; k < 3; k++) volume *= fmax(extent[k], longest / 64.0);
  double per_unit = longest > 0.0 ? cbrt((double)density * (double)n / volume) : 0.0;
  int max_axis = LT_GRID_MAX_AXIS_CELLS >> LT_IRG_MAX_LEVEL;
  for (int k = 0; k < 3; k++) {
    double d = floor(extent[k] * per_unit + 0.5);
    dims[k] = d < 1.0 ? 1 : d > max_axis ? max_axis : (int)d;
  }
  while ((double)dims[0] * dims[1] * dims[2] > MAX_TOP_CELLS) {
    int k = dims[0] >= dims[1] && dims[0] >= dims[2] ? 0 : dims[1] >= dims[2] ? 1 : 2;
    dims[k] = dims[k] * 7 / 8 > 1 ? dims[k] * 7 / 8 : 1;
  }
}

static lt_status launch(lt__irgrid *g, lt__buffer *rays, lt__buffer *hits, int count, int flags, int speculate,
                        int setup);
static lt_status read_counters(lt__irgrid *g, lt_stats *stats);

lt_status lt__irgrid_create(lt_context *ctx, const lt_scene *scene, const lt__irgrid_config *config, int mode,
                            const lt__irgrid_room *room, lt__irgrid *g) {
  memset(g, 0, sizeof *g);
  g->ctx = ctx;
  g->config = *config;
  g->count = (int)lt_scene_triangle_count(scene);
  size_t n = (size_t)g->count;

  lt_box bounds;
  lt_status status = lt__buffer_create(ctx, &g->prim_boxes, n * 8 * sizeof(float), NULL, LT_BUFFER_UNINIT);
  if (!status) {
    float *boxes = lt__buffer_begin_write(ctx, &g->prim_boxes);
    status = boxes ? lt__triangle_boxes(scene, boxes, &bounds) : lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory for %zu boxes", n);
    lt_status uploaded = boxes ? lt__buffer_end_write(ctx, &g->prim_boxes, boxes) : LT_OK;
    if (!status) status = uploaded;
  }
  if (status) {
    lt__irgrid_release(g);
    return status;
  }

  /* The top grid, and the fine grid it is refined into. Extents in double: hi - lo may
   * overflow a float. */
  double extent[3];
  for (int k = 0; k < 3; k++) extent[k] = (double)bounds.hi[k] - (double)bounds.lo[k];
  if (config->uniform > 0) {
    lt__grid_config uniform = lt__grid_config_default();
    uniform.resolution_factor = config->uniform;
    lt__grid_resolution(extent, n, &uniform, g->top_dims);
    g->shift = 0;
  } else {
    lt__irgrid_top_dims(extent, n, config->top_density, g->top_dims);
    g->shift = LT_IRG_MAX_LEVEL;
  }
  g->top_count = g->top_dims[0] * g->top_dims[1] * g->top_dims[2];
  int fine[3];
  for (int k = 0; k < 3; k++) fine[k] = g->top_dims[k] << g->shift;
  g->fine.lo = lt_make_float4(bounds.lo[0], bounds.lo[1], bounds.lo[2], 0.0f);
  g->fine.hi = lt_make_float4(bounds.hi[0], bounds.hi[1], bounds.hi[2], 0.0f);
  g->fine.size = lt_make_float4((float)(extent[0] / fine[0]), (float)(extent[1] / fine[1]), (float)(extent[2] / fine[2]), 0.0f);
  g->fine.dims = lt_make_int4(fine[0], fine[1], fine[2], fine[0] * fine[1] * fine[2]);

  /* A uniform grid's references are known here, exactly: its room never needs a retry. */
  int refs = room->refs;
  if (config->uniform > 0) {
    int64_t total = lt__grid_reference_count(&g->fine, lt_scene_triangles(scene), n, INT32_MAX / 2);
    if (total > INT32_MAX / 2) {
      lt__irgrid_release(g);
      return lt__fail(LT_ERROR_OUT_OF_MEMORY, "a uniform grid of %d cells would hold %lld references: too many",
                      g->top_count, (long long)total);
    }
    refs = (int)total + 1;
  }
  lt_pool_config pool = {room->pool, 0, 0, 0, 0, 0};
  status = lt__pool_create(ctx, &pool, mode, &g->pool);
  if (!status) status = lt__heap_create(ctx, &g->cell_heap, room->cells);
  if (!status) status = lt__heap_create(ctx, &g->ref_heap, refs);
  if (!status) status = lt__heap_create(ctx, &g->map_heap, room->maps);
  if (!status) status = lt__buffer_wrap(ctx, &g->verts, lt_scene_triangles(scene), n * 9 * sizeof(float));
  if (!status) status = lt__buffer_create(ctx, &g->header, sizeof g->fine, &g->fine, 0);
  size_t top_map = config->uniform > 0 ? 1 : (size_t)g->top_count; /* a uniform grid has no voxel map */
  if (!status) status = lt__buffer_create(ctx, &g->top_map, top_map * 4, NULL, LT_IRG_COUNTING);
  if (!status) status = lt__buffer_create(ctx, &g->top_begin, (size_t)(g->top_count + 1) * 4, NULL, 0);
  if (!status) status = lt__buffer_create(ctx, &g->top_fill, (size_t)g->top_count * 4, NULL, 0);
  if (!status) status = lt__buffer_create(ctx, &g->sub_maps, (size_t)room->maps * 4, NULL, LT_BUFFER_UNINIT);
  if (!status) status = lt__buffer_create(ctx, &g->cells, (size_t)room->cells * sizeof(lt_irg_cell), NULL, LT_BUFFER_UNINIT);
  if (!status) status = lt__buffer_create(ctx, &g->refs, (size_t)refs * 4, NULL, LT_BUFFER_UNINIT);
  if (!status)
    status = lt__buffer_create(ctx, &g->scratch, (size_t)ctx->work_groups * LT_IRG_SCRATCH * 4, NULL, LT_BUFFER_UNINIT);
  if (!status)
    status = lt__buffer_create(ctx, &g->counters, (size_t)ctx->work_groups * LT_IRG_STAT_COUNT * 4, NULL, 0);
  if (!status) status = lt__buffer_create(ctx, &g->control, LT_IRG_CONTROL_WORDS * 4, NULL, 0);
  /* The global passes' scratch: only a full build with global merging uses it. */
  size_t scratch_cells = config->global_merge && mode == LT_POOL_FULL ? (size_t)room->cells : 1;
  if (!status) status = lt__buffer_create(ctx, &g->cell_scratch, scratch_cells * 12, NULL, LT_BUFFER_UNINIT);

  /* The COUNT task, inserted on the device. */
  lt__buffer none;
  memset(&none, 0, sizeof none);
  if (!status) status = lt__buffer_create(ctx, &none, 16, NULL, 0);
  if (!status) status = launch(g, &none, &none, 0, 0, 0, 1);
  lt__buffer_release(&none);
  if (!status) status = lt__pool_end_launch(&g->pool, NULL);
  if (!status) status = read_counters(g, NULL);
  if (status) lt__irgrid_release(g);
  return status;
}

void lt__irgrid_release(lt__irgrid *g) {
  lt__pool_release(&g->pool);
  lt__heap_release(&g->cell_heap);
  lt__heap_release(&g->ref_heap);
  lt__heap_release(&g->map_heap);
  lt__buffer *buffers[] = {&g->verts, &g->prim_boxes, &g->header, &g->top_map, &g->top_begin, &g->top_fill,
                           &g->sub_maps, &g->cells, &g->refs, &g->scratch, &g->counters, &g->control,
                           &g->cell_scratch};
  for (size_t i = 0; i < sizeof buffers / sizeof buffers[0]; i++) lt__buffer_release(buffers[i]);
}

/* The kernels' arguments from their lists (kernels/irgrid_ondemand.h, kernels/irgrid_trace.h). */
LT__KERNEL_ARGS(irg_args, LT_IRG_ARGS, lt_irg_args)
LT__KERNEL_ARGS(irg_trace_args, LT_IRG_TRACE_ARGS, lt_irg_trace_view)

static lt_status launch_kernel(lt__irgrid *g, const lt__persistent_kernel *kernel, lt__buffer *rays, lt__buffer *hits,
                               int count, int flags, int speculate, int setup) {
  irg_args args;
  LT__POOL_HOST_ARGS(&args, &g->pool);
  LT__HEAP_HOST_ARGS(&args, cell_heap, &g->cell_heap);
  LT__HEAP_HOST_ARGS(&args, ref_heap, &g->ref_heap);
  LT__HEAP_HOST_ARGS(&args, map_heap, &g->map_heap);
  args.verts = &g->verts, args.prim_boxes = &g->prim_boxes, args.header = &g->header, args.top_map = &g->top_map;
  args.top_begin = &g->top_begin, args.top_fill = &g->top_fill, args.sub_maps = &g->sub_maps, args.cells = &g->cells;
  args.refs = &g->refs, args.scratch = &g->scratch, args.counters = &g->counters;
  args.control = &g->control, args.cell_scratch = &g->cell_scratch, args.global_merge = g->config.global_merge;
  args.fine_dims = g->fine.dims, args.prim_count = g->count, args.top_count = g->top_count;
  args.shift = g->shift, args.uniform = g->config.uniform > 0, args.merge = g->config.merge, args.expansion_passes = g->config.expansion_passes;
  args.cell_density = g->config.cell_density, args.merge_alpha = g->config.merge_alpha;
  args.traversal_cost = g->config.traversal_cost, args.intersection_cost = g->config.intersection_cost;
  args.rays = rays, args.hits = hits, args.ray_count = count, args.flags = flags;
  args.max_idle_polls = g->pool.config.max_idle_polls, args.speculate = speculate;
  lt_irg_args view;
  return lt__persistent_launch(g->ctx, kernel, &args, &view, setup, &g->pool.control, g->pool.config.max_stall_seconds);
}

/* The kernel that builds top cells and traces (kernels/irgrid_ondemand.h). */
static lt_status launch(lt__irgrid *g, lt__buffer *rays, lt__buffer *hits, int count, int flags, int speculate,
                        int setup) {
  static const lt__persistent_kernel kernel = {"lt_irg_ondemand", lt__native_irgrid_ondemand_kernel, irg_args_set_any,
                                               irg_args_view_any};
  return launch_kernel(g, &kernel, rays, hits, count, flags, speculate, setup);
}

lt_status lt__irgrid_merge(lt__irgrid *g, lt_stats *stats) {
  static const lt__persistent_kernel kernel = {"lt_irg_merge", lt__native_irgrid_merge_kernel, irg_args_set_any,
                                               irg_args_view_any};
  lt__buffer none;
  memset(&none, 0, sizeof none);
  lt_status status = lt__buffer_create(g->ctx, &none, 16, NULL, 0);
  if (!status) status = launch_kernel(g, &kernel, &none, &none, 0, 0, 0, 1);
  if (!status) status = lt__pool_end_launch(&g->pool, NULL);
  if (!status) status = lt__pool_begin_launch(&g->pool);
  if (!status) status = launch_kernel(g, &kernel, &none, &none, 0, 0, 0, 0);
  if (!status) status = lt__pool_end_launch(&g->pool, stats);
  if (!status) status = read_counters(g, stats);
  lt__buffer_release(&none);
  return status;
}

/* Adds the launch's counters, summed over the work-groups, to stats and the grid's totals, and
 * clears them for the next launch. */
static lt_status read_counters(lt__irgrid *g, lt_stats *stats) {
  static const int stat_of[LT_IRG_STAT_COUNT] = {
#define LT_IRG_STAT_TARGET(id, stat) stat,
      LT_IRG_STAT_LIST(LT_IRG_STAT_TARGET)
#undef LT_IRG_STAT_TARGET
  };
  lt_context *ctx = g->ctx;
  size_t words = (size_t)ctx->work_groups * LT_IRG_STAT_COUNT;
  lt_u32 *counters = malloc(words * sizeof *counters);
  if (!counters) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory reading counters");
  lt_status status = lt__buffer_read(ctx, &g->counters, 0, words * 4, counters);
  double sum[LT_IRG_STAT_COUNT] = {0};
  for (size_t w = 0; !status && w < words; w++) sum[w % LT_IRG_STAT_COUNT] += counters[w];
  free(counters);
  if (status) return status;
  for (int k = 0; k < LT_IRG_STAT_COUNT; k++) {
    g->totals[k] += sum[k];
    if (stat_of[k] != LT_STAT_NONE) lt__stats_add(stats, (lt_stat_id)stat_of[k], sum[k]);
  }
  return lt__buffer_fill(ctx, &g->counters, 0);
}

lt_status lt__irgrid_launch(lt__irgrid *g, const lt_ray *rays, int count, int flags, lt_hit *hits, int speculate,
                            lt_stats *stats) {
  lt_context *ctx = g->ctx;
  lt__buffer ray_buf, hit_buf;
  lt_status status = lt__batch_buffers_begin(ctx, &ray_buf, &hit_buf, rays, count, hits);
  if (status) return status;
  status = lt__pool_begin_launch(&g->pool);
  if (!status) status = launch(g, &ray_buf, &hit_buf, count, flags, speculate, 0);
  if (!status) status = lt__pool_end_launch(&g->pool, stats);
  status = lt__batch_buffers_end(ctx, &ray_buf, &hit_buf, hits, count, status);
  if (!status) status = read_counters(g, stats);
  return status;
}

lt_status lt__irgrid_trace_finished(lt__irgrid *g, const lt_ray *rays, int count, int flags, lt_hit *hits,
                                    lt_stats *stats) {
  irg_trace_args args = {NULL, NULL, 0, 0, &g->header, &g->top_map, &g->sub_maps, &g->cells, &g->refs, &g->verts,
                         g->fine.dims, g->shift, g->narrow};
  lt_irg_trace_view view;
  lt__trace_call call = {"lt_irg_trace", lt__native_irgrid_trace_kernel, irg_trace_args_set_any, irg_trace_args_view_any,
                         &args, &args.rays, &args.hits, &args.ray_count, &args.flags, &view};
  return lt__trace_finished(g->ctx, &call, rays, count, flags, hits, stats);
}

int lt__irgrid_heap_full(lt__irgrid *g) {
  const lt__heap *heaps[] = {&g->cell_heap, &g->ref_heap, &g->map_heap};
  for (int i = 0; i < 3; i++) {
    int used, exhausted = 0;
    lt__heap_used(g->ctx, heaps[i], &used, &exhausted);
    if (exhausted) return i + 1;
  }
  return 0;
}

double lt__irgrid_bytes(lt__irgrid *g, double *cell_bytes, double *reference_bytes, double *map_bytes,
                        double *pool_bytes) {
  int cells = 0, refs = 0, maps = 0, exhausted;
  lt__heap_used(g->ctx, &g->cell_heap, &cells, &exhausted);
  lt__heap_used(g->ctx, &g->ref_heap, &refs, &exhausted);
  lt__heap_used(g->ctx, &g->map_heap, &maps, &exhausted);
  *cell_bytes = (double)cells * (double)(g->narrow ? sizeof(lt_irg_cell16) : sizeof(lt_irg_cell));
  *reference_bytes = (double)refs * 4.0 + (double)g->top_begin.bytes; /* with where the top lists begin */
  *map_bytes = (double)maps * 4.0 + (double)g->top_count * 4.0 + sizeof(lt_grid_header);
  *pool_bytes = (double)(g->pool.headers.bytes + g->pool.tasks.bytes + g->pool.empty_cache.bytes +
                         g->pool.priority_cache.bytes + g->pool.control.bytes);
  return *cell_bytes + *reference_bytes + *map_bytes + *pool_bytes + (double)g->prim_boxes.bytes +
         (double)g->top_fill.bytes + (double)g->scratch.bytes + (double)g->cell_scratch.bytes;
}

void lt__irgrid_arrays_free(lt__irgrid_arrays *a) {
  free(a->top_map), free(a->top_begin), free(a->sub_maps), free(a->refs), free(a->cells);
  memset(a, 0, sizeof *a);
}

/* A compacted grid's 16-byte cells and packed lists into out->cells and out->refs (which holds
 * the packed words on entry), as lt_irg_cell and lists of 32-bit triangle numbers laid end to end:
 * each packed list decoded once, where a cell first reads it; the cells that share it point at
 * that copy. */
static lt_status read_cells16(lt__irgrid *g, lt__irgrid_arrays *out) {
  size_t size = (size_t)out->ref_count * 4;
  lt_irg_cell16 *narrow = malloc(((size_t)out->cell_count + 1) * sizeof *narrow);
  lt_u8 *packed = calloc(size + 4, 1);                /* the zeros after it end any varint begun inside */
  lt_i32 *first = malloc((size + 1) * sizeof *first); /* by byte offset: the cell that first read the list there */
  size_t room = size + 1, fill = 0;
  lt_i32 *refs = malloc(room * sizeof *refs);
  if (!narrow || !packed || !first || !refs) {
    free(narrow), free(packed), free(first), free(refs);
    return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory copying an irregular grid");
  }
  memcpy(packed, out->refs, size);
  for (size_t b = 0; b <= size; b++) first[b] = -1;
  lt_status status = lt__buffer_read(g->ctx, &g->cells, 0, (size_t)out->cell_count * sizeof *narrow, narrow);
  for (int i = 0; !status && i < out->cell_count; i++) {
    lt_irg_cell cell = lt_irg_cell_get(NULL, narrow, i);
    if (cell.begin < 0 || (size_t)cell.begin >= size) {
      status = lt__fail(LT_ERROR_INVALID_ARGUMENT, "compacted cell %d's list is out of bounds", i);
      break;
    }
    lt_i32 *earlier = &first[cell.begin];
    if (*earlier >= 0) {
      cell.begin = out->cells[*earlier].begin, cell.end = out->cells[*earlier].end;
      out->cells[i] = cell;
      continue;
    }
    /* A list read for the first time: decoded through the traversal's own reader. */
    lt_irg_list list = lt_irg_list_open((const lt_i32 *)packed, 1, &cell);
    if (list.left < 0 || list.left > LT_IRG_PACK_MAX) {
      status = lt__fail(LT_ERROR_INVALID_ARGUMENT, "compacted cell %d's list has a bad count", i);
      break;
    }
    if (fill + (size_t)list.left > room) {
      room = 2 * (fill + (size_t)list.left);
      lt_i32 *more = realloc(refs, room * sizeof *refs);
      if (!more) {
        status = lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory copying an irregular grid");
        break;
      }
      refs = more;
    }
    cell.begin = cell.end = (lt_i32)fill;
    while (list.left > 0 && (size_t)list.at <= size)
      refs[cell.end++] = lt_irg_list_next((const lt_i32 *)packed, 1, &list);
    if ((size_t)list.at > size)
      status = lt__fail(LT_ERROR_INVALID_ARGUMENT, "compacted cell %d's list runs past the references", i);
    fill = (size_t)cell.end;
    out->cells[i] = cell, *earlier = i;
  }
  free(narrow), free(packed), free(first);
  if (status) {
    free(refs);
    return status;
  }
  free(out->refs);
  out->refs = refs, out->ref_count = (int)fill;
  return LT_OK;
}

/* A compacted grid's packed sub-map entries (3 bytes each, out->sub_maps holding the words on
 * entry) as lt_i32; the byte after the last may make one more entry, which nothing names. */
static lt_status read_map24(lt__irgrid_arrays *out) {
  int count = (4 * out->sub_count - 1) / 3;
  lt_i32 *map = malloc(((size_t)count + 1) * sizeof *map);
  if (!map) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory copying an irregular grid");
  for (int i = 0; i < count; i++) map[i] = lt_irg_map_entry(out->sub_maps, 1, i);
  free(out->sub_maps);
  out->sub_maps = map, out->sub_count = count;
  return LT_OK;
}

lt_status lt__irgrid_read(lt__irgrid *g, lt__irgrid_arrays *out) {
  memset(out, 0, sizeof *out);
  int exhausted;
  lt_status status = lt__heap_used(g->ctx, &g->map_heap, &out->sub_count, &exhausted);
  if (!status) status = lt__heap_used(g->ctx, &g->cell_heap, &out->cell_count, &exhausted);
  if (!status) status = lt__heap_used(g->ctx, &g->ref_heap, &out->ref_count, &exhausted);
  if (status) return status;
  size_t top = (size_t)g->top_count;
  out->top_map = malloc(top * 4);
  out->top_begin = calloc(top + 1, 4);
  out->sub_maps = malloc((size_t)(out->sub_count + 1) * 4);
  out->refs = malloc((size_t)(out->ref_count + 1) * 4);
  out->cells = malloc((size_t)(out->cell_count + 1) * sizeof(lt_irg_cell));
  if (!out->top_map || !out->top_begin || !out->sub_maps || !out->refs || !out->cells) {
    lt__irgrid_arrays_free(out);
    return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory copying an irregular grid");
  }
  status = lt__buffer_read(g->ctx, &g->top_map, 0, g->top_map.bytes < top * 4 ? g->top_map.bytes : top * 4, out->top_map);
  if (!status && !g->compacted) status = lt__buffer_read(g->ctx, &g->top_begin, 0, (top + 1) * 4, out->top_begin);
  if (!status) status = lt__buffer_read(g->ctx, &g->sub_maps, 0, (size_t)out->sub_count * 4, out->sub_maps);
  if (!status) status = lt__buffer_read(g->ctx, &g->refs, 0, (size_t)out->ref_count * 4, out->refs);
  if (!status && !g->narrow)
    status = lt__buffer_read(g->ctx, &g->cells, 0, (size_t)out->cell_count * sizeof(lt_irg_cell), out->cells);
  if (!status && g->narrow) status = read_cells16(g, out);
  if (!status && g->narrow) status = read_map24(out);
  if (status) lt__irgrid_arrays_free(out);
  return status;
}
