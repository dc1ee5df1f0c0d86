/* The registry entry of the SAH BVH built through the task pool (runtime/bvh_ondemand_host.c,
 * kernels/bvh_ondemand.h): fully, or on demand while the rays are traced. */
#include <stdint.h>
#include <stdlib.h>

#include "kernels/bvh_trace.h"
#include "kernels/native_kernels.h"
#include "runtime/bvh_ondemand_host.h"
#include "runtime/kernel_args_host.h"
#include "runtime/ondemand_trace.h"
#include "runtime/trace_launch.h"
#include "runtime/context_internal.h"
#include "runtime/error.h"
#include "runtime/registry.h"
#include "runtime/stats_internal.h"

typedef struct bvh_state {
  lt__sah_config sah;
  lt__ondemand od;
  int live;          /* od holds a tree */
  int pool_capacity; /* doubled when the pool fills up */
  int node_capacity; /* doubled when the node heap fills up (a binary tree of n leaves has
                        fewer than n + 2 nodes with the super-root, so it never has so far) */
} bvh_state;

/* The largest pool a retry may ask for. */
#define MAX_POOL (1 << 26)

/* Pool capacity to start from; a full pool doubles it and starts again (never a silent drop). */
static int initial_pool_capacity(size_t triangles) {
  size_t c = triangles / 8;
  return c < 4096 ? 4096 : c > (1u << 22) ? (1 << 22) : (int)c;
}

static lt_build_mode mode_of(const lt_structure *s) { return s->config.build; }

/* (Re)creates the tree, and in a full build builds all of it. */
static lt_status start(lt_structure *s, lt_stats *stats) {
  bvh_state *b = s->state;
  if (b->live) lt__ondemand_release(&b->od);
  b->live = 0;

  /* Setting up (packing triangles and their boxes, allocating) is build time in every mode;
   * the kernel warm-up inside it is compile time and is taken out. */
  double begin = lt_now_ms(), compile = s->ctx->compile_ms;
  int pool_mode = (int)mode_of(s) - LT_BUILD_FULL; /* LT_POOL_FULL, _REQUESTED, _SPECULATIVE */
  int morton_above = s->config.bvh_top == LT_BVH_TOP_MORTON ? s->config.bvh_morton_above : 0;
  lt_status status = lt__ondemand_create(s->ctx, s->scene, &b->sah, pool_mode, b->pool_capacity, b->node_capacity,
                                         morton_above, &b->od);
  if (!status) b->live = 1;
  /* The Morton top's sort (the only sorting so far: the set-up launch only spawns the root). */
  if (!status) lt__stats_add(stats, LT_STAT_SORT_OPS, b->od.sort_ops);
  if (!status && mode_of(s) == LT_BUILD_FULL) status = lt__ondemand_launch(&b->od, NULL, 0, 0, NULL, 0, stats);
  lt__stats_add(stats, LT_STAT_BUILD_MS, lt_now_ms() - begin - (s->ctx->compile_ms - compile));
  return status;
}

/* Whether the pool and the node heap may still grow. */
static int may_grow(const bvh_state *b) { return b->pool_capacity < MAX_POOL && b->node_capacity < INT32_MAX / 2; }

/* Starts again from scratch with twice the room, while the pool or the node heap fills up. */
static lt_status with_retry(lt_structure *s, lt_stats *stats, lt_status status) {
  bvh_state *b = s->state;
  while (status == LT_ERROR_CAPACITY && may_grow(b)) {
    int heap_full = b->live && lt__ondemand_heap_full(&b->od);
    if (!s->ctx->quiet)
      fprintf(stderr, "lazytrace: %s; retrying with %s of %d\n", lt_last_error(), heap_full ? "a node heap" : "a pool",
              heap_full ? 2 * b->node_capacity : 2 * b->pool_capacity);
    if (heap_full) b->node_capacity *= 2;
    else b->pool_capacity *= 2;
    status = start(s, stats);
  }
  return status;
}

static lt_status create(lt_structure *s, lt_stats *stats) {
  bvh_state *b = s->state;
  if (s->config.sah_bins > LT_MAX_BINS || s->config.sah_bins < 2)
    return lt__fail(LT_ERROR_INVALID_ARGUMENT, "--bins %d: the BVH takes 2 to %d SAH bins", s->config.sah_bins, LT_MAX_BINS);
  b->sah = lt__structure_sah(&s->config);
  b->pool_capacity = s->config.pool_capacity > 0 ? s->config.pool_capacity
                                                 : initial_pool_capacity(lt_scene_triangle_count(s->scene));
  b->node_capacity = lt__structure_tiny_capacities ? 4 : (int)lt_scene_triangle_count(s->scene) + 2;
  if (lt__structure_tiny_capacities && s->config.pool_capacity <= 0) b->pool_capacity = 4;
  return with_retry(s, stats, start(s, stats));
}

LT__KERNEL_ARGS(index_args, LT_BVH_INDEX_ARGS, lt_bvh_index_view)

/* A full build's tree is finished: its rays go through the plain trace kernel, which costs a
 * ray less than the persistent kernel's round of batches and link reads. */
