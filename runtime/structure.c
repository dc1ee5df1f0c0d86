/* Structures: build on the host, upload, and trace batches on the context's backend. */
#include <stdlib.h>
#include <string.h>

#include "builders/bvh_sah.h"
#include "kernels/native_kernels.h"
#include "runtime/context_internal.h"
#include "runtime/error.h"
#include "runtime/stats_internal.h"
#include "scenes/scene_internal.h"

struct lt_structure {
  lt_context *ctx;
  lt_structure_config config;
  lt__bvh bvh;
  cl_mem nodes; /* OpenCL copies of bvh.nodes and bvh.tris */
  cl_mem tris;
};

static const char *const structure_names[] = {"bvh"};
/* Names a user may give that later issues implement; each is refused with a clear message. */
static const char *const planned_structures[] = {"kdtree", "irgrid", "grid", "qbvh", "lbvh", "escape-bvh", NULL};
static const char *const build_names[] = {"full", "requested", "speculative"};

const char *lt_structure_kind_name(lt_structure_kind kind) {
  return kind < LT_STRUCTURE_COUNT ? structure_names[kind] : "unknown";
}
const char *lt_build_mode_name(lt_build_mode mode) { return mode <= LT_BUILD_SPECULATIVE ? build_names[mode] : "unknown"; }

