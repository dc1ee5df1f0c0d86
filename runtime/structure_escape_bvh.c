/* The registry entry of the escape-index BVH (Thrane and Simonsen 2005): a BVH built on the host
 * (--builder: the binned SAH builder, builders/host/bvh_sah.c, or the thesis' Kay-Kajiya and
 * Goldsmith-Salmon builders, builders/host/bvh_thesis.c) laid out in depth-first order with
 * escape indices (builders/host/escape_bvh.c) and traced without a stack
 * (kernels/escape_bvh_trace.h). A reference to compare against, not a default. Full build only. */
#include <stdlib.h>
#include <string.h>

#include "builders/host/escape_bvh.h"
#include "kernels/escape_bvh_trace.h"
#include "kernels/native_kernels.h"
#include "runtime/context_internal.h"
#include "runtime/error.h"
#include "runtime/kernel_args_host.h"
#include "runtime/registry.h"
#include "runtime/stats_internal.h"
#include "runtime/trace_launch.h"

/* Goldsmith-Salmon: the thesis' number of shuffled orders, and the seed that fixes them. */
#define GS_ORDERS 15
#define GS_SEED 20050601u

typedef struct escape_state {
  lt__bvh bvh; /* the SAH tree as built; its triangles in leaf order are the leaves' (the other
                  builders: bvh.tris and tri_count only, the copy in leaf order) */
  lt__escape_bvh escape;
  lt__buffer nodes, tris; /* on the device (on native, the arrays themselves) */
} escape_state;

/* The trace kernel's arguments from its one list (kernels/escape_bvh_trace.h). */
LT__KERNEL_ARGS(trace_args, LT_ESCAPE_BVH_TRACE_ARGS, lt_escape_bvh_trace_view)

static lt_status create(lt_structure *s, lt_stats *stats) {
  escape_state *e = s->state;
  lt__sah_config sah = lt__structure_sah(&s->config);
  size_t n = lt_scene_triangle_count(s->scene);
  double start = lt_now_ms();

  const float *tris = lt_scene_triangles(s->scene);
  lt_status status;
  if (s->config.bvh_builder == LT_BVH_BUILDER_SAH) {
    status = lt__bvh_build_sah(tris, n, &sah, &e->bvh);
    if (status)
      return lt__fail(status, "building the SAH BVH for the escape-index BVH over %zu triangles: %s", n,
                      lt_status_str(status));
    status = lt__escape_bvh_from_bvh(&e->bvh, &e->escape);
    free(e->bvh.nodes);
    e->bvh.nodes = NULL;
  } else {
    lt__tree tree;
    int kk = s->config.bvh_builder == LT_BVH_BUILDER_KAY_KAJIYA;
    status = kk ? lt__tree_build_kay_kajiya(tris, n, &tree)
                : lt__tree_build_goldsmith_salmon(tris, n, GS_ORDERS, GS_SEED, &tree);
    if (status)
      return lt__fail(status, "the %s builder over %zu triangles: %s", kk ? "Kay-Kajiya" : "Goldsmith-Salmon", n,
                      lt_status_str(status));
    e->bvh.sah_cost = tree.cost;
    e->bvh.tri_count = (int)n;
    status = lt__escape_bvh_from_tree(&tree, tris, &e->escape, &e->bvh.tris);
    lt__tree_free(&tree);
  }
  if (status) return lt__fail(status, "laying out the escape-index BVH: %s", lt_status_str(status));

  status = lt__buffer_wrap(s->ctx, &e->nodes, e->escape.nodes, (size_t)e->escape.node_count * sizeof(lt_escape_node));
  if (!status)
    status = lt__buffer_wrap(s->ctx, &e->tris, e->bvh.tris, (size_t)e->bvh.tri_count * sizeof(lt_tri));
  lt__stats_add(stats, LT_STAT_BUILD_MS, lt_now_ms() - start);
  lt__stats_add(stats, LT_STAT_SORT_OPS, (double)e->bvh.sort_ops);
  return status;
}

