/* The registry entry of the irregular grid (Perard-Gayot, Kalojanov and Slusallek 2017) built
 * through the task pool (runtime/irgrid_host.c, kernels/irgrid_ondemand.h): fully, or with its
 * top cells materialised on demand while the rays are traced. Without merging it is the
 * two-level grid of Kalojanov et al. (2011) that the paper starts from. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "runtime/context_internal.h"
#include "runtime/error.h"
#include "runtime/irgrid_host.h"
#include "runtime/ondemand_trace.h"
#include "runtime/registry.h"
#include "runtime/stats_internal.h"

typedef struct irgrid_state {
  lt__irgrid_config config;
  lt__irgrid grid;
  int live; /* grid holds a grid */
  lt__irgrid_room room; /* each doubled when it fills up, and the build starts again */
} irgrid_state;

/* The largest pool or heap a retry may ask for. */
#define MAX_POOL (1 << 26)
#define MAX_HEAP (INT32_MAX / 2)

static lt_build_mode mode_of(const lt_structure *s) { return s->config.build; }

/* (Re)creates the grid, and in a full build builds all of it. */
static lt_status start(lt_structure *s, lt_stats *stats) {
  irgrid_state *g = s->state;
  if (g->live) lt__irgrid_release(&g->grid);
  g->live = 0;
  double begin = lt_now_ms(), compile = s->ctx->compile_ms;
  int pool_mode = (int)mode_of(s) - LT_BUILD_FULL; /* LT_POOL_FULL, _REQUESTED, _SPECULATIVE */
  lt_status status = lt__irgrid_create(s->ctx, s->scene, &g->config, pool_mode, &g->room, &g->grid);
  if (!status) g->live = 1;
  if (!status && mode_of(s) == LT_BUILD_FULL) status = lt__irgrid_launch(&g->grid, NULL, 0, 0, NULL, 0, stats);
  if (!status && mode_of(s) == LT_BUILD_FULL && g->config.global_merge) status = lt__irgrid_merge(&g->grid, stats);
  if (!status && mode_of(s) == LT_BUILD_FULL) status = lt__irgrid_compact(&g->grid);
  lt__stats_add(stats, LT_STAT_BUILD_MS, lt_now_ms() - begin - (s->ctx->compile_ms - compile));
  return status;
}

static int may_grow(const irgrid_state *g) {
  return g->room.pool < MAX_POOL && g->room.cells < MAX_HEAP && g->room.refs < MAX_HEAP && g->room.maps < MAX_HEAP;
}

/* Starts again from scratch with twice the room of what filled up. */
static lt_status with_retry(lt_structure *s, lt_stats *stats, lt_status status) {
  irgrid_state *g = s->state;
  while (status == LT_ERROR_CAPACITY && may_grow(g)) {
    int full = g->live ? lt__irgrid_heap_full(&g->grid) : 0;
    int *grow = full == 1 ? &g->room.cells : full == 2 ? &g->room.refs : full == 3 ? &g->room.maps : &g->room.pool;
    static const char *const what[] = {"a pool", "a cell heap", "a reference heap", "a voxel-map heap"};
    if (!s->ctx->quiet) fprintf(stderr, "lazytrace: %s; retrying with %s of %d\n", lt_last_error(), what[full], 2 * *grow);
    *grow *= 2;
    status = start(s, stats);
  }
  return status;
}