lt_status lt_structure_kind_parse(const char *name, lt_structure_kind *out) {
  for (int i = 0; i < LT_STRUCTURE_COUNT; i++)
    if (strcmp(name, structure_names[i]) == 0) return *out = (lt_structure_kind)i, LT_OK;
  for (int i = 0; planned_structures[i]; i++)
    if (strcmp(name, planned_structures[i]) == 0)
      return lt__fail(LT_ERROR_UNSUPPORTED, "--structure %s is not implemented yet (available: bvh)", name);
  return lt__fail(LT_ERROR_INVALID_ARGUMENT, "unknown structure '%s' (known: bvh; planned: kdtree, irgrid, grid, qbvh, lbvh)", name);
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

lt_status lt_structure_create(lt_context *ctx, const lt_scene *scene, const lt_structure_config *config,
                              lt_stats *stats, lt_structure **out) {
  lt_structure_config defaults = {LT_STRUCTURE_BVH, LT_BUILD_FULL, 16, 32, 1.0f};
  if (!ctx || !scene || !out) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt_structure_create: NULL argument");
  if (!config) config = &defaults;
  if (config->kind != LT_STRUCTURE_BVH) return lt__fail(LT_ERROR_UNSUPPORTED, "only the BVH exists so far");
  if (config->build != LT_BUILD_FULL)
    return lt__fail(LT_ERROR_UNSUPPORTED, "--build %s needs the task pool, which is not implemented yet; use --build full",
                    lt_build_mode_name(config->build));
  if (scene->count == 0) return lt__fail(LT_ERROR_EMPTY_SCENE, "the scene has no triangles");

  lt_structure *s = calloc(1, sizeof *s);
  if (!s) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory for a structure");
  s->ctx = ctx;
  s->config = *config;

  /* Kernels compile before the clock starts: compile time is reported apart. */
  lt_status status = ctx->kind == LT_DEVICE_OPENCL ? lt__opencl_program(ctx) : LT_OK;
  double start = lt_now_ms();
  lt__sah_config sah = lt__sah_config_default();
  if (config->max_leaf_size > 0) sah.max_leaf_size = config->max_leaf_size;
  if (config->sah_bins > 0) sah.bins = config->sah_bins;
  if (config->traversal_cost > 0) sah.traversal_cost = config->traversal_cost;
  if (!status) status = lt__bvh_build_sah(scene->tris, scene->count, &sah, &s->bvh);
  if (!status && ctx->kind == LT_DEVICE_OPENCL) status = upload(s);
  double build_ms = lt_now_ms() - start;
  if (status) {
    lt_structure_destroy(s);
    return status;
  }

  /* What the build made, in the contract's terms. */
  if (stats) {
    size_t node_bytes = (size_t)s->bvh.node_count * sizeof(lt_bvh_node);
    size_t ref_bytes = (size_t)s->bvh.tri_count * sizeof(lt_tri);
    lt__stats_text(stats, "structure", lt_structure_kind_name(config->kind));
    lt__stats_text(stats, "build", lt_build_mode_name(config->build));
    lt__stats_text(stats, "device", ctx->name);
    lt__stats_put(stats, LT_STAT_TRIANGLES, (double)scene->count);
    lt__stats_put(stats, LT_STAT_SKIPPED_TRIANGLES, (double)scene->skipped);
    lt__stats_put(stats, LT_STAT_COMPILE_MS, ctx->compile_ms);
    lt__stats_add(stats, LT_STAT_BUILD_MS, build_ms);
    lt__stats_put(stats, LT_STAT_NODES_BUILT, (double)lt__bvh_tree_nodes(&s->bvh));
    lt__stats_put(stats, LT_STAT_NODES_FULL, (double)lt__bvh_tree_nodes(&s->bvh));
    lt__stats_put(stats, LT_STAT_REFERENCES, (double)s->bvh.tri_count);
    lt__stats_add(stats, LT_STAT_SORT_OPS, (double)s->bvh.sort_ops);
    lt__stats_put(stats, LT_STAT_NODE_BYTES, (double)node_bytes);
    lt__stats_put(stats, LT_STAT_REFERENCE_BYTES, (double)ref_bytes);
    lt__stats_put(stats, LT_STAT_POOL_BYTES, 0);
    lt__stats_put(stats, LT_STAT_MEMORY_BYTES, (double)(node_bytes + ref_bytes));
    lt__stats_put(stats, LT_STAT_MAX_DEPTH, s->bvh.max_depth);
    lt__stats_put(stats, LT_STAT_SAH_COST, s->bvh.sah_cost);
  }
  *out = s;
  return LT_OK;
}

void lt_structure_destroy(lt_structure *s) {
  if (!s) return;
  if (s->nodes) clReleaseMemObject(s->nodes);
  if (s->tris) clReleaseMemObject(s->tris);
  lt__bvh_free(&s->bvh);
  free(s);
}

/* One launch of the trace kernel over all rays on the OpenCL device. */
static lt_status trace_opencl(lt_structure *s, const lt_ray *rays, int count, int any, lt_hit *hits,
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
  err |= clSetKernelArg(k, 2, sizeof any, &any);
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

static lt_status trace_native(lt_structure *s, const lt_ray *rays, int count, int any, lt_hit *hits,
                              uint64_t *steps, uint64_t *tests) {
  lt__native_trace_args args = {(const float *)rays, count, any, s->bvh.nodes, s->bvh.tris,
                                (lt_hit_record *)hits, 0, 0, 0, 0};
  lt_status status = lt__native_run(s->ctx->work_groups, lt__native_trace_kernel, &args);
  *steps += args.traversal_steps, *tests += args.intersections;
  if (!status && args.error)
    status = lt__fail(LT_ERROR_CAPACITY, "traversal stack overflow (tree deeper than %d)", LT_BVH_STACK_SIZE);
  return status;
}

lt_status lt_structure_trace(lt_structure *s, const lt_ray *rays, size_t count, int query, lt_hit *hits,
                             lt_stats *stats) {
  if (!s || (count && (!rays || !hits))) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt_structure_trace: NULL argument");
  if (query != LT_QUERY_CLOSEST && query != LT_QUERY_ANY)
    return lt__fail(LT_ERROR_INVALID_ARGUMENT, "unknown query kind %d", query);
  if (count > (size_t)INT32_MAX / 8) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "%zu rays in one batch is too many", count);
  if (count == 0) return LT_OK;

  double start = lt_now_ms();
  uint64_t steps = 0, tests = 0;
  lt_status status = s->ctx->kind == LT_DEVICE_OPENCL
                         ? trace_opencl(s, rays, (int)count, query == LT_QUERY_ANY, hits, &steps, &tests)
                         : trace_native(s, rays, (int)count, query == LT_QUERY_ANY, hits, &steps, &tests);
  double trace_ms = lt_now_ms() - start;
  if (!status && stats) {
    lt__stats_add(stats, LT_STAT_RAYS, (double)count);
    lt__stats_add(stats, LT_STAT_TRACE_MS, trace_ms);
    lt__stats_add(stats, LT_STAT_TRAVERSAL_STEPS, (double)steps);
    lt__stats_add(stats, LT_STAT_INTERSECTIONS, (double)tests);
    double build = lt_stats_get(stats, "build_ms");
    lt__stats_put(stats, LT_STAT_TOTAL_MS, (build > 0 ? build : 0) + lt_stats_get(stats, "trace_ms"));
  }
  return status;
}