static lt_status trace_finished(lt_structure *s, const lt_ray *rays, int count, int flags, lt_hit *hits,
                                lt_stats *stats) {
  bvh_state *b = s->state;
  index_args args = {NULL, NULL, 0, 0, &b->od.nodes, &b->od.index, &b->od.verts};
  lt_bvh_index_view view;
  lt__trace_call call = {"lt_bvh_trace_index", lt__native_bvh_trace_index_kernel, index_args_set_any,
                         index_args_view_any, &args, &args.rays, &args.hits, &args.ray_count, &args.flags, &view};
  return lt__trace_finished(s->ctx, &call, rays, count, flags, hits, stats);
}

static lt_status launch(lt_structure *s, const lt_ray *rays, int count, int flags, lt_hit *hits, int speculate,
                        lt_stats *stats) {
  bvh_state *b = s->state;
  return lt__ondemand_launch(&b->od, rays, count, flags, hits, speculate, stats);
}

static int may_grow_structure(const lt_structure *s) { return may_grow(s->state); }

/* The re-trace for statistics collapses nothing (runtime/bvh_wide_host.c): the next batch's
 * launch does, in its own time, so that no collapse is left out of a time to image. */
static void retracing(lt_structure *s, int on) {
  bvh_state *b = s->state;
  if (b->live) b->od.wide_hold = on;
}

/* A full build's tree is traced by the plain kernel; on demand, lt__ondemand_trace. */
static lt_status trace(lt_structure *s, const lt_ray *rays, int count, int flags, lt_hit *hits, lt_stats *stats) {
  static const lt__ondemand_ops ops = {launch, may_grow_structure, with_retry, retracing};
  if (mode_of(s) == LT_BUILD_FULL) return trace_finished(s, rays, count, flags, hits, stats);
  return lt__ondemand_trace(s, &ops, rays, count, flags, hits, stats);
}

static void put_stats(lt_structure *s, lt_stats *stats) {
  bvh_state *b = s->state;
  double nodes = 0, node_bytes, ref_bytes, pool_bytes;
  lt__ondemand_nodes_built(&b->od, &nodes);
  lt__stats_put(stats, LT_STAT_REFERENCES, (double)lt_scene_triangle_count(s->scene));
  lt__stats_put(stats, LT_STAT_NODES_BUILT, nodes);
  if (mode_of(s) == LT_BUILD_FULL) lt__stats_put(stats, LT_STAT_NODES_FULL, nodes);
  lt__stats_put(stats, LT_STAT_MEMORY_BYTES, lt__ondemand_bytes(&b->od, &node_bytes, &ref_bytes, &pool_bytes));
  lt__stats_put(stats, LT_STAT_NODE_BYTES, node_bytes);
  lt__stats_put(stats, LT_STAT_REFERENCE_BYTES, ref_bytes);
  lt__stats_put(stats, LT_STAT_POOL_BYTES, pool_bytes);
  if (b->od.wide_on) {
    const lt__bvh8 *w = &b->od.wide;
    lt__stats_put(stats, LT_STAT_WIDE_NODES, w->node_count);
    lt__stats_put(stats, LT_STAT_WIDE_BYTES,
                  (double)w->node_capacity * sizeof(lt_bvh8_node) +
                      (double)w->slot_capacity * (sizeof(lt_tri4) / 4));
    lt__stats_put(stats, LT_STAT_WIDE_MS, b->od.wide_ms);
  }
}

static void release(lt_structure *s) {
  bvh_state *b = s->state;
  if (b->live) lt__ondemand_release(&b->od);
  b->live = 0;
}

lt__ondemand *lt__structure_ondemand(lt_structure *s) {
  if (s->cls != &lt__structure_bvh) return NULL;
  bvh_state *b = s->state;
  return b->live ? &b->od : NULL;
}

static const char *const kernels[] = {"lt_bvh_ondemand", "lt_bvh_trace_index", NULL};

static const lt__param params[] = {
    LT__PARAM_INT("--leaf-size", max_leaf_size, 1, 1 << 24, "most triangles a leaf holds without SAH asking"),
    LT__PARAM_INT("--bins", sah_bins, 2, LT_MAX_BINS, "SAH bins per axis"),
    LT__PARAM_CHOICE("--top", bvh_top, "sah|morton",
                     "top levels: binned SAH, or split by Morton code after one sort (for scenes rebuilt every frame)"),
    LT__PARAM_INT("--morton-above", bvh_morton_above, 16, 1 << 30,
                  "with --top morton: nodes of more triangles split by Morton code, smaller ones by SAH"),
    {0, 0, 0, 0, 0, 0, 0},
};

const lt__structure_class lt__structure_bvh = {
    .name = "bvh",
    .summary = "binned SAH BVH (Vinkler et al. 2016), built through the task pool in full or on demand",
    .params = params,
    .modes = 1u << LT_BUILD_FULL | 1u << LT_BUILD_REQUESTED | 1u << LT_BUILD_SPECULATIVE,
    .defaults = {.kind = LT_STRUCTURE_BVH, .build = LT_BUILD_SPECULATIVE, .max_leaf_size = 16, .sah_bins = 32,
                 .traversal_cost = 1.0f, .pool_capacity = 0, .intersect = LT_INTERSECT_WATERTIGHT, .grid_density = 3.0f,
                 .bvh_top = LT_BVH_TOP_SAH, .bvh_morton_above = 2048},
    .state_size = sizeof(bvh_state),
    .create = create,
    .trace = trace,
    .put_stats = put_stats,
    .release = release,
    .kernels = kernels,
};
