/* The registry entry of the QBVH (Bogolepov and Ulyanov): the binary SAH BVH built on the host
 * (builders/host/bvh_sah.c) and collapsed into a 4-ary tree (builders/host/qbvh_collapse.c),
 * traced four boxes at a time with 32-bit stack entries (kernels/qbvh_trace.h). Full build
 * only. On the native backend of a CPU with AVX2 the same binary tree is collapsed 8 wide
 * instead (builders/host/bvh8_collapse.c) and traced eight boxes at a time
 * (kernels/bvh8_trace.h); LT_QBVH_WIDTH=4 in the environment keeps the 4-wide path there. */
#include <stdlib.h>
#include <string.h>

#include "builders/host/bvh8_collapse.h"
#include "builders/host/qbvh_collapse.h"
#include "kernels/native_kernels.h"
#include "kernels/qbvh_trace.h"
#include "runtime/bvh_ondemand_host.h"
#include "runtime/context_internal.h"
#include "runtime/error.h"
#include "runtime/kernel_args_host.h"
#include "runtime/registry.h"
#include "runtime/stats_internal.h"
#include "runtime/trace_launch.h"
#if defined(__x86_64__)
#include "kernels/bvh8_trace.h"
#endif

int lt__structure_qbvh_max_nodes = LT_QBVH_MAX_NODES;

typedef struct qbvh_state {
  lt__bvh bvh;  /* the binary tree; its triangles in leaf order are the QBVH's leaves */
  lt__qbvh qbvh;  /* the 4-wide tree, or */
  lt__bvh8 bvh8;  /* the 8-wide one (native, AVX2) */
  int width;      /* 4 or 8: which of the two is traced */
  lt__buffer nodes, tris; /* on the device (on native, the arrays themselves) */
  lt__buffer blocks;      /* the 8-wide tree's triangle blocks (native) */
  lt__buffer verts;       /* the scene's triangles (native 8 wide: any-hit guesses) */
} qbvh_state;

/* The trace kernel's arguments from its one list (kernels/qbvh_trace.h). */
LT__KERNEL_ARGS(trace_args, LT_QBVH_TRACE_ARGS, lt_qbvh_trace_view)
#if defined(__x86_64__)
LT__KERNEL_ARGS(trace8_args, LT_BVH8_TRACE_ARGS, lt_bvh8_trace_view)
#endif

/* The width a structure on ctx traces with: 8 on the native backend of a CPU with AVX2, unless
 * LT_QBVH_WIDTH=4 asks for the 4-wide path (tests and benchmarks compare both); 4 otherwise. */
static int native_width(const lt_context *ctx) {
  if (ctx->kind != LT_DEVICE_NATIVE) return 4;
  const char *forced = getenv("LT_QBVH_WIDTH");
  if (forced && strcmp(forced, "4") == 0) return 4;
#if defined(__x86_64__)
  return lt_bvh8_supported() ? 8 : 4;
#else
  return 4;
#endif
}

static lt_status create(lt_structure *s, lt_stats *stats) {
  qbvh_state *q = s->state;
  lt__sah_config sah = lt__structure_sah(&s->config);
  size_t n = lt_scene_triangle_count(s->scene);
  double start = lt_now_ms();

  /* The binary tree, then its collapse; the binary nodes are not needed after it. The 4-wide
   * tree's limit is checked on both paths, so that a scene behaves the same on every backend. */
  lt_status status = lt__bvh_build_sah(lt_scene_triangles(s->scene), n, &sah, &q->bvh);
  if (status)
    return lt__fail(status, "building the SAH BVH for the QBVH over %zu triangles: %s", n, lt_status_str(status));
  q->width = native_width(s->ctx);
  if (q->width == 8) {
    int count = lt__qbvh_count_nodes(&q->bvh);
    status = count > lt__structure_qbvh_max_nodes ? LT_ERROR_UNSUPPORTED : lt__bvh8_collapse(&q->bvh, &q->bvh8);
  } else {
    status = lt__qbvh_collapse(&q->bvh, lt__structure_qbvh_max_nodes, &q->qbvh);
  }
  if (status == LT_ERROR_UNSUPPORTED)
    return lt__fail(status,
                    "--structure qbvh: the tree over %zu triangles needs %d nodes, more than the %d its 32-bit stack "
                    "entries can name (26 bits; scenes of up to %d triangles always fit): use --structure bvh",
                    n, lt__qbvh_count_nodes(&q->bvh), lt__structure_qbvh_max_nodes, LT_QBVH_MAX_NODES);
  if (status) return lt__fail(status, "collapsing the SAH BVH into a QBVH: %s", lt_status_str(status));
  free(q->bvh.nodes);
  q->bvh.nodes = NULL;

  if (q->width == 8) {
    /* The 8-wide tree has its own triangles (padded leaves) in blocks of four. */
    free(q->bvh.tris);
    q->bvh.tris = NULL;
    status = lt__buffer_wrap(s->ctx, &q->nodes, q->bvh8.nodes, (size_t)q->bvh8.node_count * sizeof(lt_bvh8_node));
    if (!status)
      status = lt__buffer_wrap(s->ctx, &q->blocks, q->bvh8.blocks, (size_t)q->bvh8.tri_slots / 4 * sizeof(lt_tri4));
    /* Any-hit guesses read the scene's triangles (traversal/bvh8_guess.h); none without them. */
    if (!status && lt__ondemand_wide_guesses())
      status = lt__buffer_wrap(s->ctx, &q->verts, lt_scene_triangles(s->scene), n * 9 * sizeof(float));
  } else {
    status = lt__buffer_wrap(s->ctx, &q->nodes, q->qbvh.nodes, (size_t)q->qbvh.node_count * sizeof(lt_qbvh_node));
    if (!status) status = lt__buffer_wrap(s->ctx, &q->tris, q->bvh.tris, (size_t)q->bvh.tri_count * sizeof(lt_tri));
  }
  lt__stats_add(stats, LT_STAT_BUILD_MS, lt_now_ms() - start);
  lt__stats_add(stats, LT_STAT_SORT_OPS, (double)q->bvh.sort_ops);
  return status;
}

