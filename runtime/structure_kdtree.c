/* The registry entry of the SAH kd-tree built through the task pool (runtime/kd_ondemand_host.c,
 * kernels/kd_ondemand.h): fully, or on demand while the rays are traced (the on-demand paper,
 * section 3.5: Kd-tree, Kd-tree_R, Kd-tree_A). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "kernels/kd_trace.h"
#include "kernels/native_kernels.h"
#include "runtime/context_internal.h"
#include "runtime/error.h"
#include "runtime/kd_ondemand_host.h"
#include "runtime/kernel_args_host.h"
#include "runtime/ondemand_trace.h"
#include "runtime/registry.h"
#include "runtime/stats_internal.h"
#include "runtime/trace_launch.h"

typedef struct kd_state {
  lt__kd_config config;
  lt__kd kd;
  int live;          /* kd holds a tree */
  int pool_capacity; /* each doubled when it fills up, and the build starts again */
  int node_capacity;
  int ref_capacity;
} kd_state;

/* The largest pool or heap a retry may ask for. */
#define MAX_POOL (1 << 26)
#define MAX_HEAP (INT32_MAX / 2)

static lt_build_mode mode_of(const lt_structure *s) { return s->config.build; }

/* (Re)creates the tree, and in a full build builds all of it. */
static lt_status start(lt_structure *s, lt_stats *stats) {
  kd_state *k = s->state;
  if (k->live) lt__kd_release(&k->kd);
  k->live = 0;
  double begin = lt_now_ms(), compile = s->ctx->compile_ms;
  int pool_mode = (int)mode_of(s) - LT_BUILD_FULL; /* LT_POOL_FULL, _REQUESTED, _SPECULATIVE */
  lt_status status = lt__kd_create(s->ctx, s->scene, &k->config, pool_mode, k->pool_capacity, k->node_capacity,
                                   k->ref_capacity, &k->kd);
  if (!status) k->live = 1;
  if (!status && mode_of(s) == LT_BUILD_FULL) status = lt__kd_launch(&k->kd, NULL, 0, 0, NULL, 0, stats);
  lt__stats_add(stats, LT_STAT_BUILD_MS, lt_now_ms() - begin - (s->ctx->compile_ms - compile));
  return status;
}

/* Whether another retry may grow what filled up. */
static int may_grow(const kd_state *k) {
  return k->pool_capacity < MAX_POOL && k->node_capacity < MAX_HEAP && k->ref_capacity < MAX_HEAP;
}

/* Starts again from scratch with twice the room of what filled up: the pool, the node heap or
 * the reference heap. */
static lt_status with_retry(lt_structure *s, lt_stats *stats, lt_status status) {
  kd_state *k = s->state;
  while (status == LT_ERROR_CAPACITY && may_grow(k)) {
    int nodes_full = 0, refs_full = 0;
    if (k->live) lt__kd_heaps_full(&k->kd, &nodes_full, &refs_full);
    int *grow = nodes_full ? &k->node_capacity : refs_full ? &k->ref_capacity : &k->pool_capacity;
    const char *what = nodes_full ? "a node heap" : refs_full ? "a reference heap" : "a pool";
    if (!s->ctx->quiet) fprintf(stderr, "lazytrace: %s; retrying with %s of %d\n", lt_last_error(), what, 2 * *grow);
    *grow *= 2;
    status = start(s, stats);
  }
  return status;
}

