/* The host half of the on-demand BVH (see ondemand_internal.h). */
#include <stdlib.h>
#include <string.h>

#include "builders/host/morton.h"
#include "kernels/bvh_ondemand.h"
#include "kernels/native_kernels.h"
#include "runtime/context_internal.h"
#include "runtime/error.h"
#include "runtime/bvh_ondemand_host.h"
#include "runtime/kernel_args_host.h"
#include "runtime/persistent_launch.h"
#include "runtime/stats_internal.h"
#include "runtime/triangle_boxes.h"

/* Bin slabs: how many large nodes may bin at once; a node that finds none is split in one go
 * by one work-item. Tests set it to 0 to take that path always. */
int lt__ondemand_slab_count = 64;

static lt_status launch(lt__ondemand *od, lt__buffer *rays, lt__buffer *hits, int count, int flags, int speculate,
                        int setup, int answered);
static lt_status read_counters(lt__ondemand *od, lt_stats *stats);

/* A per-frame array that a scene rebuilt every frame would otherwise fault in again every frame:
 * on native, host memory kept on the context (taken here, given back at release); on OpenCL a
 * device buffer like any other. Its contents are undefined. */
static lt_status per_frame_buffer(lt__ondemand *od, int slot, lt__buffer *buffer, size_t bytes) {
  lt_context *ctx = od->ctx;
  if (ctx->kind != LT_DEVICE_NATIVE) return lt__buffer_create(ctx, buffer, bytes, NULL, LT_BUFFER_UNINIT);
  void *host = lt__context_take(ctx, slot, bytes, &od->kept_bytes[slot]);
  if (!host) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory for a %zu-byte array", bytes);
  lt_status status = lt__buffer_wrap(ctx, buffer, host, bytes);
  if (status) lt__context_give(ctx, slot, host, od->kept_bytes[slot]);
  else od->kept[slot] = host;
  return status;
}

/* The Morton top's buffers: the triangles in code order go into both index and scratch (the
 * partitions' ping-pong, see builders/bvh_task.h), beside the sorted codes and block boxes. The
 * sort runs on one host thread per work-group, at most one per core. */
static lt_status morton_order(lt__ondemand *od, const float *boxes, int *index) {
  lt_context *ctx = od->ctx;
  size_t n = (size_t)od->count, blocks = lt__morton_block_count(n);
  od->morton_blocks = (od->count + LT_BVH_MORTON_BLOCK - 1) / LT_BVH_MORTON_BLOCK;
  lt_status status = per_frame_buffer(od, LT__KEEP_CODES, &od->codes, n * 4);
  if (!status) status = per_frame_buffer(od, LT__KEEP_BLOCKS, &od->block_boxes, blocks * 8 * sizeof(float));
  if (status) return status;
  uint32_t *codes = lt__buffer_begin_write(ctx, &od->codes);
  float *block_boxes = lt__buffer_begin_write(ctx, &od->block_boxes);
  int *scratch = lt__buffer_begin_write(ctx, &od->scratch);
  int workers = lt_context_work_groups(ctx), cores = lt__native_threads();
  lt__executor executor = {workers < cores ? workers : cores, lt__native_run};
  size_t work_bytes;
  void *work = lt__context_take(ctx, LT__KEEP_SORT, lt__morton_work_bytes(n), &work_bytes);
  status = codes && block_boxes && scratch && work ? LT_OK
                                                   : lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory for a Morton order");
  if (!status)
    status =
        lt__morton_order(boxes, n, &od->bounds, &executor, work, codes, (int32_t *)index, block_boxes, &od->sort_ops);
  if (!status) memcpy(scratch, index, n * sizeof *index);
  lt__context_give(ctx, LT__KEEP_SORT, work, work_bytes);
  /* Always hand the staging copies back, whatever happened. */
  lt_status uploaded = codes ? lt__buffer_end_write(ctx, &od->codes, codes) : LT_OK;
  if (!status) status = uploaded;
  uploaded = block_boxes ? lt__buffer_end_write(ctx, &od->block_boxes, block_boxes) : LT_OK;
  if (!status) status = uploaded;
  uploaded = scratch ? lt__buffer_end_write(ctx, &od->scratch, scratch) : LT_OK;
  return status ? status : uploaded;
}