static lt_status trace(lt_structure *s, const lt_ray *rays, int count, int flags, lt_hit *hits, lt_stats *stats) {
  qbvh_state *q = s->state;
#if defined(__x86_64__)
  if (q->width == 8) {
    trace8_args args8 = {NULL, NULL, 0, 0, &q->nodes, &q->blocks, &q->verts};
    lt_bvh8_trace_view view8;
    lt__trace_call call8 = {"lt_qbvh_trace", lt__native_bvh8_trace_kernel, trace8_args_set_any, trace8_args_view_any,
                            &args8, &args8.rays, &args8.hits, &args8.ray_count, &args8.flags, &view8};
    return lt__trace_finished(s->ctx, &call8, rays, count, flags, hits, stats);
  }
#endif
  trace_args args = {NULL, NULL, 0, 0, &q->nodes, &q->tris};
  lt_qbvh_trace_view view;
  lt__trace_call call = {"lt_qbvh_trace", lt__native_qbvh_trace_kernel, trace_args_set_any, trace_args_view_any,
                         &args, &args.rays, &args.hits, &args.ray_count, &args.flags, &view};
  return lt__trace_finished(s->ctx, &call, rays, count, flags, hits, stats);
}

static void put_stats(lt_structure *s, lt_stats *stats) {
  qbvh_state *q = s->state;
  int wide = q->width == 8;
  size_t node_bytes = wide ? (size_t)q->bvh8.node_count * sizeof(lt_bvh8_node)
                           : (size_t)q->qbvh.node_count * sizeof(lt_qbvh_node);
  size_t ref_bytes = wide ? (size_t)q->bvh8.tri_slots * (sizeof(lt_tri4) / 4)
                          : (size_t)q->bvh.tri_count * sizeof(lt_tri);
  double nodes = wide ? (double)q->bvh8.node_count + q->bvh8.leaf_count : (double)q->qbvh.node_count + q->qbvh.leaf_count;
  lt__stats_put(stats, LT_STAT_REFERENCES, (double)lt_scene_triangle_count(s->scene));
  lt__stats_put(stats, LT_STAT_NODES_BUILT, nodes);
  lt__stats_put(stats, LT_STAT_NODES_FULL, nodes);
  lt__stats_put(stats, LT_STAT_NODE_BYTES, (double)node_bytes);
  lt__stats_put(stats, LT_STAT_REFERENCE_BYTES, (double)ref_bytes);
  lt__stats_put(stats, LT_STAT_POOL_BYTES, 0);
  lt__stats_put(stats, LT_STAT_MEMORY_BYTES, (double)(node_bytes + ref_bytes));
  lt__stats_put(stats, LT_STAT_MAX_DEPTH, wide ? q->bvh8.max_depth : q->qbvh.max_depth);
  lt__stats_put(stats, LT_STAT_SAH_COST, q->bvh.sah_cost);
}

static void release(lt_structure *s) {
  qbvh_state *q = s->state;
  lt__buffer_release(&q->nodes);
  lt__buffer_release(&q->tris);
  lt__buffer_release(&q->blocks);
  lt__buffer_release(&q->verts);
  lt__qbvh_free(&q->qbvh);
  lt__bvh8_free(&q->bvh8);
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
