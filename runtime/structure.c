/* Structures: build on the host, upload, and trace batches on the context's backend. */
#include <stdlib.h>
#include <string.h>

#include "builders/host/bvh_sah.h"
#include "builders/host/lbvh.h"
#include "kernels/native_kernels.h"
#include "runtime/context_internal.h"
#include "runtime/error.h"
#include "runtime/stats_internal.h"
#include "runtime/bvh_ondemand_host.h"
#include "runtime/structure_internal.h"
#include "scenes/scene_internal.h"
#include "traversal/ray.h"

struct lt_structure {
  lt_context *ctx;
  lt_structure_config config;
  const lt_scene *scene; /* kept to rebuild with larger buffers when one fills up */
  lt__sah_config sah;

  /* A tree built on the host and traced by the trace kernel (LBVH). */
  int host_built;
  lt__bvh bvh;
  cl_mem nodes; /* OpenCL copies of bvh.nodes and bvh.tris */
  cl_mem tris;

  /* The SAH BVH built through the task pool, fully or on demand. */
  lt__ondemand od;
  int od_live;
  int pool_capacity;

  /* Query flags every trace adds: the triangle test, and internal knobs (structure_internal.h). */
  int flags;
};

static const char *const structure_names[] = {"bvh", "lbvh"};
/* Names a user may give that later issues implement; each is refused with a clear message. */
static const char *const planned_structures[] = {"kdtree", "irgrid", "grid", "qbvh", "escape-bvh", NULL};
static const char *const build_names[] = {"full", "requested", "speculative"};
static const char *const intersect_names[] = {"watertight", "fast"};

const char *lt_structure_kind_name(lt_structure_kind kind) {
  return kind < LT_STRUCTURE_COUNT ? structure_names[kind] : "unknown";
}
const char *lt_build_mode_name(lt_build_mode mode) { return mode <= LT_BUILD_SPECULATIVE ? build_names[mode] : "unknown"; }

lt_status lt_structure_kind_parse(const char *name, lt_structure_kind *out) {
  for (int i = 0; i < LT_STRUCTURE_COUNT; i++)
    if (strcmp(name, structure_names[i]) == 0) return *out = (lt_structure_kind)i, LT_OK;
  for (int i = 0; planned_structures[i]; i++)
    if (strcmp(name, planned_structures[i]) == 0)
      return lt__fail(LT_ERROR_UNSUPPORTED, "--structure %s is not implemented yet (available: bvh, lbvh)", name);
  return lt__fail(LT_ERROR_INVALID_ARGUMENT, "unknown structure '%s' (known: bvh, lbvh; planned: kdtree, irgrid, grid, qbvh)", name);
}

const char *lt_intersect_kind_name(lt_intersect_kind kind) {
  return kind <= LT_INTERSECT_FAST ? intersect_names[kind] : "unknown";
}

lt_status lt_intersect_kind_parse(const char *name, lt_intersect_kind *out) {
  for (int i = 0; i <= LT_INTERSECT_FAST; i++)
    if (strcmp(name, intersect_names[i]) == 0) return *out = (lt_intersect_kind)i, LT_OK;
  return lt__fail(LT_ERROR_INVALID_ARGUMENT, "unknown intersection test '%s' (known: watertight, fast)", name);
}

lt_status lt_build_mode_parse(const char *name, lt_build_mode *out) {
  for (int i = 0; i <= LT_BUILD_SPECULATIVE; i++)
    if (strcmp(name, build_names[i]) == 0) return *out = (lt_build_mode)i, LT_OK;
  return lt__fail(LT_ERROR_INVALID_ARGUMENT, "unknown build mode '%s' (known: full, requested, speculative)", name);
}

static lt_status upload(lt_structure *s) {
  cl_int err;
  size_t node_bytes = (size_t)s->bvh.node_count * sizeof(lt_bvh_node);
  size_t tri_bytes = (size_t)s->bvh.tri_count * sizeof(lt_tri);
  s->nodes = clCreateBuffer(s->ctx->cl, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, node_bytes, s->bvh.nodes, &err);
  if (err != CL_SUCCESS) return lt__opencl_check(err, "uploading BVH nodes");
  s->tris = clCreateBuffer(s->ctx->cl, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, tri_bytes, s->bvh.tris, &err);
  return lt__opencl_check(err, "uploading BVH triangles");
}