static lt_status create(lt_structure *s, lt_stats *stats) {
  kd_state *k = s->state;
  size_t n = lt_scene_triangle_count(s->scene);
  if (s->config.sah_bins > LT_MAX_BINS || s->config.sah_bins < 2)
    return lt__fail(LT_ERROR_INVALID_ARGUMENT, "--bins %d: the kd-tree takes 2 to %d SAH bins", s->config.sah_bins,
                    LT_MAX_BINS);
  if (n > (size_t)MAX_HEAP / 8)
    return lt__fail(LT_ERROR_INVALID_ARGUMENT, "the kd-tree takes at most %d triangles", MAX_HEAP / 8);
  if (s->config.kd_traversal != LT_KD_TRAVERSAL_STACK && s->config.build != LT_BUILD_FULL)
    return lt__fail(LT_ERROR_UNSUPPORTED, "--traversal %s runs on a fully built kd-tree: add --build full",
                    s->config.kd_traversal == LT_KD_TRAVERSAL_RESTART ? "restart" : "backtrack");
  k->config.max_leaf = s->config.max_leaf_size, k->config.bins = s->config.sah_bins;
  k->config.sweep = s->config.kd_split == LT_KD_SPLIT_SWEEP, k->config.clip = s->config.kd_clip == LT_KD_CLIP_ON;
  k->config.traversal = s->config.kd_traversal == LT_KD_TRAVERSAL_RESTART     ? LT_KD_TRAVERSE_RESTART
                        : s->config.kd_traversal == LT_KD_TRAVERSAL_BACKTRACK ? LT_KD_TRAVERSE_BACKTRACK
                                                                              : LT_KD_TRAVERSE_STACK;
  k->config.max_depth = lt__kd_max_depth(n);
  k->config.traversal_cost = s->config.traversal_cost, k->config.intersection_cost = 1.0f;
  int tiny = lt__structure_tiny_capacities;
  size_t pool = n / 8 < 4096 ? 4096 : n / 8 > (1u << 22) ? (1u << 22) : n / 8;
  k->pool_capacity = s->config.pool_capacity > 0 ? s->config.pool_capacity : tiny ? 4 : (int)pool;
  /* Straddling triangles make more references than triangles, and each level moves the right
   * sides to new arrays (the heap never frees): a full build of the generators took up to
   * about 0.7 * max_depth references per triangle. Untouched room costs no memory on the
   * native backend. */
  k->node_capacity = tiny ? 4 : (int)(n + 1024); /* full trees of the generators: 0.2 to 0.4 per triangle */
  double refs = (double)n * (0.75 * k->config.max_depth + 2.0) + 1024.0;
  k->ref_capacity = tiny ? (int)n : refs > MAX_HEAP / 2 ? MAX_HEAP / 2 : (int)refs;
  return with_retry(s, stats, start(s, stats));
}

LT__KERNEL_ARGS(kd_trace_args, LT_KD_TRACE_ARGS, lt_kd_trace_view)

/* A full build's tree is finished: its rays go through the plain trace kernel. */
static lt_status trace_finished(lt_structure *s, const lt_ray *rays, int count, int flags, lt_hit *hits,
                                lt_stats *stats) {
  kd_state *k = s->state;
  lt__kd *kd = &k->kd;
  kd_trace_args args = {NULL, NULL, 0, 0, &kd->nodes, &kd->refs, &kd->verts, &kd->parents, &kd->cells,
                        (lt_float4){kd->bounds.lo[0], kd->bounds.lo[1], kd->bounds.lo[2], 0.0f},
                        (lt_float4){kd->bounds.hi[0], kd->bounds.hi[1], kd->bounds.hi[2], 0.0f}, k->config.traversal};
  lt_kd_trace_view view;
  lt__trace_call call = {"lt_kd_trace", lt__native_kd_trace_kernel, kd_trace_args_set_any, kd_trace_args_view_any,
                         &args, &args.rays, &args.hits, &args.ray_count, &args.flags, &view};
  return lt__trace_finished(s->ctx, &call, rays, count, flags, hits, stats);
}

static lt_status launch(lt_structure *s, const lt_ray *rays, int count, int flags, lt_hit *hits, int speculate,
                        lt_stats *stats) {
  kd_state *k = s->state;
  return lt__kd_launch(&k->kd, rays, count, flags, hits, speculate, stats);
}

static int may_grow_structure(const lt_structure *s) { return may_grow(s->state); }