static lt_status create(lt_structure *s, lt_stats *stats) {
  irgrid_state *g = s->state;
  const lt_structure_config *c = &s->config;
  size_t n = lt_scene_triangle_count(s->scene);
  if (n > (size_t)MAX_HEAP / 16)
    return lt__fail(LT_ERROR_INVALID_ARGUMENT, "the irregular grid takes at most %d triangles", MAX_HEAP / 16);
  g->config.top_density = c->irgrid_top_density, g->config.cell_density = c->irgrid_cell_density;
  g->config.merge = c->irgrid_merge != LT_IRGRID_MERGE_OFF, g->config.merge_alpha = c->irgrid_merge_alpha;
  g->config.global_merge = c->irgrid_merge == LT_IRGRID_MERGE_ON && c->build == LT_BUILD_FULL;
  g->config.expansion_passes = c->irgrid_expansion_passes - 1;
  g->config.traversal_cost = 1.0f, g->config.intersection_cost = 1.0f; /* Ct = Ci = 1, as in the paper */

  /* Room to start with: one pool slot per top cell; the generators' full builds took up to
   * about 0.7 cells, 6 references and 12.4 sub-map entries per triangle at the default densities
   * (untouched room costs no memory on the native backend). */
  int tiny = lt__structure_tiny_capacities;
  double extent[3] = {1, 1, 1};
  int dims[3];
  lt__irgrid_top_dims(extent, n, g->config.top_density, dims);
  int top = dims[0] * dims[1] * dims[2];
  double per = fmax(1.0, g->config.cell_density / 2.4);
  double cells = 3.0 * per * (double)n + 1024, refs = 8.0 * (double)n + 65536, maps = 16.0 * per * (double)n + 65536;
  g->room.pool = c->pool_capacity > 0 ? c->pool_capacity : tiny ? 4 : top + 1024;
  g->room.cells = tiny ? 4 : cells > MAX_HEAP / 2 ? MAX_HEAP / 2 : (int)cells;
  g->room.refs = tiny ? (int)n : refs > MAX_HEAP / 2 ? MAX_HEAP / 2 : (int)refs;
  g->room.maps = tiny ? 4 : maps > MAX_HEAP / 2 ? MAX_HEAP / 2 : (int)maps;
  return with_retry(s, stats, start(s, stats));
}

static lt_status launch(lt_structure *s, const lt_ray *rays, int count, int flags, lt_hit *hits, int speculate,
                        lt_stats *stats) {
  irgrid_state *g = s->state;
  return lt__irgrid_launch(&g->grid, rays, count, flags, hits, speculate, stats);
}

static int may_grow_structure(const lt_structure *s) { return may_grow(s->state); }

/* A full build's grid is traced by the plain kernel; on demand, lt__ondemand_trace. */
static lt_status trace(lt_structure *s, const lt_ray *rays, int count, int flags, lt_hit *hits, lt_stats *stats) {
  static const lt__ondemand_ops ops = {launch, may_grow_structure, with_retry, NULL};
  irgrid_state *g = s->state;
  if (mode_of(s) == LT_BUILD_FULL) return lt__irgrid_trace_finished(&g->grid, rays, count, flags, hits, stats);
  return lt__ondemand_trace(s, &ops, rays, count, flags, hits, stats);
}

static void put_stats(lt_structure *s, lt_stats *stats) {
  irgrid_state *g = s->state;
  if (!g->live) return;
  const double *t = g->grid.totals;
  double cell_bytes, ref_bytes, map_bytes, pool_bytes;
  double memory = lt__irgrid_bytes(&g->grid, &cell_bytes, &ref_bytes, &map_bytes, &pool_bytes);
  /* Cells and references live: those the top cells made, less what the global passes merged. */
  double cells = t[LT_IRG_STAT_CELLS] - t[LT_IRG_STAT_GLOBAL_MERGES];
  lt__stats_put(stats, LT_STAT_REFERENCES, t[LT_IRG_STAT_CELL_REFS] - t[LT_IRG_STAT_REFS_SAVED]);
  lt__stats_put(stats, LT_STAT_NODES_BUILT, cells);
  if (mode_of(s) == LT_BUILD_FULL) lt__stats_put(stats, LT_STAT_NODES_FULL, cells);
  lt__stats_put(stats, LT_STAT_CELLS_TOP, g->grid.top_count);
  lt__stats_put(stats, LT_STAT_CELLS_TOP_BUILT, t[LT_IRG_STAT_TOP_BUILT]);
  lt__stats_put(stats, LT_STAT_CELLS_INITIAL, t[LT_IRG_STAT_INITIAL]);
  lt__stats_put(stats, LT_STAT_CELLS_FINAL, cells);
  lt__stats_put(stats, LT_STAT_CELLS_MERGES, t[LT_IRG_STAT_MERGES] + t[LT_IRG_STAT_GLOBAL_MERGES]);
  lt__stats_put(stats, LT_STAT_CELLS_EXPANSIONS, t[LT_IRG_STAT_EXPANSIONS]);
  lt__stats_put(stats, LT_STAT_MEMORY_BYTES, memory);
  lt__stats_put(stats, LT_STAT_NODE_BYTES, cell_bytes);
  lt__stats_put(stats, LT_STAT_REFERENCE_BYTES, ref_bytes);
  lt__stats_put(stats, LT_STAT_MAP_BYTES, map_bytes);
  lt__stats_put(stats, LT_STAT_POOL_BYTES, pool_bytes);
}