#define MAX_POOL (1 << 26)

/* Pool capacity to start from; a full pool doubles it and starts again (never a silent drop). */
static int initial_pool_capacity(size_t triangles) {
  size_t c = triangles / 8;
  return c < 4096 ? 4096 : c > (1u << 22) ? (1 << 22) : (int)c;
}

/* (Re)creates the on-demand tree, and in a full build builds all of it. */
static lt_status start_ondemand(lt_structure *s, lt_stats *stats) {
  if (s->od_live) lt__ondemand_release(&s->od);
  s->od_live = 0;

  /* Setting up (packing triangles and their boxes, allocating) is build time in every mode;
   * the kernel warm-up inside it is compile time and is taken out. */
  double start = lt_now_ms(), compile = s->ctx->compile_ms;
  lt_status status = lt__ondemand_create(s->ctx, s->scene, &s->sah, (int)s->config.build, s->pool_capacity,
                                         (int)s->scene->count + 2, &s->od);
  if (!status) s->od_live = 1;
  if (!status && s->config.build == LT_BUILD_FULL) status = lt__ondemand_launch(&s->od, NULL, 0, 0, NULL, 0, stats);
  lt__stats_add(stats, LT_STAT_BUILD_MS, lt_now_ms() - start - (s->ctx->compile_ms - compile));
  return status;
}

/* Runs `step` again with a pool twice as large, from scratch, while the pool fills up. */
static lt_status with_retry(lt_structure *s, lt_stats *stats, lt_status status) {
  while (status == LT_ERROR_CAPACITY && s->pool_capacity < MAX_POOL) {
    if (!s->ctx->quiet) fprintf(stderr, "lazytrace: %s; retrying with a pool of %d tasks\n", lt_last_error(), 2 * s->pool_capacity);
    s->pool_capacity *= 2;
    status = start_ondemand(s, stats);
  }
  return status;
}

static void put_build_stats(lt_structure *s, lt_stats *stats) {
  lt__stats_text(stats, "structure", lt_structure_kind_name(s->config.kind));
  lt__stats_text(stats, "build", lt_build_mode_name(s->config.build));
  lt__stats_text(stats, "device", s->ctx->name);
  lt__stats_text(stats, "intersect", lt_intersect_kind_name(s->config.intersect));
  lt__stats_put(stats, LT_STAT_TRIANGLES, (double)s->scene->count);
  lt__stats_put(stats, LT_STAT_SKIPPED_TRIANGLES, (double)s->scene->skipped);
  lt__stats_put(stats, LT_STAT_COMPILE_MS, s->ctx->compile_ms);
  lt__stats_put(stats, LT_STAT_REFERENCES, (double)s->scene->count);
  if (s->host_built) {
    size_t node_bytes = (size_t)s->bvh.node_count * sizeof(lt_bvh_node);
    size_t ref_bytes = (size_t)s->bvh.tri_count * sizeof(lt_tri);
    lt__stats_put(stats, LT_STAT_NODES_BUILT, (double)lt__bvh_tree_nodes(&s->bvh));
    lt__stats_put(stats, LT_STAT_NODES_FULL, (double)lt__bvh_tree_nodes(&s->bvh));
    lt__stats_put(stats, LT_STAT_NODE_BYTES, (double)node_bytes);
    lt__stats_put(stats, LT_STAT_REFERENCE_BYTES, (double)ref_bytes);
    lt__stats_put(stats, LT_STAT_POOL_BYTES, 0);
    lt__stats_put(stats, LT_STAT_MEMORY_BYTES, (double)(node_bytes + ref_bytes));
    lt__stats_put(stats, LT_STAT_MAX_DEPTH, s->bvh.max_depth);
    lt__stats_put(stats, LT_STAT_SAH_COST, s->bvh.sah_cost);
    return;
  }
  double nodes = 0, node_bytes, ref_bytes, pool_bytes;
  lt__ondemand_nodes_built(&s->od, &nodes);
  lt__stats_put(stats, LT_STAT_NODES_BUILT, nodes);
  if (s->config.build == LT_BUILD_FULL) lt__stats_put(stats, LT_STAT_NODES_FULL, nodes);
  lt__stats_put(stats, LT_STAT_MEMORY_BYTES, lt__ondemand_bytes(&s->od, &node_bytes, &ref_bytes, &pool_bytes));
  lt__stats_put(stats, LT_STAT_NODE_BYTES, node_bytes);
  lt__stats_put(stats, LT_STAT_REFERENCE_BYTES, ref_bytes);
  lt__stats_put(stats, LT_STAT_POOL_BYTES, pool_bytes);
}

