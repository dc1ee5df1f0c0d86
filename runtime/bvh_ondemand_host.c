/* The host half of the on-demand BVH (see ondemand_internal.h). */
#include <stdlib.h>
#include <string.h>

#include "builders/bvh_task.h"
#include "kernels/bvh_ondemand.h"
#include "kernels/native_kernels.h"
#include "runtime/error.h"
#include "runtime/bvh_ondemand_host.h"
#include "runtime/stats_internal.h"
#include "scenes/scene_internal.h"

/* Bin slabs: how many large nodes may bin at once; a node that finds none is split in one go
 * by one work-item. Tests set it to 0 to take that path always. */
int lt__ondemand_slab_count = 64;

#define MAX_BOX_THREADS 64

/* Each triangle's box, written where `boxes` points (8 floats: lo xyz 0, hi xyz 0), by one
 * host thread per slice of the scene, each bounding its slice. */
typedef struct box_job {
  const lt_scene *scene;
  float *boxes;
  int threads;
  lt_box bounds[MAX_BOX_THREADS];
} box_job;

static void box_slice(void *arg) {
  box_job *job = arg;
  int t = lt__native_group_id;
  size_t n = job->scene->count, begin = n * t / job->threads, end = n * (t + 1) / job->threads;
  lt_v4 inf = lt_v4_splat(INFINITY), ninf = lt_v4_splat(-INFINITY);
  lt_v4 blo = inf, bhi = ninf;
  lt_v4 *boxes = (lt_v4 *)job->boxes;
  for (size_t i = begin; i < end; i++) {
    lt_v4 lo, hi;
    lt_tri_box4(job->scene->tris + 9 * i, &lo, &hi);
    boxes[2 * i] = lo, boxes[2 * i + 1] = hi;
    blo = lt_v4_min(lo, blo), bhi = lt_v4_max(hi, bhi);
  }
  job->bounds[t] = lt_box_of4(blo, bhi);
}

/* The boxes and the root's bounds. */
static lt_status triangle_boxes(const lt_scene *scene, float *boxes, lt_box *bounds) {
  box_job job;
  int threads = lt__native_threads();
  job.scene = scene, job.boxes = boxes;
  job.threads = threads < 1 ? 1 : threads > MAX_BOX_THREADS ? MAX_BOX_THREADS : threads;
  if (scene->count < 65536) job.threads = 1;
  lt_status status = lt__native_run(job.threads, box_slice, &job);
  *bounds = lt_box_empty();
  for (int t = 0; !status && t < job.threads; t++) lt_box_grow(bounds, &job.bounds[t]);
  return status;
}

static lt_status warm_up_launch(void *user, lt__buffer *scratch);

lt_status lt__ondemand_create(lt_context *ctx, const lt_scene *scene, const lt__sah_config *sah, int mode,
                              int pool_capacity, int node_capacity, lt__ondemand *od) {
  memset(od, 0, sizeof *od);
  od->ctx = ctx;
  od->count = (int)scene->count;
  od->node_capacity = node_capacity;
  od->slab_count = lt__ondemand_slab_count > 0 ? lt__ondemand_slab_count : 0;
  od->sah = *sah;
  if (sah->bins > LT_MAX_BINS) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "at most %d SAH bins", LT_MAX_BINS);
  /* Device buffers: the scene's triangles as they are (no copy on native), their boxes,
   * references, partition room, nodes, bin slabs, counters. */
  lt_pool_config config = {pool_capacity, 0, 0, 0, 0};
  size_t n = scene->count;
  lt_box bounds;
  lt_status status = lt__pool_create(ctx, &config, mode, &od->pool);
  if (!status) status = lt__buffer_wrap(ctx, &od->verts, scene->tris, n * 9 * sizeof(float));
  if (!status) status = lt__buffer_create(ctx, &od->prim_boxes, n * 8 * sizeof(float), NULL, LT_BUFFER_UNINIT);
  if (!status) status = lt__buffer_create(ctx, &od->index, n * 4, NULL, LT_BUFFER_UNINIT);
  if (!status) {
    float *boxes = lt__buffer_begin_write(ctx, &od->prim_boxes);
    int *index = lt__buffer_begin_write(ctx, &od->index);
    status = boxes && index ? LT_OK : lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory for %zu triangles", n);
    if (!status) status = triangle_boxes(scene, boxes, &bounds);
    for (int i = 0; !status && i < od->count; i++) index[i] = i;
    /* Always hand the staging copies back (OpenCL frees them), whatever happened. */
    lt_status uploaded = boxes ? lt__buffer_end_write(ctx, &od->prim_boxes, boxes) : LT_OK;
    if (!status) status = uploaded;
    uploaded = index ? lt__buffer_end_write(ctx, &od->index, index) : LT_OK;
    if (!status) status = uploaded;
  }
  if (!status) status = lt__buffer_create(ctx, &od->side, n * 4, NULL, LT_BUFFER_UNINIT);
  if (!status) status = lt__buffer_create(ctx, &od->scratch, n * 4, NULL, LT_BUFFER_UNINIT);
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

  /* Node 0: the super-root; its left child is the scene's root, built by the task in slot 0
   * (a single triangle is a leaf at once). */
  lt_bvh_node root;
  lt_box empty = lt_box_empty();
  memset(&root, 0, sizeof root);
  lt_bvh_set_child(&root, 0, &bounds, od->count == 1 ? 0 : lt_bvh_unbuilt_link(0), od->count == 1 ? 1 : 0);
  lt_bvh_set_child(&root, 1, &empty, -1, 0);
  if (!status) status = lt__buffer_write(ctx, &od->nodes, 0, sizeof root, &root);
  lt_pool_control control = {0};
  control.nodes_next = 1;
  if (!status) status = lt__buffer_write(ctx, &od->pool.control, 0, sizeof control, &control);
  if (!status && od->count > 1) {
    int one_go = ctx->kind == LT_DEVICE_NATIVE ? LT_BVH_ONE_GO : LT_BVH_CHUNK; /* as lt_bvh_spawn */
    lt_task task = {0, od->count, 0, od->count <= one_go ? LT_BVH_SMALL : LT_BVH_INIT, 1, 0, 0, 0, {0}};
    for (int k = 0; k < 3; k++) {
      task.work[W_BOUNDS + k] = lt_float_as_int(bounds.lo[k]);
      task.work[W_BOUNDS + 3 + k] = lt_float_as_int(bounds.hi[k]);
    }
    status = lt__pool_insert_root(&od->pool, 0, 0, 0, od->count, 1);
    if (!status) status = lt__buffer_write(ctx, &od->pool.tasks, 0, sizeof task, &task);
  }
  if (od->count == 1) od->leaves = 1;
  if (!status && ctx->kind == LT_DEVICE_OPENCL && !ctx->ondemand_warm) {
    status = lt__pool_warm_up(&od->pool, warm_up_launch, od);
    ctx->ondemand_warm = 1;
  }
  if (status) lt__ondemand_release(od);
  return status;
}

