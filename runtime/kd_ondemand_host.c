/* The host half of the on-demand kd-tree (see kd_ondemand_host.h). */
#include "runtime/kd_ondemand_host.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "kernels/kd_ondemand.h"
#include "kernels/native_kernels.h"
#include "runtime/error.h"
#include "runtime/kernel_args_host.h"
#include "runtime/persistent_launch.h"
#include "runtime/stats_internal.h"
#include "runtime/triangle_boxes.h"

int lt__kd_max_depth(size_t n) {
  double depth = 1.2 * log2(n > 1 ? (double)n : 1.0) + 2.0;
  return depth > LT_KD_MAX_DEPTH ? LT_KD_MAX_DEPTH : (int)depth;
}

static lt_status launch(lt__kd *kd, lt__buffer *rays, lt__buffer *hits, int count, int flags, int speculate, int setup);
static lt_status read_counters(lt__kd *kd, lt_stats *stats);

lt_status lt__kd_create(lt_context *ctx, const lt_scene *scene, const lt__kd_config *config, int mode,
                        int pool_capacity, int node_capacity, int ref_capacity, lt__kd *kd) {
  memset(kd, 0, sizeof *kd);
  kd->ctx = ctx;
  kd->count = (int)lt_scene_triangle_count(scene);
  kd->config = *config;
  if (config->bins > LT_MAX_BINS) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "at most %d SAH bins", LT_MAX_BINS);
  lt_pool_config pool = {pool_capacity, 0, 0, 0, 0, 0};
  size_t n = (size_t)kd->count;
  lt_status status = lt__pool_create(ctx, &pool, mode, &kd->pool);
  if (!status) status = lt__heap_create(ctx, &kd->node_heap, node_capacity);
  if (!status) status = lt__heap_create(ctx, &kd->ref_heap, ref_capacity);
  if (!status) status = lt__buffer_wrap(ctx, &kd->verts, lt_scene_triangles(scene), n * 9 * sizeof(float));
  if (!status) status = lt__buffer_create(ctx, &kd->prim_boxes, n * 8 * sizeof(float), NULL, LT_BUFFER_UNINIT);
  if (!status) {
    float *boxes = lt__buffer_begin_write(ctx, &kd->prim_boxes);
    status = boxes ? lt__triangle_boxes(scene, boxes, &kd->bounds) : lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory for %zu boxes", n);
    lt_status uploaded = boxes ? lt__buffer_end_write(ctx, &kd->prim_boxes, boxes) : LT_OK;
    if (!status) status = uploaded;
  }
  if (!status)
    status = lt__buffer_create(ctx, &kd->nodes, (size_t)node_capacity * sizeof(lt_kd_node), NULL, LT_BUFFER_UNINIT);
  if (!status) status = lt__buffer_create(ctx, &kd->refs, (size_t)ref_capacity * 4, NULL, LT_BUFFER_UNINIT);
  if (!status) status = lt__buffer_create(ctx, &kd->parents, (size_t)node_capacity * 4, NULL, LT_BUFFER_UNINIT);
  if (!status) status = lt__buffer_create(ctx, &kd->cells, (size_t)node_capacity * 24, NULL, LT_BUFFER_UNINIT);
  if (!status)
    status = lt__buffer_create(ctx, &kd->counters, (size_t)ctx->work_groups * LT_KD_STAT_COUNT * 4, NULL, 0);

  /* Node 0, the super-root, and the root's task (or leaf), made on the device. */
  lt__buffer none;
  memset(&none, 0, sizeof none);
  if (!status) status = lt__buffer_create(ctx, &none, 16, NULL, 0);
  if (!status) status = launch(kd, &none, &none, 0, 0, 0, 1);
  lt__buffer_release(&none);
  if (!status) status = lt__pool_end_launch(&kd->pool, NULL);
  if (!status) status = read_counters(kd, NULL);
  if (status) lt__kd_release(kd);
  return status;
}

void lt__kd_release(lt__kd *kd) {
  lt__pool_release(&kd->pool);
  lt__heap_release(&kd->node_heap);
  lt__heap_release(&kd->ref_heap);
  lt__buffer *buffers[] = {&kd->verts, &kd->prim_boxes, &kd->nodes, &kd->refs, &kd->parents, &kd->cells, &kd->counters};
  for (size_t i = 0; i < sizeof buffers / sizeof buffers[0]; i++) lt__buffer_release(buffers[i]);
}

