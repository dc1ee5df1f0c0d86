/* The registry entry of the uniform grid (Thrane and Simonsen 2005): the irregular grid's
 * COUNT task alone, built through the task pool (builders/irgrid_task.h: count, fill and sort
 * the references of every cell), at the thesis's resolution (builders/host/grid.h), and traced
 * by its own kernel (kernels/grid_trace.h) with the 3D-DDA of Amanatides and Woo
 * (traversal/grid_traverse.h). docs/notes/structures.md walks through its files. */
#include <stdlib.h>

#include "kernels/grid_trace.h"
#include "kernels/native_kernels.h"
#include "runtime/context_internal.h"
#include "runtime/error.h"
#include "runtime/irgrid_host.h"
#include "runtime/kernel_args_host.h"
#include "runtime/registry.h"
#include "runtime/stats_internal.h"
#include "runtime/trace_launch.h"

typedef struct grid_state {
  lt__irgrid grid;
  int live;
  double refs; /* references over all cells */
} grid_state;

/* The trace kernel's arguments from its one list (kernels/grid_trace.h). */
LT__KERNEL_ARGS(trace_args, LT_GRID_TRACE_ARGS, lt_grid_trace_view)

static lt_status create(lt_structure *s, lt_stats *stats) {
  grid_state *g = s->state;
  size_t n = lt_scene_triangle_count(s->scene);
  if (n > (size_t)(INT32_MAX / 16))
    return lt__fail(LT_ERROR_INVALID_ARGUMENT, "the uniform grid takes at most %d triangles", INT32_MAX / 16);
  lt__irgrid_config config = {0};
  config.uniform = s->config.grid_density;
  /* The pool holds the COUNT task; the references are counted exactly on creation. */
  lt__irgrid_room room = {64, 1, 1, 1};
  double start = lt_now_ms(), compile = s->ctx->compile_ms;
  lt_status status = lt__irgrid_create(s->ctx, s->scene, &config, LT_POOL_FULL, &room, &g->grid);
  if (!status) {
    g->live = 1;
    status = lt__irgrid_launch(&g->grid, NULL, 0, 0, NULL, 0, stats);
  }
  lt__stats_add(stats, LT_STAT_BUILD_MS, lt_now_ms() - start - (s->ctx->compile_ms - compile));
  if (status) return status;
  lt_i32 bounds[2];
  status = lt__buffer_read(s->ctx, &g->grid.top_begin, 0, 4, bounds);
  if (!status) status = lt__buffer_read(s->ctx, &g->grid.top_begin, (size_t)g->grid.top_count * 4, 4, bounds + 1);
  g->refs = status ? 0 : bounds[1] - bounds[0];
  return status;
}

static lt_status trace(lt_structure *s, const lt_ray *rays, int count, int flags, lt_hit *hits, lt_stats *stats) {
  grid_state *g = s->state;
  trace_args args = {NULL, NULL, 0, 0, &g->grid.header, &g->grid.top_begin, &g->grid.refs, &g->grid.verts};
  lt_grid_trace_view view;
  lt__trace_call call = {"lt_grid_trace", lt__native_grid_trace_kernel, trace_args_set_any, trace_args_view_any, &args, &args.rays,
                         &args.hits, &args.ray_count, &args.flags, &view};
  return lt__trace_finished(s->ctx, &call, rays, count, flags, hits, stats);
}

/* A grid's nodes are its cells; its references are the cells' triangle numbers. */
static void put_stats(lt_structure *s, lt_stats *stats) {
  grid_state *g = s->state;
  if (!g->live) return;
  double cells = g->grid.top_count, ref_bytes = 4.0 * g->refs;
  double node_bytes = sizeof(lt_grid_header) + 4.0 * (cells + 1);
  lt__stats_put(stats, LT_STAT_REFERENCES, g->refs);
  lt__stats_put(stats, LT_STAT_NODES_BUILT, cells);
  lt__stats_put(stats, LT_STAT_NODES_FULL, cells);
  lt__stats_put(stats, LT_STAT_NODE_BYTES, node_bytes);
  lt__stats_put(stats, LT_STAT_REFERENCE_BYTES, ref_bytes);
  lt__stats_put(stats, LT_STAT_POOL_BYTES, (double)(g->grid.pool.headers.bytes + g->grid.pool.tasks.bytes));
  lt__stats_put(stats, LT_STAT_MEMORY_BYTES, node_bytes + ref_bytes);
}

static void release(lt_structure *s) {
  grid_state *g = s->state;
  if (g->live) lt__irgrid_release(&g->grid);
  g->live = 0;
}

lt__irgrid *lt__uniform_grid_of(lt_structure *s) {
  if (s->cls != &lt__structure_grid) return NULL;
  grid_state *g = s->state;
  return g->live ? &g->grid : NULL;
}

static const char *const kernels[] = {"lt_irg_ondemand", "lt_grid_trace", NULL};

static const lt__param params[] = {
    LT__PARAM_FLOAT("--grid-density", grid_density, 0.001, 1000,
                    "cells along the longest axis per cube root of the triangle count"),
    {0, 0, 0, 0, 0, 0, 0},
};

const lt__structure_class lt__structure_grid = {
    .name = "grid",
    .summary = "uniform grid (Thrane and Simonsen 2005) with a 3D-DDA, built through the task pool",
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