void lt__ondemand_release(lt__ondemand *od) {
  lt__pool_release(&od->pool);
  lt__buffer *buffers[] = {&od->verts, &od->prim_boxes, &od->side,  &od->index,   &od->scratch,
                           &od->chunk_left, &od->nodes, &od->slabs, &od->slab_used, &od->counters};
  for (size_t i = 0; i < sizeof buffers / sizeof buffers[0]; i++) lt__buffer_release(buffers[i]);
}

/* Arguments after the pool's nine, in the order of lt_bvh_ondemand in kernels/bvh_ondemand.cl. */
static lt_status launch_opencl(lt__ondemand *od, lt__buffer *rays, lt__buffer *hits, cl_int4 trace) {
  lt_context *ctx = od->ctx;
  cl_kernel k = ctx->ondemand_kernel;
  cl_int4 sizes = {{od->slab_count, od->node_capacity, od->sah.max_leaf_size, od->sah.bins}};
  cl_float2 costs = {{od->sah.traversal_cost, od->sah.intersection_cost}};
  lt_status status = lt__pool_set_args(&od->pool, k);
  if (status) return status;
  lt__buffer *buffers[] = {&od->verts, &od->prim_boxes, &od->side,  &od->index,   &od->scratch,
                           &od->chunk_left, &od->nodes, &od->slabs, &od->slab_used, &od->counters};
  cl_int err = CL_SUCCESS;
  for (int i = 0; i < 10; i++) err |= clSetKernelArg(k, 9 + i, sizeof(cl_mem), &buffers[i]->mem);
  err |= clSetKernelArg(k, 19, sizeof sizes, &sizes);
  err |= clSetKernelArg(k, 20, sizeof costs, &costs);
  err |= clSetKernelArg(k, 21, sizeof(cl_mem), &rays->mem);
  err |= clSetKernelArg(k, 22, sizeof(cl_mem), &hits->mem);
  err |= clSetKernelArg(k, 23, sizeof trace, &trace);
  if ((status = lt__opencl_check(err, "setting on-demand kernel arguments"))) return status;

  /* Exactly as many work-groups as run at once: persistent groups wait on each other. */
  size_t local = (size_t)ctx->local_size, global = local * (size_t)ctx->work_groups;
  err = clEnqueueNDRangeKernel(ctx->queue, k, 1, NULL, &global, &local, 0, NULL, NULL);
  if (err == CL_SUCCESS) err = clFinish(ctx->queue);
  return lt__opencl_check(err, "running the on-demand kernel");
}