lt_status lt__ondemand_create(lt_context *ctx, const lt_scene *scene, const lt__sah_config *sah, int mode,
                              int pool_capacity, int node_capacity, int morton_above, lt__ondemand *od) {
  memset(od, 0, sizeof *od);
  od->ctx = ctx;
  od->count = (int)lt_scene_triangle_count(scene);
  od->slab_count = lt__ondemand_slab_count > 0 ? lt__ondemand_slab_count : 0;
  od->sah = *sah;
  od->morton_above = morton_above > 0 && morton_above < od->count ? morton_above : od->count;
  od->wide_on = lt__ondemand_wide_wanted(ctx, mode);
  od->wide_stride = lt__ondemand_wide_stride();
  od->wide_guesses = lt__ondemand_wide_guesses();
  if (sah->bins > LT_MAX_BINS) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "at most %d SAH bins", LT_MAX_BINS);
  /* Device buffers: the scene's triangles as they are (no copy on native), their boxes,
   * references, partition room, nodes, bin slabs, counters. */
  lt_pool_config config = {pool_capacity, 0, 0, 0, 0, 0};
  size_t n = (size_t)od->count;
  lt_status status = lt__pool_create(ctx, &config, mode, &od->pool);
  if (!status) status = lt__heap_create(ctx, &od->node_heap, node_capacity);
  if (!status) status = lt__buffer_wrap(ctx, &od->verts, lt_scene_triangles(scene), n * 9 * sizeof(float));
  if (!status) status = per_frame_buffer(od, LT__KEEP_BOXES, &od->prim_boxes, n * 8 * sizeof(float));
  if (!status) status = per_frame_buffer(od, LT__KEEP_INDEX, &od->index, n * 4);
  if (!status) status = per_frame_buffer(od, LT__KEEP_SCRATCH, &od->scratch, n * 4);
  if (!status) {
    float *boxes = lt__buffer_begin_write(ctx, &od->prim_boxes);
    int *index = lt__buffer_begin_write(ctx, &od->index);
    status = boxes && index ? LT_OK : lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory for %zu triangles", n);
    if (!status) status = lt__triangle_boxes(scene, boxes, &od->bounds);
    if (!status && od->morton_above < od->count) status = morton_order(od, boxes, index);
    for (int i = 0; !status && od->morton_above == od->count && i < od->count; i++) index[i] = i;
    /* Always hand the staging copies back (OpenCL frees them), whatever happened. */
    lt_status uploaded = boxes ? lt__buffer_end_write(ctx, &od->prim_boxes, boxes) : LT_OK;
    if (!status) status = uploaded;
    uploaded = index ? lt__buffer_end_write(ctx, &od->index, index) : LT_OK;
    if (!status) status = uploaded;
  }
  if (!status) status = lt__buffer_create(ctx, &od->side, n * 4, NULL, LT_BUFFER_UNINIT);
  if (!status && od->morton_above == od->count) status = lt__buffer_create(ctx, &od->codes, 16, NULL, 0);
  if (!status && od->morton_above == od->count) status = lt__buffer_create(ctx, &od->block_boxes, 32, NULL, 0);
  if (!status) status = lt__buffer_create(ctx, &od->chunk_left, n * 4, NULL, LT_BUFFER_UNINIT);
  if (!status)
    status = lt__buffer_create(ctx, &od->nodes, (size_t)node_capacity * sizeof(lt_bvh_node), NULL, LT_BUFFER_UNINIT);
  if (!status) status = lt__buffer_create(ctx, &od->slabs, (size_t)(od->slab_count + 1) * LT_BVH_SLAB_SIZE * 4, NULL, 0);
  if (!status) status = lt__buffer_create(ctx, &od->slab_used, (size_t)(od->slab_count + 1) * 4, NULL, 0);
  if (!status)
    status = lt__buffer_create(ctx, &od->counters, (size_t)ctx->work_groups * LT_BVH_STAT_COUNT * 4, NULL, 0);
  if (status) {
    lt__ondemand_release(od);
    return status;
  }

  /* Node 0, the super-root, and the root's task (or leaf), made on the device by the same
   * spawn as every other node. */
  lt__buffer none;
  if (!status) status = lt__buffer_create(ctx, &none, 16, NULL, 0);
  if (!status) {
    status = launch(od, &none, &none, 0, 0, 0, 1, 0);
    lt__buffer_release(&none);
  }
  if (!status) status = lt__pool_end_launch(&od->pool, NULL); /* a full pool, said as such */
  if (!status) status = read_counters(od, NULL);
  if (status) lt__ondemand_release(od);
  return status;
}

