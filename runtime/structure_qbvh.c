/* The registry entry of the QBVH (Bogolepov and Ulyanov): the binary SAH BVH built on the host
 * (builders/host/bvh_sah.c) and collapsed into a 4-ary tree (builders/host/qbvh_collapse.c),
 * traced four boxes at a time with 32-bit stack entries (kernels/qbvh_trace.h). Full build
 * only. */
#include <stdlib.h>
#include <string.h>

#include "builders/host/qbvh_collapse.h"
#include "kernels/native_kernels.h"
#include "kernels/qbvh_trace.h"
#include "runtime/context_internal.h"
#include "runtime/error.h"
#include "runtime/kernel_args_host.h"
#include "runtime/registry.h"
#include "runtime/stats_internal.h"
#include "runtime/trace_launch.h"

int lt__structure_qbvh_max_nodes = LT_QBVH_MAX_NODES;

typedef struct qbvh_state {
  lt__bvh bvh;  /* the binary tree; its triangles in leaf order are the QBVH's leaves */
  lt__qbvh qbvh;
  lt__buffer nodes, tris; /* on the device (on native, the arrays themselves) */
} qbvh_state;

/* The trace kernel's arguments from its one list (kernels/qbvh_trace.h). */
LT__KERNEL_ARGS(trace_args, LT_QBVH_TRACE_ARGS, lt_qbvh_trace_view)

static lt_status create(lt_structure *s, lt_stats *stats) {
  qbvh_state *q = s->state;
  lt__sah_config sah = lt__structure_sah(&s->config);
  size_t n = lt_scene_triangle_count(s->scene);
  double start = lt_now_ms();

  /* The binary tree, then its collapse; the binary nodes are not needed after it. */
  lt_status status = lt__bvh_build_sah(lt_scene_triangles(s->scene), n, &sah, &q->bvh);
  if (status)
    return lt__fail(status, "building the SAH BVH for the QBVH over %zu triangles: %s", n, lt_status_str(status));
  status = lt__qbvh_collapse(&q->bvh, lt__structure_qbvh_max_nodes, &q->qbvh);
  if (status == LT_ERROR_UNSUPPORTED)
    return lt__fail(status,
                    "--structure qbvh: the tree over %zu triangles needs %d nodes, more than the %d its 32-bit stack "
                    "entries can name (26 bits; scenes of up to %d triangles always fit): use --structure bvh",
                    n, lt__qbvh_count_nodes(&q->bvh), lt__structure_qbvh_max_nodes, LT_QBVH_MAX_NODES);
  if (status) return lt__fail(status, "collapsing the SAH BVH into a QBVH: %s", lt_status_str(status));
  free(q->bvh.nodes);
  q->bvh.nodes = NULL;

  status = lt__buffer_wrap(s->ctx, &q->nodes, q->qbvh.nodes, (size_t)q->qbvh.node_count * sizeof(lt_qbvh_node));
  if (!status) status = lt__buffer_wrap(s->ctx, &q->tris, q->bvh.tris, (size_t)q->bvh.tri_count * sizeof(lt_tri));
  lt__stats_add(stats, LT_STAT_BUILD_MS, lt_now_ms() - start);
  lt__stats_add(stats, LT_STAT_SORT_OPS, (double)q->bvh.sort_ops);
  return status;
}

static lt_status trace(lt_structure *s, const lt_ray *rays, int count, int flags, lt_hit *hits, lt_stats *stats) {
  qbvh_state *q = s->state;
  trace_args args = {NULL, NULL, 0, 0, &q->nodes, &q->tris};
  lt_qbvh_trace_view view;
  lt__trace_call call = {"lt_qbvh_trace", lt__native_qbvh_trace_kernel, trace_args_set_any, trace_args_view_any,
                         &args, &args.rays, &args.hits, &args.ray_count, &args.flags, &view};
  return lt__trace_finished(s->ctx, &call, rays, count, flags, hits, stats);
}

static void put_stats(lt_structure *s, lt_stats *stats) {
  qbvh_state *q = s->state;
  size_t node_bytes = (size_t)q->qbvh.node_count * sizeof(lt_qbvh_node);
  size_t ref_bytes = (size_t)q->bvh.tri_count * sizeof(lt_tri);
  double nodes = (double)q->qbvh.node_count + q->qbvh.leaf_count;
  lt__stats_put(stats, LT_STAT_REFERENCES, (double)lt_scene_triangle_count(s->scene));
  lt__stats_put(stats, LT_STAT_NODES_BUILT, nodes);
  lt__stats_put(stats, LT_STAT_NODES_FULL, nodes);
  lt__stats_put(stats, LT_STAT_NODE_BYTES, (double)node_bytes);
  lt__stats_put(stats, LT_STAT_REFERENCE_BYTES, (double)ref_bytes);
  lt__stats_put(stats, LT_STAT_POOL_BYTES, 0);
  lt__stats_put(stats, LT_STAT_MEMORY_BYTES, (double)(node_bytes + ref_bytes));
  lt__stats_put(stats, LT_STAT_MAX_DEPTH, q->qbvh.max_depth);
  lt__stats_put(stats, LT_STAT_SAH_COST, q->bvh.sah_cost);
}

static void release(lt_structure *s) {
  qbvh_state *q = s->state;
  lt__buffer_release(&q->nodes);
  lt__buffer_release(&q->tris);
  lt__qbvh_free(&q->qbvh);
  lt__bvh_free(&q->bvh);
}

static const char *const kernels[] = {"lt_qbvh_trace", NULL};

static const lt__param params[] = {
    LT__PARAM_INT("--leaf-size", max_leaf_size, 1, 1 << 24, "most triangles a leaf holds without SAH asking"),
    LT__PARAM_INT("--bins", sah_bins, 2, LT_MAX_BINS, "SAH bins per axis"),
    {0, 0, 0, 0, 0, 0, 0},
};

const lt__structure_class lt__structure_qbvh = {
    .name = "qbvh",
    .summary = "SAH BVH collapsed to 4 children a node (Bogolepov and Ulyanov), built on the host: full",
    .params = params,
    .modes = 1u << LT_BUILD_FULL,
    .defaults = {.kind = LT_STRUCTURE_QBVH, .build = LT_BUILD_FULL, .max_leaf_size = 16, .sah_bins = 32,
                 .traversal_cost = 1.0f, .pool_capacity = 0, .intersect = LT_INTERSECT_WATERTIGHT, .grid_density = 3.0f},
    .state_size = sizeof(qbvh_state),
    .create = create,
    .trace = trace,
    .put_stats = put_stats,
    .release = release,
    .kernels = kernels,
};