lt_status lt_structure_create(lt_context *ctx, const lt_scene *scene, const lt_structure_config *config,
                              lt_stats *stats, lt_structure **out) {
  lt_structure_config defaults = {LT_STRUCTURE_BVH, LT_BUILD_SPECULATIVE, 16, 32, 1.0f, 0, LT_INTERSECT_WATERTIGHT};
  if (!ctx || !scene || !out) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt_structure_create: NULL argument");
  if (!config) config = &defaults;
  if (config->kind >= LT_STRUCTURE_COUNT) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "unknown structure kind %d", config->kind);
  if ((unsigned)config->intersect > LT_INTERSECT_FAST)
    return lt__fail(LT_ERROR_INVALID_ARGUMENT, "unknown intersection test %d", (int)config->intersect);
  if (config->kind == LT_STRUCTURE_LBVH && config->build != LT_BUILD_FULL)
    return lt__fail(LT_ERROR_UNSUPPORTED, "the LBVH is built in full only (--build full)");
  if (scene->count == 0) return lt__fail(LT_ERROR_EMPTY_SCENE, "the scene has no triangles");

  lt_structure *s = calloc(1, sizeof *s);
  if (!s) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory for a structure");
  s->ctx = ctx;
  s->config = *config;
  s->scene = scene;
  s->pool_capacity = config->pool_capacity > 0 ? config->pool_capacity : initial_pool_capacity(scene->count);
  s->flags = config->intersect == LT_INTERSECT_FAST ? LT_QUERY_FLAG_FAST_TRIANGLES : 0;
  s->sah = lt__sah_config_default();
  if (config->max_leaf_size > 0) s->sah.max_leaf_size = config->max_leaf_size;
  if (config->sah_bins > 0) s->sah.bins = config->sah_bins;
  if (config->traversal_cost > 0) s->sah.traversal_cost = config->traversal_cost;

  /* Kernels compile before the clock starts: compile time is reported apart. */
  lt_status status = ctx->kind == LT_DEVICE_OPENCL ? lt__opencl_program(ctx) : LT_OK;
  if (!status && config->kind == LT_STRUCTURE_LBVH) {
    double start = lt_now_ms();
    s->host_built = 1;
    status = lt__bvh_build_lbvh(scene->tris, scene->count, &s->sah, &s->bvh);
    if (!status && ctx->kind == LT_DEVICE_OPENCL) status = upload(s);
    lt__stats_add(stats, LT_STAT_BUILD_MS, lt_now_ms() - start);
    lt__stats_add(stats, LT_STAT_SORT_OPS, (double)s->bvh.sort_ops);
  } else if (!status) {
    status = with_retry(s, stats, start_ondemand(s, stats));
  }
  if (status) {
    lt_structure_destroy(s);
    return status;
  }
  if (stats) put_build_stats(s, stats);
  *out = s;
  return LT_OK;
}

lt__ondemand *lt__structure_ondemand(lt_structure *s) { return s->od_live ? &s->od : NULL; }

lt_status lt__structure_from_bvh(lt_context *ctx, const lt_scene *scene, lt__bvh *bvh, lt_structure **out) {
  if (!ctx || !scene || !bvh || !out) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt__structure_from_bvh: NULL argument");
  lt_structure *s = calloc(1, sizeof *s);
  if (!s) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory for a structure");
  s->ctx = ctx;
  s->config = (lt_structure_config){LT_STRUCTURE_BVH, LT_BUILD_FULL, 16, 32, 1.0f, 0, LT_INTERSECT_WATERTIGHT};
  s->scene = scene;
  s->host_built = 1;
  s->bvh = *bvh;
  memset(bvh, 0, sizeof *bvh);
  lt_status status = ctx->kind == LT_DEVICE_OPENCL ? lt__opencl_program(ctx) : LT_OK;
  if (!status && ctx->kind == LT_DEVICE_OPENCL) status = upload(s);
  if (status) {
    lt_structure_destroy(s);
    return status;
  }
  *out = s;
  return LT_OK;
}