void lt__ondemand_release(lt__ondemand *od) {
  lt__pool_release(&od->pool);
  lt__heap_release(&od->node_heap);
  lt__buffer *buffers[] = {&od->verts, &od->prim_boxes, &od->side,  &od->index,   &od->scratch,
                           &od->chunk_left, &od->nodes, &od->slabs, &od->slab_used, &od->counters,
                           &od->codes,      &od->block_boxes};
  for (size_t i = 0; i < sizeof buffers / sizeof buffers[0]; i++) lt__buffer_release(buffers[i]);
  lt__bvh8_free(&od->wide);
  for (int slot = 0; slot < 8; slot++)
    if (od->kept[slot]) lt__context_give(od->ctx, slot, od->kept[slot], od->kept_bytes[slot]), od->kept[slot] = NULL;
}

/* The kernel's arguments from its one list (kernels/bvh_ondemand.h). */
LT__KERNEL_ARGS(od_args, LT_OD_ARGS, lt_od_args)

/* The arguments and, natively, the wide tree, which are no kernel argument: the native
 * view gets them beside the list's (args first, so that od_args_set_any reads it as od_args). */
typedef struct od_launch_args {
  od_args args;
  const void *wide; /* an lt_bvh_wide_view, or NULL */
  int answered;     /* the stride of the rays whose hits are in already, or 0 */
} od_launch_args;

static void od_view_any(const void *launch_args, void *view) {
  const od_launch_args *l = launch_args;
  od_args_view(&l->args, view);
#if LT_BVH_WIDE
  ((lt_od_args *)view)->wide = l->wide;
  ((lt_od_args *)view)->answered = l->answered;
#endif
}

/* One launch on either backend: the set-up launch (work-group 0 makes the root) or the persistent loop
 * over `count` rays (exactly as many work-groups as run at once: they wait on each other). */
static lt_status launch(lt__ondemand *od, lt__buffer *rays, lt__buffer *hits, int count, int flags, int speculate,
                        int setup, int answered) {
  lt_context *ctx = od->ctx;
  od_launch_args launch_args = {.wide = NULL, .answered = answered};
  od_args args;
  LT__POOL_HOST_ARGS(&args, &od->pool);
  LT__HEAP_HOST_ARGS(&args, node_heap, &od->node_heap);
  args.verts = &od->verts, args.prim_boxes = &od->prim_boxes, args.side = &od->side, args.index = &od->index;
  args.scratch = &od->scratch, args.chunk_left = &od->chunk_left, args.nodes = &od->nodes;
  args.slabs = &od->slabs, args.slab_used = &od->slab_used, args.counters = &od->counters;
  args.codes = &od->codes, args.block_boxes = &od->block_boxes;
  args.morton_above = od->morton_above, args.morton_blocks = od->morton_blocks;
  args.task_kind = 0; /* the kernel numbers its own task kinds */
  args.slab_count = od->slab_count, args.max_leaf = od->sah.max_leaf_size, args.bins = od->sah.bins;
  args.traversal_cost = od->sah.traversal_cost, args.intersection_cost = od->sah.intersection_cost;
  args.rays = rays, args.hits = hits, args.ray_count = count, args.flags = flags;
  args.max_idle_polls = od->pool.config.max_idle_polls, args.speculate = speculate, args.prim_count = od->count;
  args.root_lo = (lt_float4){od->bounds.lo[0], od->bounds.lo[1], od->bounds.lo[2], 0.0f};
  args.root_hi = (lt_float4){od->bounds.hi[0], od->bounds.hi[1], od->bounds.hi[2], 0.0f};
  launch_args.args = args;
#if LT_BVH_WIDE
  /* Rays start on the wide tree where the root is wide (runtime/bvh_wide_host.c). */
  lt_bvh_wide_view wide = {od->wide.nodes, od->wide.blocks, -1, od->verts.host, od->wide_guesses};
  if (od->wide.node_count > 0) {
    lt_i32 link, count;
    if (lt_bvh_child(&((const lt_bvh_node *)od->nodes.host)[0], 0, &link, &count) == LT_CHILD_INNER &&
        lt_bvh_child_is_wide(count))
      wide.root = lt_bvh_wide_node(count);
    launch_args.wide = &wide;
  }
#endif
  static const lt__persistent_kernel kernel = {"lt_bvh_ondemand", lt__native_bvh_ondemand_kernel, od_args_set_any,
                                               od_view_any};
  lt_od_args view;
  return lt__persistent_launch(ctx, &kernel, &launch_args, &view, setup, &od->pool.control,
                                       od->pool.config.max_stall_seconds);
}

