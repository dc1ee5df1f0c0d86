/* The registry entry of the uniform grid (Thrane and Simonsen 2005): built on the host in full
 * (builders/host/grid.c), traced by its own kernel (kernels/grid_trace.h) with the 3D-DDA of
 * Amanatides and Woo (traversal/grid_traverse.h). The first structure added as a plug-in:
 * docs/notes/structures.md walks through its files. */
#include <stdlib.h>

#include "builders/host/grid.h"
#include "kernels/grid_trace.h"
#include "kernels/native_kernels.h"
#include "runtime/context_internal.h"
#include "runtime/error.h"
#include "runtime/kernel_args_host.h"
#include "runtime/registry.h"
#include "runtime/stats_internal.h"
#include "runtime/trace_launch.h"

typedef struct grid_state {
  lt__grid grid;
  lt__buffer header, cells, refs, verts; /* on native, the arrays themselves */
} grid_state;

/* The trace kernel's arguments from its one list (kernels/grid_trace.h). */
LT__KERNEL_ARGS(trace_args, LT_GRID_TRACE_ARGS, lt_grid_trace_view)

static lt_status create(lt_structure *s, lt_stats *stats) {
  grid_state *g = s->state;
  lt_context *ctx = s->ctx;
  lt__grid_config config = lt__grid_config_default();
  config.resolution_factor = s->config.grid_density;
  size_t n = lt_scene_triangle_count(s->scene);
  const float *tris = lt_scene_triangles(s->scene);
  double start = lt_now_ms();
  lt_status status = lt__grid_build(tris, n, &config, &g->grid);
  if (status)
    return lt__fail(status, "building a uniform grid over %zu triangles (density %g): %s", n,
                    (double)config.resolution_factor, lt_status_str(status));

  /* The grid's arrays and the scene's vertices on the device (in place on native). */
  status = lt__buffer_wrap(ctx, &g->header, &g->grid.header, sizeof g->grid.header);
  if (!status)
    status = lt__buffer_wrap(ctx, &g->cells, g->grid.cell_begin, (size_t)(g->grid.cell_count + 1) * sizeof(lt_i32));
  if (!status)
    status = lt__buffer_wrap(ctx, &g->refs, g->grid.refs, (size_t)(g->grid.ref_count ? g->grid.ref_count : 1) * sizeof(lt_i32));
  if (!status) status = lt__buffer_wrap(ctx, &g->verts, tris, n * 9 * sizeof(float));
  lt__stats_add(stats, LT_STAT_BUILD_MS, lt_now_ms() - start);
  /* Primitive operations of the build: each reference is placed twice (counted, then filled). */
  lt__stats_add(stats, LT_STAT_SORT_OPS, 2.0 * (double)g->grid.ref_count);
  return status;
}

static lt_status trace(lt_structure *s, const lt_ray *rays, int count, int flags, lt_hit *hits, lt_stats *stats) {
  grid_state *g = s->state;
  trace_args args = {NULL, NULL, 0, 0, &g->header, &g->cells, &g->refs, &g->verts};
  lt_grid_trace_view view;
  lt__trace_call call = {"lt_grid_trace", lt__native_grid_trace_kernel, trace_args_set_any, trace_args_view_any, &args, &args.rays,
                         &args.hits, &args.ray_count, &args.flags, &view};
  return lt__trace_finished(s->ctx, &call, rays, count, flags, hits, stats);
}

/* A grid's nodes are its cells; its references are the cells' triangle numbers. */
static void put_stats(lt_structure *s, lt_stats *stats) {
  grid_state *g = s->state;
  double ref_bytes = (double)g->grid.ref_count * sizeof(lt_i32);
  double node_bytes = (double)g->grid.bytes - ref_bytes;
  lt__stats_put(stats, LT_STAT_REFERENCES, (double)g->grid.ref_count);
  lt__stats_put(stats, LT_STAT_NODES_BUILT, (double)g->grid.cell_count);
  lt__stats_put(stats, LT_STAT_NODES_FULL, (double)g->grid.cell_count);
  lt__stats_put(stats, LT_STAT_NODE_BYTES, node_bytes);
  lt__stats_put(stats, LT_STAT_REFERENCE_BYTES, ref_bytes);
  lt__stats_put(stats, LT_STAT_POOL_BYTES, 0);
  lt__stats_put(stats, LT_STAT_MEMORY_BYTES, (double)g->grid.bytes);
}

static void release(lt_structure *s) {
  grid_state *g = s->state;
  lt__buffer_release(&g->header);
  lt__buffer_release(&g->cells);
  lt__buffer_release(&g->refs);
  lt__buffer_release(&g->verts);
  lt__grid_free(&g->grid);
}

static const char *const kernels[] = {"lt_grid_trace", NULL};

static const lt__param params[] = {
    LT__PARAM_FLOAT("--grid-density", grid_density, 0.001, 1000,
                    "cells along the longest axis per cube root of the triangle count"),
    {0, 0, 0, 0, 0, 0, 0},
};

const lt__structure_class lt__structure_grid = {
    .name = "grid",
    .summary = "uniform grid (Thrane and Simonsen 2005) with a 3D-DDA, built on the host",
    .params = params,
    .modes = 1u << LT_BUILD_FULL,
    .defaults = {.kind = LT_STRUCTURE_GRID, .build = LT_BUILD_FULL, .max_leaf_size = 16, .sah_bins = 32,
                 .traversal_cost = 1.0f, .pool_capacity = 0, .intersect = LT_INTERSECT_WATERTIGHT, .grid_density = 3.0f},
    .state_size = sizeof(grid_state),
    .create = create,
    .trace = trace,
    .put_stats = put_stats,
    .release = release,
    .kernels = kernels,
};