/* A full build's tree is traced by the plain kernel; on demand, lt__ondemand_trace. */
static lt_status trace(lt_structure *s, const lt_ray *rays, int count, int flags, lt_hit *hits, lt_stats *stats) {
  static const lt__ondemand_ops ops = {launch, may_grow_structure, with_retry, NULL};
  if (mode_of(s) == LT_BUILD_FULL) return trace_finished(s, rays, count, flags, hits, stats);
  return lt__ondemand_trace(s, &ops, rays, count, flags, hits, stats);
}

static void put_stats(lt_structure *s, lt_stats *stats) {
  kd_state *k = s->state;
  if (!k->live) return;
  double nodes = lt__kd_nodes_built(&k->kd), node_bytes, ref_bytes, pool_bytes;
  double memory = lt__kd_bytes(&k->kd, &node_bytes, &ref_bytes, &pool_bytes);
  lt__stats_put(stats, LT_STAT_REFERENCES, k->kd.leaf_refs);
  lt__stats_put(stats, LT_STAT_NODES_BUILT, nodes);
  if (mode_of(s) == LT_BUILD_FULL) lt__stats_put(stats, LT_STAT_NODES_FULL, nodes);
  lt__stats_put(stats, LT_STAT_MAX_DEPTH, k->kd.depth);
  double cost;
  if (mode_of(s) == LT_BUILD_FULL && lt__kd_sah_cost(&k->kd, &cost) == LT_OK) lt__stats_put(stats, LT_STAT_SAH_COST, cost);
  lt__stats_put(stats, LT_STAT_MEMORY_BYTES, memory);
  lt__stats_put(stats, LT_STAT_NODE_BYTES, node_bytes);
  lt__stats_put(stats, LT_STAT_REFERENCE_BYTES, ref_bytes);
  lt__stats_put(stats, LT_STAT_POOL_BYTES, pool_bytes);
}

static void release(lt_structure *s) {
  kd_state *k = s->state;
  if (k->live) lt__kd_release(&k->kd);
  k->live = 0;
}

lt__kd *lt__structure_kd(lt_structure *s) {
  if (s->cls != &lt__structure_kdtree) return NULL;
  kd_state *k = s->state;
  return k->live ? &k->kd : NULL;
}

static const char *const kernels[] = {"lt_kd_ondemand", "lt_kd_trace", NULL};

static const lt__param params[] = {
    LT__PARAM_INT("--leaf-size", max_leaf_size, 1, 1 << 24, "most references a leaf holds without SAH asking"),
    LT__PARAM_INT("--bins", sah_bins, 2, LT_MAX_BINS, "SAH bins per axis"),
    LT__PARAM_CHOICE("--traversal", kd_traversal, "stack|restart|backtrack",
                     "front to back with a stack, or stackless (Foley and Sugerman; --build full)"),
    LT__PARAM_CHOICE("--split", kd_split, "binned|sweep", "split search: SAH bins, or an exact sweep of cells up to 1024 references"),
    LT__PARAM_CHOICE("--clip", kd_clip, "off|on", "classify by the triangle's part inside the cell (perfect splits)"),
    {0, 0, 0, 0, 0, 0, 0},
};

const lt__structure_class lt__structure_kdtree = {
    .name = "kdtree",
    .summary = "binned SAH kd-tree (Vinkler et al. 2016), built through the task pool in full or on demand",
    .params = params,
    .modes = 1u << LT_BUILD_FULL | 1u << LT_BUILD_REQUESTED | 1u << LT_BUILD_SPECULATIVE,
    .defaults = {.kind = LT_STRUCTURE_KDTREE, .build = LT_BUILD_SPECULATIVE, .max_leaf_size = 16, .sah_bins = 32,
                 .traversal_cost = 1.0f, .pool_capacity = 0, .intersect = LT_INTERSECT_WATERTIGHT, .grid_density = 3.0f,
                 .kd_traversal = LT_KD_TRAVERSAL_STACK, .kd_split = LT_KD_SPLIT_BINNED, .kd_clip = LT_KD_CLIP_OFF},
    .state_size = sizeof(kd_state),
    .create = create,
    .trace = trace,
    .put_stats = put_stats,
    .release = release,
    .kernels = kernels,
};