/* The kernel's arguments from its one list (kernels/kd_ondemand.h). */
LT__KERNEL_ARGS(kd_args, LT_KD_ARGS, lt_kd_args)

static lt_status launch(lt__kd *kd, lt__buffer *rays, lt__buffer *hits, int count, int flags, int speculate, int setup) {
  kd_args args;
  LT__POOL_HOST_ARGS(&args, &kd->pool);
  LT__HEAP_HOST_ARGS(&args, node_heap, &kd->node_heap);
  LT__HEAP_HOST_ARGS(&args, ref_heap, &kd->ref_heap);
  args.verts = &kd->verts, args.nodes = &kd->nodes, args.refs = &kd->refs, args.counters = &kd->counters;
  args.parents = &kd->parents, args.cells = &kd->cells, args.prim_boxes = &kd->prim_boxes;
  args.sweep = kd->config.sweep, args.clip = kd->config.clip, args.traversal = kd->config.traversal;
  args.task_kind = 0; /* the kernel numbers its own task kinds */
  args.max_leaf = kd->config.max_leaf, args.bins = kd->config.bins, args.max_depth = kd->config.max_depth;
  args.traversal_cost = kd->config.traversal_cost, args.intersection_cost = kd->config.intersection_cost;
  args.rays = rays, args.hits = hits, args.ray_count = count, args.flags = flags;
  args.max_idle_polls = kd->pool.config.max_idle_polls, args.speculate = speculate, args.prim_count = kd->count;
  args.root_lo = (lt_float4){kd->bounds.lo[0], kd->bounds.lo[1], kd->bounds.lo[2], 0.0f};
  args.root_hi = (lt_float4){kd->bounds.hi[0], kd->bounds.hi[1], kd->bounds.hi[2], 0.0f};
  static const lt__persistent_kernel kernel = {"lt_kd_ondemand", lt__native_kd_ondemand_kernel, kd_args_set_any,
                                               kd_args_view_any};
  lt_kd_args view;
  return lt__persistent_launch(kd->ctx, &kernel, &args, &view, setup, &kd->pool.control,
                               kd->pool.config.max_stall_seconds);
}

/* Adds the launch's counters, summed over the work-groups (the depth as a maximum), to stats
 * and the tree's totals, and clears them for the next launch. */
static lt_status read_counters(lt__kd *kd, lt_stats *stats) {
  static const int stat_of[LT_KD_STAT_COUNT] = {
#define LT_KD_STAT_TARGET(id, stat) stat,
      LT_KD_STAT_LIST(LT_KD_STAT_TARGET)
#undef LT_KD_STAT_TARGET
  };
  lt_context *ctx = kd->ctx;
  size_t words = (size_t)ctx->work_groups * LT_KD_STAT_COUNT;
  lt_u32 *counters = malloc(words * sizeof *counters);
  if (!counters) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory reading counters");
  lt_status status = lt__buffer_read(ctx, &kd->counters, 0, words * 4, counters);
  double sum[LT_KD_STAT_COUNT] = {0};
  for (size_t w = 0; !status && w < words; w++) {
    int k = (int)(w % LT_KD_STAT_COUNT);
    if (k == LT_KD_STAT_DEPTH) kd->depth = (int)counters[w] > kd->depth ? (int)counters[w] : kd->depth;
    else sum[k] += counters[w];
  }
  free(counters);
  if (status) return status;
  kd->leaves += sum[LT_KD_STAT_LEAVES];
  kd->leaf_refs += sum[LT_KD_STAT_LEAF_REFS];
  kd->sort_ops += sum[LT_KD_STAT_SORT_OPS];
  for (int k = 0; k < LT_KD_STAT_COUNT; k++)
    if (stat_of[k] != LT_STAT_NONE) lt__stats_add(stats, (lt_stat_id)stat_of[k], sum[k]);
  return lt__buffer_fill(ctx, &kd->counters, 0);
}

lt_status lt__kd_launch(lt__kd *kd, const lt_ray *rays, int count, int flags, lt_hit *hits, int speculate,
                        lt_stats *stats) {
  lt_context *ctx = kd->ctx;
  lt__buffer ray_buf, hit_buf;
  lt_status status = lt__batch_buffers_begin(ctx, &ray_buf, &hit_buf, rays, count, hits);
  if (status) return status;
  status = lt__pool_begin_launch(&kd->pool);
  if (!status) status = launch(kd, &ray_buf, &hit_buf, count, flags, speculate, 0);
  if (!status) status = lt__pool_end_launch(&kd->pool, stats);
  status = lt__batch_buffers_end(ctx, &ray_buf, &hit_buf, hits, count, status);
  if (!status) status = read_counters(kd, stats);
  return status;
}