void lt__structure_set_flags(lt_structure *s, int flags) { s->flags |= flags & ~LT_QUERY_FLAG_ANY; }

int lt__structure_flags(const lt_structure *s, int query) {
  return s->flags | (query == LT_QUERY_ANY ? LT_QUERY_FLAG_ANY : 0);
}

void lt_structure_destroy(lt_structure *s) {
  if (!s) return;
  if (s->nodes) clReleaseMemObject(s->nodes);
  if (s->tris) clReleaseMemObject(s->tris);
  if (s->od_live) lt__ondemand_release(&s->od);
  lt__bvh_free(&s->bvh);
  free(s);
}

/* One launch of the trace kernel over all rays on the OpenCL device. */
static lt_status trace_opencl(lt_structure *s, const lt_ray *rays, int count, int flags, lt_hit *hits,
                              uint64_t *steps, uint64_t *tests) {
  lt_context *ctx = s->ctx;
  size_t local = (size_t)ctx->local_size;
  size_t groups = ((size_t)count + local - 1) / local;
  cl_int err;
  cl_mem ray_buf = clCreateBuffer(ctx->cl, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, count * sizeof(lt_ray),
                                  (void *)rays, &err);
  cl_mem hit_buf = clCreateBuffer(ctx->cl, CL_MEM_WRITE_ONLY, count * sizeof(lt_hit), NULL, &err);
  lt_u32 *counters = calloc(2 * groups, sizeof *counters);
  cl_mem counter_buf = clCreateBuffer(ctx->cl, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, 2 * groups * sizeof(lt_u32),
                                      counters, &err);
  int error = 0;
  cl_mem error_buf = clCreateBuffer(ctx->cl, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, sizeof error, &error, &err);
  lt_status status = LT_OK;
  if (!ray_buf || !hit_buf || !counter_buf || !error_buf || !counters) {
    status = lt__fail(LT_ERROR_DEVICE_MEMORY, "could not allocate device buffers for %d rays", count);
    goto done;
  }

  /* Arguments in the order of lt_trace_bvh in kernels/trace.cl. */
  cl_kernel k = ctx->trace_kernel;
  err = clSetKernelArg(k, 0, sizeof ray_buf, &ray_buf);
  err |= clSetKernelArg(k, 1, sizeof count, &count);
  err |= clSetKernelArg(k, 2, sizeof flags, &flags);
  err |= clSetKernelArg(k, 3, sizeof s->nodes, &s->nodes);
  err |= clSetKernelArg(k, 4, sizeof s->tris, &s->tris);
  err |= clSetKernelArg(k, 5, sizeof hit_buf, &hit_buf);
  err |= clSetKernelArg(k, 6, sizeof counter_buf, &counter_buf);
  err |= clSetKernelArg(k, 7, sizeof error_buf, &error_buf);
  if ((status = lt__opencl_check(err, "setting trace kernel arguments"))) goto done;
  size_t global = groups * local;
  err = clEnqueueNDRangeKernel(ctx->queue, k, 1, NULL, &global, &local, 0, NULL, NULL);
  if ((status = lt__opencl_check(err, "launching the trace kernel"))) goto done;
  err = clEnqueueReadBuffer(ctx->queue, hit_buf, CL_TRUE, 0, count * sizeof(lt_hit), hits, 0, NULL, NULL);
  err |= clEnqueueReadBuffer(ctx->queue, counter_buf, CL_TRUE, 0, 2 * groups * sizeof(lt_u32), counters, 0, NULL, NULL);
  err |= clEnqueueReadBuffer(ctx->queue, error_buf, CL_TRUE, 0, sizeof error, &error, 0, NULL, NULL);
  if ((status = lt__opencl_check(err, "reading trace results"))) goto done;
  for (size_t g = 0; g < groups; g++) *steps += counters[2 * g], *tests += counters[2 * g + 1];
  if (error) status = lt__fail(LT_ERROR_CAPACITY, "traversal stack overflow (tree deeper than %d)", LT_BVH_STACK_SIZE);

done:
  if (ray_buf) clReleaseMemObject(ray_buf);
  if (hit_buf) clReleaseMemObject(hit_buf);
  if (counter_buf) clReleaseMemObject(counter_buf);
  if (error_buf) clReleaseMemObject(error_buf);
  free(counters);
  return status;
}