static void release(lt_structure *s) {
  irgrid_state *g = s->state;
  if (g->live) lt__irgrid_release(&g->grid);
  g->live = 0;
}

lt__irgrid *lt__irgrid_of(lt_structure *s) {
  if (s->cls != &lt__structure_irgrid) return NULL;
  irgrid_state *g = s->state;
  return g->live ? &g->grid : NULL;
}

static const char *const kernels[] = {"lt_irg_ondemand", "lt_irg_trace", NULL};

static const lt__param params[] = {
    LT__PARAM_FLOAT("--top-density", irgrid_top_density, 0.0001, 100, "top-level cells per triangle (lambda1)"),
    LT__PARAM_FLOAT("--cell-density", irgrid_cell_density, 0.001, 1000,
                    "sub-voxels per reference of a top cell (lambda2); a top cell is cut into 8^level"),
    LT__PARAM_CHOICE("--merge", irgrid_merge, "on|off|top",
                     "SAH merge passes: across the grid in a full build (within top cells on demand), none (the "
                     "two-level grid), or within top cells only"),
    LT__PARAM_FLOAT("--merge-alpha", irgrid_merge_alpha, 0.001, 1,
                    "merging stops when a pass merges fewer than 1 - alpha of the cells"),
    LT__PARAM_CHOICE("--expansion-passes", irgrid_expansion_passes, "0|1|2|3|4|5|6|7|8",
                     "passes that grow cells over neighbours whose triangles they hold"),
    {0, 0, 0, 0, 0, 0, 0},
};

const lt__structure_class lt__structure_irgrid = {
    .name = "irgrid",
    .summary = "irregular grid (Perard-Gayot et al. 2017), built through the task pool in full or top cells on demand",
    .params = params,
    .modes = 1u << LT_BUILD_FULL | 1u << LT_BUILD_REQUESTED | 1u << LT_BUILD_SPECULATIVE,
    .defaults = {.kind = LT_STRUCTURE_IRGRID, .build = LT_BUILD_SPECULATIVE, .max_leaf_size = 16, .sah_bins = 32,
                 .traversal_cost = 1.0f, .pool_capacity = 0, .intersect = LT_INTERSECT_WATERTIGHT, .grid_density = 3.0f,
                 .kd_traversal = LT_KD_TRAVERSAL_STACK, .kd_split = LT_KD_SPLIT_BINNED, .kd_clip = LT_KD_CLIP_OFF,
                 .irgrid_top_density = 0.12f, .irgrid_cell_density = 2.4f, .irgrid_merge = LT_IRGRID_MERGE_ON,
                 .irgrid_merge_alpha = 0.995f, .irgrid_expansion_passes = LT_IRGRID_PASSES(3)},
    .state_size = sizeof(irgrid_state),
    .create = create,
    .trace = trace,
    .put_stats = put_stats,
    .release = release,
    .kernels = kernels,
};