void lt__kd_heaps_full(lt__kd *kd, int *nodes_full, int *refs_full) {
  int used;
  *nodes_full = *refs_full = 0;
  lt__heap_used(kd->ctx, &kd->node_heap, &used, nodes_full);
  lt__heap_used(kd->ctx, &kd->ref_heap, &used, refs_full);
}

double lt__kd_nodes_built(lt__kd *kd) {
  int used = 0, exhausted;
  lt__heap_used(kd->ctx, &kd->node_heap, &used, &exhausted);
  return used > 0 ? used - 1 : 0;
}

lt_status lt__kd_snapshot(lt__kd *kd, lt_kd_node **nodes, int *node_count, int **refs, int *ref_count) {
  int exhausted;
  *nodes = NULL, *refs = NULL;
  lt_status status = lt__heap_used(kd->ctx, &kd->node_heap, node_count, &exhausted);
  if (!status) status = lt__heap_used(kd->ctx, &kd->ref_heap, ref_count, &exhausted);
  if (status) return status;
  *nodes = malloc((size_t)(*node_count > 0 ? *node_count : 1) * sizeof **nodes);
  *refs = malloc((size_t)(*ref_count > 0 ? *ref_count : 1) * sizeof **refs);
  if (!*nodes || !*refs) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory copying a tree");
  status = lt__buffer_read(kd->ctx, &kd->nodes, 0, (size_t)*node_count * sizeof **nodes, *nodes);
  return status ? status : lt__buffer_read(kd->ctx, &kd->refs, 0, (size_t)*ref_count * 4, *refs);
}

double lt__kd_bytes(lt__kd *kd, double *node_bytes, double *reference_bytes, double *pool_bytes) {
  int nodes = 0, refs = 0, exhausted;
  lt__heap_used(kd->ctx, &kd->node_heap, &nodes, &exhausted);
  lt__heap_used(kd->ctx, &kd->ref_heap, &refs, &exhausted);
  *node_bytes = (double)nodes * (sizeof(lt_kd_node) + 4 + 24); /* with parent links and cells */
  *reference_bytes = (double)refs * 4.0;
  *pool_bytes = (double)(kd->pool.headers.bytes + kd->pool.tasks.bytes + kd->pool.empty_cache.bytes +
                         kd->pool.priority_cache.bytes + kd->pool.control.bytes);
  return *node_bytes + *reference_bytes + *pool_bytes + (double)kd->prim_boxes.bytes;
}

/* The surface area of a cell stored as lo xyz hi xyz. */
static double cell_area(const float *c) {
  double x = c[3] - c[0], y = c[4] - c[1], z = c[5] - c[2];
  return 2.0 * (x * y + y * z + z * x);
}

lt_status lt__kd_sah_cost(lt__kd *kd, double *cost) {
  int count, exhausted;
  *cost = NAN;
  lt_status status = lt__heap_used(kd->ctx, &kd->node_heap, &count, &exhausted);
  if (status || count < 2) return status;
  lt_kd_node *nodes = malloc((size_t)count * sizeof *nodes);
  float *cells = malloc((size_t)count * 24);
  if (!nodes || !cells) {
    free(nodes), free(cells);
    return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory reading a kd-tree");
  }
  status = lt__buffer_read(kd->ctx, &kd->nodes, 0, (size_t)count * sizeof *nodes, nodes);
  if (!status) status = lt__buffer_read(kd->ctx, &kd->cells, 0, (size_t)count * 24, cells);
  if (!status) {
    /* Every node but the super-root: inner cells cost a step, leaves a test per reference. */
    double root = cell_area(cells + 6), sum = 0;
    for (int i = 1; i < count && root > 0; i++) {
      double a = cell_area(cells + 6 * (size_t)i) / root;
      if (lt_kd_axis(nodes[i].meta) == LT_KD_LEAF_AXIS)
        sum += kd->config.intersection_cost * lt_kd_leaf_count(nodes[i].meta) * a;
      else
        sum += kd->config.traversal_cost * a;
    }
    *cost = sum;
  }
  free(nodes), free(cells);
  return status;
}