/* Adds the launch's build and traversal counters, summed over the work-groups, to stats and
 * to the tree's totals, and clears them for the next launch. */
static lt_status read_counters(lt__ondemand *od, lt_stats *stats) {
  static const int stat_of[LT_BVH_STAT_COUNT] = {
#define LT_BVH_STAT_TARGET(id, stat) stat,
      LT_BVH_STAT_LIST(LT_BVH_STAT_TARGET)
#undef LT_BVH_STAT_TARGET
  };
  lt_context *ctx = od->ctx;
  size_t words = (size_t)ctx->work_groups * LT_BVH_STAT_COUNT;
  lt_u32 *counters = malloc(words * sizeof *counters);
  if (!counters) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory reading counters");
  lt_status status = lt__buffer_read(ctx, &od->counters, 0, words * 4, counters);
  double sum[LT_BVH_STAT_COUNT] = {0};
  for (size_t w = 0; !status && w < words; w++) sum[w % LT_BVH_STAT_COUNT] += counters[w];
  free(counters);
  if (status) return status;
  od->leaves += sum[LT_BVH_STAT_LEAVES];
  od->sort_ops += sum[LT_BVH_STAT_SORT_OPS];
  for (int k = 0; k < LT_BVH_STAT_COUNT; k++)
    if (stat_of[k] != LT_STAT_NONE) lt__stats_add(stats, (lt_stat_id)stat_of[k], sum[k]);
  return lt__buffer_fill(ctx, &od->counters, 0);
}

/* One launch over the batch (its counters all count); `answered`: natively, the stride of the
 * rays whose hits are in already (0: none). */
static lt_status launch_batch(lt__ondemand *od, const lt_ray *rays, int count, int flags, lt_hit *hits,
                              int speculate, lt_stats *stats, int answered) {
  lt_context *ctx = od->ctx;
  lt__buffer ray_buf, hit_buf;
  /* Before rays are traced again, what the last launches finished becomes wide (counted in
   * this launch's time); a re-trace of the same rays for statistics holds it back, so that its
   * collapse is not hidden from the next launch's time. */
  lt_status status = count > 0 && !od->wide_hold ? lt__ondemand_widen(od) : LT_OK;
  if (status) return status;
  status = lt__batch_buffers_begin(ctx, &ray_buf, &hit_buf, rays, count, hits);
  if (status) return status;
  status = lt__pool_begin_launch(&od->pool);
  if (!status) status = launch(od, &ray_buf, &hit_buf, count, flags, speculate, 0, answered);
  if (!status) status = lt__pool_end_launch(&od->pool, stats);
  status = lt__batch_buffers_end(ctx, &ray_buf, &hit_buf, hits, count, status);
  if (!status) status = read_counters(od, stats);
  return status;
}