static lt_status trace_native(lt_structure *s, const lt_ray *rays, int count, int flags, lt_hit *hits,
                              uint64_t *steps, uint64_t *tests) {
  lt__native_trace_args args = {(const float *)rays, count, flags, s->bvh.nodes, s->bvh.tris,
                                (lt_hit_record *)hits, 0, 0, 0, 0};
  lt_status status = lt__native_run(s->ctx->work_groups, lt__native_trace_kernel, &args);
  *steps += args.traversal_steps, *tests += args.intersections;
  if (!status && args.error)
    status = lt__fail(LT_ERROR_CAPACITY, "traversal stack overflow (tree deeper than %d)", LT_BVH_STACK_SIZE);
  return status;
}

/* On demand: one launch builds what the rays need while tracing them (time to image); with
 * statistics asked for, a second launch traces the same rays on the tree as built, which is
 * the trace time, and build time is the difference (the paper's convention). The query flags
 * travel in the launch's any-hit argument (traversal/ray.h). */
static lt_status trace_ondemand(lt_structure *s, const lt_ray *rays, int count, int flags, lt_hit *hits,
                                lt_stats *stats) {
  int speculate = s->config.build == LT_BUILD_SPECULATIVE;
  double start = lt_now_ms();
  lt_status status = lt__ondemand_launch(&s->od, rays, count, flags, hits, speculate, stats);
  while (status == LT_ERROR_CAPACITY && s->pool_capacity < MAX_POOL) {
    status = with_retry(s, stats, status);
    start = lt_now_ms();
    if (!status) status = lt__ondemand_launch(&s->od, rays, count, flags, hits, speculate, stats);
  }
  double total = lt_now_ms() - start;
  if (status || !stats) return status;
  if (s->config.build == LT_BUILD_FULL) {
    lt__stats_add(stats, LT_STAT_TRACE_MS, total);
  } else {
    lt_stats *again;
    if ((status = lt_stats_create(&again))) return status;
    double retrace_start = lt_now_ms();
    status = lt__ondemand_launch(&s->od, rays, count, flags, hits, 0, again);
    double trace = lt_now_ms() - retrace_start;
    lt_stats_destroy(again);
    lt__stats_add(stats, LT_STAT_TRACE_MS, trace);
    lt__stats_add(stats, LT_STAT_BUILD_MS, total > trace ? total - trace : 0.0);
  }
  return status;
}

lt_status lt_structure_trace(lt_structure *s, const lt_ray *rays, size_t count, int query, lt_hit *hits,
                             lt_stats *stats) {
  if (!s || (count && (!rays || !hits))) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt_structure_trace: NULL argument");
  if (query != LT_QUERY_CLOSEST && query != LT_QUERY_ANY)
    return lt__fail(LT_ERROR_INVALID_ARGUMENT, "unknown query kind %d", query);
  if (count > (size_t)INT32_MAX / 8) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "%zu rays in one batch is too many", count);
  if (count == 0) return LT_OK;

  uint64_t steps = 0, tests = 0;
  lt_status status;
  if (s->host_built) {
    double start = lt_now_ms();
    status = s->ctx->kind == LT_DEVICE_OPENCL
                 ? trace_opencl(s, rays, (int)count, lt__structure_flags(s, query), hits, &steps, &tests)
                 : trace_native(s, rays, (int)count, lt__structure_flags(s, query), hits, &steps, &tests);
    if (!status) {
      lt__stats_add(stats, LT_STAT_TRACE_MS, lt_now_ms() - start);
      lt__stats_add(stats, LT_STAT_TRAVERSAL_STEPS, (double)steps);
      lt__stats_add(stats, LT_STAT_INTERSECTIONS, (double)tests);
    }
  } else {
    status = trace_ondemand(s, rays, (int)count, lt__structure_flags(s, query), hits, stats);
  }
  if (!status && stats) {
    lt__stats_add(stats, LT_STAT_RAYS, (double)count);
    double build = lt_stats_get(stats, "build_ms");
    lt__stats_put(stats, LT_STAT_TOTAL_MS, (build > 0 ? build : 0) + lt_stats_get(stats, "trace_ms"));
    put_build_stats(s, stats);
  }
  return status;
}