static lt_status launch_native(lt__ondemand *od, lt__buffer *rays, lt__buffer *hits, cl_int4 trace) {
  lt_od_trace_args a;
  a.build = (lt_bvh_build){lt__pool_native_view(&od->pool), od->verts.host, od->prim_boxes.host, od->side.host,
                           od->index.host, od->scratch.host,
                           od->chunk_left.host, od->nodes.host, od->slabs.host, od->slab_used.host,
                           od->counters.host, od->slab_count, od->node_capacity, od->sah.max_leaf_size,
                           od->sah.bins, od->sah.traversal_cost, od->sah.intersection_cost};
  a.rays = rays->host, a.hits = hits->host;
  a.ray_count = trace.s[0], a.any_hit = trace.s[1], a.max_idle_polls = trace.s[2], a.speculate = trace.s[3];
  return lt__native_run(od->ctx->work_groups, lt__native_bvh_ondemand_kernel, &a);
}

/* The warm-up launch (lt__pool_warm_up): no rays. */
static lt_status warm_up_launch(void *user, lt__buffer *scratch) {
  cl_int4 trace = {{0, 0, 1, 0}};
  return launch_opencl(user, scratch, scratch, trace);
}

lt_status lt__ondemand_launch(lt__ondemand *od, const lt_ray *rays, int count, int any_hit, lt_hit *hits,
                              int speculate, lt_stats *stats) {
  lt_context *ctx = od->ctx;
  lt__buffer ray_buf, hit_buf;
  lt_status status = lt__buffer_create(ctx, &ray_buf, (size_t)count * sizeof(lt_ray), rays, 0);
  if (status) return status;
  status = lt__buffer_create(ctx, &hit_buf, (size_t)count * sizeof(lt_hit), NULL, 0);
  if (!status) status = lt__pool_begin_launch(&od->pool);
  if (!status) status = lt__buffer_fill(ctx, &od->counters, 0);
  cl_int4 trace = {{count, any_hit, od->pool.config.max_idle_polls, speculate}};
  if (!status) status = ctx->kind == LT_DEVICE_NATIVE ? launch_native(od, &ray_buf, &hit_buf, trace)
                                                      : launch_opencl(od, &ray_buf, &hit_buf, trace);
  if (!status) status = lt__pool_end_launch(&od->pool, stats);
  if (!status && count) status = lt__buffer_read(ctx, &hit_buf, 0, (size_t)count * sizeof(lt_hit), hits);

  /* Build and traversal counters of the launch, summed over the work-groups. */
  lt_u32 *counters = malloc((size_t)ctx->work_groups * LT_BVH_STAT_COUNT * sizeof *counters);
  if (!status && counters)
    status = lt__buffer_read(ctx, &od->counters, 0, (size_t)ctx->work_groups * LT_BVH_STAT_COUNT * 4, counters);
  for (int g = 0; !status && counters && g < ctx->work_groups; g++) {
    lt_u32 *c = counters + g * LT_BVH_STAT_COUNT;
    od->leaves += c[LT_BVH_STAT_LEAVES];
    od->sort_ops += c[LT_BVH_STAT_SORT_OPS];
    lt__stats_add(stats, LT_STAT_SORT_OPS, c[LT_BVH_STAT_SORT_OPS]);
    lt__stats_add(stats, LT_STAT_TRAVERSAL_STEPS, c[LT_BVH_STAT_STEPS]);
    lt__stats_add(stats, LT_STAT_INTERSECTIONS, c[LT_BVH_STAT_TESTS]);
  }
  free(counters);
  lt__buffer_release(&ray_buf);
  lt__buffer_release(&hit_buf);
  return status;
}

lt_status lt__ondemand_nodes_built(lt__ondemand *od, double *nodes) {
  lt_pool_control control;
  lt_status status = lt__buffer_read(od->ctx, &od->pool.control, 0, sizeof control, &control);
  if (!status) *nodes = (double)(control.nodes_next - 1) + od->leaves;
  return status;
}

lt_status lt__ondemand_snapshot(lt__ondemand *od, lt_bvh_node **nodes, int *node_count, int **index) {
  lt_pool_control control;
  lt_status status = lt__buffer_read(od->ctx, &od->pool.control, 0, sizeof control, &control);
  if (status) return status;
  *node_count = control.nodes_next < od->node_capacity ? control.nodes_next : od->node_capacity;
  *nodes = malloc((size_t)*node_count * sizeof **nodes);
  *index = malloc((size_t)od->count * sizeof **index);
  if (!*nodes || !*index) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory copying a tree");
  status = lt__buffer_read(od->ctx, &od->nodes, 0, (size_t)*node_count * sizeof **nodes, *nodes);
  return status ? status : lt__buffer_read(od->ctx, &od->index, 0, (size_t)od->count * 4, *index);
}

double lt__ondemand_bytes(const lt__ondemand *od, double *node_bytes, double *reference_bytes, double *pool_bytes) {
  *node_bytes = (double)od->nodes.bytes;
  *reference_bytes = (double)od->index.bytes;
  *pool_bytes = (double)(od->pool.headers.bytes + od->pool.tasks.bytes + od->pool.empty_cache.bytes +
                         od->pool.priority_cache.bytes + od->pool.control.bytes + od->slabs.bytes);
  return *node_bytes + *reference_bytes + *pool_bytes + od->prim_boxes.bytes + od->side.bytes +
         od->scratch.bytes + od->chunk_left.bytes;
}