lt_status lt__ondemand_launch(lt__ondemand *od, const lt_ray *rays, int count, int flags, lt_hit *hits,
                              int speculate, lt_stats *stats) {
  int stride = od->wide_on && !od->wide_hold ? lt__ondemand_wide_sample(od->wide_stride, count) : 0;
  if (stride == 0) return launch_batch(od, rays, count, flags, hits, speculate, stats, 0);
  /* Every stride-th ray first: it has the pool build most of what the batch needs, which the
   * whole batch's launch then crosses on the wide layout (runtime/bvh_wide_host.c). The
   * sample's answers go straight into hits (the native backend's launch writes the caller's
   * array), and the batch's launch skips those rays instead of tracing them again. The sample
   * is traced the same way, its own sample first while it is large enough: a ray that meets
   * nodes still to be built crosses the binary tree and waits, several times a ray that meets
   * a collapsed tree costs, so the fewer rays come before the first collapse the better, and
   * each stage after it runs mostly wide on what the stage before built. */
  size_t n = ((size_t)count + (size_t)stride - 1) / (size_t)stride; /* count >= 1024 * stride, stride > 1 */
  lt_ray *sample = malloc(n * sizeof *sample);
  lt_hit *sample_hits = malloc(n * sizeof *sample_hits);
  lt_status status = sample && sample_hits ? LT_OK : lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory for a ray sample");
  for (size_t i = 0; !status && i < n; i++) sample[i] = rays[i * (size_t)stride];
  if (!status) status = lt__ondemand_launch(od, sample, (int)n, flags, sample_hits, speculate, stats);
  for (size_t i = 0; !status && i < n; i++) hits[i * (size_t)stride] = sample_hits[i];
  free(sample);
  free(sample_hits);
  return status ? status : launch_batch(od, rays, count, flags, hits, speculate, stats, stride);
}

int lt__ondemand_heap_full(lt__ondemand *od) {
  int used, exhausted;
  return lt__heap_used(od->ctx, &od->node_heap, &used, &exhausted) == LT_OK && exhausted;
}

lt_status lt__ondemand_nodes_built(lt__ondemand *od, double *nodes) {
  int used, exhausted;
  lt_status status = lt__heap_used(od->ctx, &od->node_heap, &used, &exhausted);
  if (!status) *nodes = (double)(used - 1) + od->leaves;
  return status;
}

lt_status lt__ondemand_snapshot(lt__ondemand *od, lt_bvh_node **nodes, int *node_count, int **index) {
  int exhausted;
  lt_status status = lt__heap_used(od->ctx, &od->node_heap, node_count, &exhausted);
  if (status) return status;
  *nodes = malloc((size_t)*node_count * sizeof **nodes);
  *index = malloc((size_t)od->count * sizeof **index);
  if (!*nodes || !*index) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory copying a tree");
  status = lt__buffer_read(od->ctx, &od->nodes, 0, (size_t)*node_count * sizeof **nodes, *nodes);
  return status ? status : lt__buffer_read(od->ctx, &od->index, 0, (size_t)od->count * 4, *index);
}

double lt__ondemand_bytes(const lt__ondemand *od, double *node_bytes, double *reference_bytes, double *pool_bytes) {
  /* The wide tree's nodes and its own triangles (in blocks of four) count too: room held. */
  *node_bytes = (double)od->nodes.bytes + (double)od->wide.node_capacity * sizeof(lt_bvh8_node);
  *reference_bytes = (double)od->index.bytes + (double)od->wide.slot_capacity * (sizeof(lt_tri4) / 4);
  *pool_bytes = (double)(od->pool.headers.bytes + od->pool.tasks.bytes + od->pool.empty_cache.bytes +
                         od->pool.priority_cache.bytes + od->pool.control.bytes + od->slabs.bytes);
  return *node_bytes + *reference_bytes + *pool_bytes + od->prim_boxes.bytes + od->side.bytes +
         od->scratch.bytes + od->chunk_left.bytes + od->codes.bytes + od->block_boxes.bytes;
}
