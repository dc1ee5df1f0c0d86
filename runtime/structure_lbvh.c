/* The registry entry of the LBVH (builders/host/lbvh.c), the fast-build baseline: built on the
 * host in full, on one thread per work-group (at most one per core), traced by the host-built
 * BVH's kernel (kernels/bvh_trace.h). Trees from the
 * other host builders (the sweep builder of the accuracy report) ride on the same entry. */
#include <stdlib.h>
#include <string.h>

#include "builders/host/lbvh.h"
#include "kernels/bvh_trace.h"
#include "kernels/native_kernels.h"
#include "runtime/context_internal.h"
#include "runtime/error.h"
#include "runtime/kernel_args_host.h"
#include "runtime/registry.h"
#include "runtime/stats_internal.h"
#include "runtime/trace_launch.h"

typedef struct lbvh_state {
  lt__bvh bvh;
  lt__buffer nodes, tris; /* bvh's arrays on the device (on native, the arrays themselves) */
} lbvh_state;

/* The trace kernel's arguments from its one list (kernels/bvh_trace.h). */
LT__KERNEL_ARGS(trace_args, LT_BVH_TRACE_ARGS, lt_bvh_trace_view)

static lt_status upload(lt_structure *s) {
  lbvh_state *l = s->state;
  lt_status status = lt__buffer_wrap(s->ctx, &l->nodes, l->bvh.nodes, (size_t)l->bvh.node_count * sizeof(lt_bvh_node));
  return status ? status : lt__buffer_wrap(s->ctx, &l->tris, l->bvh.tris, (size_t)l->bvh.tri_count * sizeof(lt_tri));
}

static lt_status create(lt_structure *s, lt_stats *stats) {
  lbvh_state *l = s->state;
  lt__sah_config sah = lt__structure_sah(&s->config);
  size_t n = lt_scene_triangle_count(s->scene);
  /* As many builder threads as work-groups run at once, but no more than the host has cores:
   * an OpenCL GPU's work-group count says nothing about the host. */
  int workers = lt_context_work_groups(s->ctx), cores = lt__native_threads();
  lt__executor executor = {workers < cores ? workers : cores, lt__native_run};
  double start = lt_now_ms();
  lt_status status =
      lt__bvh_build_lbvh_with(lt_scene_triangles(s->scene), n, &sah, LT_BVH_MAX_DEPTH, &executor, &l->bvh);
  if (status)
    return lt__fail(status, "building the LBVH over %zu triangles (leaf size %d, %d bins): %s", n, sah.max_leaf_size,
                    sah.bins, lt_status_str(status));
  status = upload(s);
  lt__stats_add(stats, LT_STAT_BUILD_MS, lt_now_ms() - start);
  lt__stats_add(stats, LT_STAT_SORT_OPS, (double)l->bvh.sort_ops);
  return status;
}

static lt_status trace(lt_structure *s, const lt_ray *rays, int count, int flags, lt_hit *hits, lt_stats *stats) {
  lbvh_state *l = s->state;
  trace_args args = {NULL, NULL, 0, 0, &l->nodes, &l->tris};
  lt_bvh_trace_view view;
  lt__trace_call call = {"lt_bvh_trace", lt__native_bvh_trace_kernel, trace_args_set_any, trace_args_view_any, &args, &args.rays,
                         &args.hits, &args.ray_count, &args.flags, &view};
  return lt__trace_finished(s->ctx, &call, rays, count, flags, hits, stats);
}

static void put_stats(lt_structure *s, lt_stats *stats) {
  lbvh_state *l = s->state;
  size_t node_bytes = (size_t)l->bvh.node_count * sizeof(lt_bvh_node);
  size_t ref_bytes = (size_t)l->bvh.tri_count * sizeof(lt_tri);
  lt__stats_put(stats, LT_STAT_REFERENCES, (double)lt_scene_triangle_count(s->scene));
  lt__stats_put(stats, LT_STAT_NODES_BUILT, (double)lt__bvh_tree_nodes(&l->bvh));
  lt__stats_put(stats, LT_STAT_NODES_FULL, (double)lt__bvh_tree_nodes(&l->bvh));
  lt__stats_put(stats, LT_STAT_NODE_BYTES, (double)node_bytes);
  lt__stats_put(stats, LT_STAT_REFERENCE_BYTES, (double)ref_bytes);
  lt__stats_put(stats, LT_STAT_POOL_BYTES, 0);
  lt__stats_put(stats, LT_STAT_MEMORY_BYTES, (double)(node_bytes + ref_bytes));
  lt__stats_put(stats, LT_STAT_MAX_DEPTH, l->bvh.max_depth);
  lt__stats_put(stats, LT_STAT_SAH_COST, l->bvh.sah_cost);
}

static void release(lt_structure *s) {
  lbvh_state *l = s->state;
  lt__buffer_release(&l->nodes);
  lt__buffer_release(&l->tris);
  lt__bvh_free(&l->bvh);
}

lt_status lt__structure_from_bvh(lt_context *ctx, const lt_scene *scene, lt__bvh *bvh, lt_structure **out) {
  if (!bvh) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt__structure_from_bvh: NULL tree");
  lt_structure_config config = lt_structure_config_default(LT_STRUCTURE_LBVH);
  lt_structure *s;
  lt_status status = lt__structure_wrap(ctx, scene, &config, &s);
  if (status) return status;
  lbvh_state *l = s->state;
  l->bvh = *bvh;
  memset(bvh, 0, sizeof *bvh);
  status = upload(s);
  if (status) {
    lt_structure_destroy(s);
    return status;
  }
  *out = s;
  return LT_OK;
}

static const char *const kernels[] = {"lt_bvh_trace", NULL};

static const lt__param params[] = {
    LT__PARAM_INT("--leaf-size", max_leaf_size, 1, 1 << 24, "most triangles a leaf holds without SAH asking"),
    LT__PARAM_INT("--bins", sah_bins, 2, LT_MAX_BINS, "SAH bins per axis of the top levels"),
    {0, 0, 0, 0, 0, 0, 0},
};

const lt__structure_class lt__structure_lbvh = {
    .name = "lbvh",
    .summary = "LBVH (Karras 2012) with an SAH top, built on the host's threads: the fast-build baseline",
    .params = params,
    .modes = 1u << LT_BUILD_FULL,
    .defaults = {.kind = LT_STRUCTURE_LBVH, .build = LT_BUILD_FULL, .max_leaf_size = 16, .sah_bins = 32,
                 .traversal_cost = 1.0f, .pool_capacity = 0, .intersect = LT_INTERSECT_WATERTIGHT, .grid_density = 3.0f},
    .state_size = sizeof(lbvh_state),
    .create = create,
    .trace = trace,
    .put_stats = put_stats,
    .release = release,
    .kernels = kernels,
};