static lt_status trace(lt_structure *s, const lt_ray *rays, int count, int flags, lt_hit *hits, lt_stats *stats) {
  escape_state *e = s->state;
  trace_args args = {NULL, NULL, 0, 0, &e->nodes, &e->tris, e->escape.node_count};
  lt_escape_bvh_trace_view view;
  lt__trace_call call = {"lt_escape_bvh_trace", lt__native_escape_bvh_trace_kernel, trace_args_set_any,
                         trace_args_view_any, &args, &args.rays, &args.hits, &args.ray_count, &args.flags, &view};
  return lt__trace_finished(s->ctx, &call, rays, count, flags, hits, stats);
}

static void put_stats(lt_structure *s, lt_stats *stats) {
  escape_state *e = s->state;
  size_t node_bytes = (size_t)e->escape.node_count * sizeof(lt_escape_node);
  size_t ref_bytes = (size_t)e->bvh.tri_count * sizeof(lt_tri);
  lt__stats_put(stats, LT_STAT_REFERENCES, (double)lt_scene_triangle_count(s->scene));
  lt__stats_put(stats, LT_STAT_NODES_BUILT, (double)e->escape.node_count);
  lt__stats_put(stats, LT_STAT_NODES_FULL, (double)e->escape.node_count);
  lt__stats_put(stats, LT_STAT_NODE_BYTES, (double)node_bytes);
  lt__stats_put(stats, LT_STAT_REFERENCE_BYTES, (double)ref_bytes);
  lt__stats_put(stats, LT_STAT_POOL_BYTES, 0);
  lt__stats_put(stats, LT_STAT_MEMORY_BYTES, (double)(node_bytes + ref_bytes));
  lt__stats_put(stats, LT_STAT_MAX_DEPTH, e->escape.max_depth);
  lt__stats_put(stats, LT_STAT_SAH_COST, e->bvh.sah_cost);
}

static void release(lt_structure *s) {
  escape_state *e = s->state;
  lt__buffer_release(&e->nodes);
  lt__buffer_release(&e->tris);
  lt__escape_bvh_free(&e->escape);
  lt__bvh_free(&e->bvh);
}

static const char *const kernels[] = {"lt_escape_bvh_trace", NULL};

static const lt__param params[] = {
    LT__PARAM_INT("--leaf-size", max_leaf_size, 1, 1 << 24, "most triangles a leaf holds without SAH asking"),
    LT__PARAM_INT("--bins", sah_bins, 2, LT_MAX_BINS, "SAH bins per axis"),
    LT__PARAM_CHOICE("--builder", bvh_builder, "sah|kay-kajiya|goldsmith-salmon",
                     "the tree: binned SAH, spatial median of the longest axis (one triangle a leaf), or insertion "
                     "by surface-area cost (best of 15 shuffled orders, fixed seed)"),
    {0, 0, 0, 0, 0, 0, 0},
};

const lt__structure_class lt__structure_escape_bvh = {
    .name = "escape-bvh",
    .summary = "SAH (or Kay-Kajiya, Goldsmith-Salmon) BVH in depth-first order with escape indices (Thrane and "
               "Simonsen), traced without a stack, built on the host: full",
    .params = params,
    .modes = 1u << LT_BUILD_FULL,
    .defaults = {.kind = LT_STRUCTURE_ESCAPE_BVH, .build = LT_BUILD_FULL, .max_leaf_size = 16, .sah_bins = 32,
                 .traversal_cost = 1.0f, .pool_capacity = 0, .intersect = LT_INTERSECT_WATERTIGHT, .grid_density = 3.0f,
                 .bvh_builder = LT_BVH_BUILDER_SAH},
    .state_size = sizeof(escape_state),
    .create = create,
    .trace = trace,
    .put_stats = put_stats,
    .release = release,
    .kernels = kernels,
};
