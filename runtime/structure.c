/* Structures, whatever their kind: arguments checked, defaults filled in from the registry,
 * then the registry entry builds, traces, reports and releases (runtime/registry.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "runtime/context_internal.h"
#include "runtime/error.h"
#include "runtime/registry.h"
#include "runtime/stats_internal.h"
#include "traversal/ray.h"

static const char *const intersect_names[] = {"watertight", "fast"};

int lt__structure_tiny_capacities;

const char *lt_intersect_kind_name(lt_intersect_kind kind) {
  return kind <= LT_INTERSECT_FAST ? intersect_names[kind] : "unknown";
}

lt_status lt_intersect_kind_parse(const char *name, lt_intersect_kind *out) {
  for (int i = 0; i <= LT_INTERSECT_FAST; i++)
    if (strcmp(name, intersect_names[i]) == 0) return *out = (lt_intersect_kind)i, LT_OK;
  return lt__fail(LT_ERROR_INVALID_ARGUMENT, "unknown intersection test '%s' (known: watertight, fast)", name);
}

/* The config with every zero field replaced by the structure's default. */
static lt_structure_config resolve(const lt_structure_config *config, const lt__structure_class *cls) {
  lt_structure_config c = *config, d = cls->defaults;
  if (c.build == LT_BUILD_DEFAULT) c.build = d.build;
  if (c.max_leaf_size <= 0) c.max_leaf_size = d.max_leaf_size;
  if (c.sah_bins <= 0) c.sah_bins = d.sah_bins;
  if (c.traversal_cost <= 0) c.traversal_cost = d.traversal_cost;
  if (c.pool_capacity <= 0) c.pool_capacity = d.pool_capacity;
  if (c.grid_density <= 0) c.grid_density = d.grid_density;
  if (c.kd_traversal <= 0) c.kd_traversal = d.kd_traversal;
  if (c.kd_split <= 0) c.kd_split = d.kd_split;
  if (c.kd_clip <= 0) c.kd_clip = d.kd_clip;
  if (c.irgrid_top_density <= 0) c.irgrid_top_density = d.irgrid_top_density;
  if (c.irgrid_cell_density <= 0) c.irgrid_cell_density = d.irgrid_cell_density;
  if (c.irgrid_merge <= 0) c.irgrid_merge = d.irgrid_merge;
  if (c.irgrid_merge_alpha <= 0) c.irgrid_merge_alpha = d.irgrid_merge_alpha;
  if (c.irgrid_expansion_passes <= 0) c.irgrid_expansion_passes = d.irgrid_expansion_passes;
  if (c.bvh_builder <= 0) c.bvh_builder = d.bvh_builder;
  if (c.bvh_top <= 0) c.bvh_top = d.bvh_top;
  if (c.bvh_morton_above <= 0) c.bvh_morton_above = d.bvh_morton_above;
  return c;
}

lt__sah_config lt__structure_sah(const lt_structure_config *config) {
  lt__sah_config sah = lt__sah_config_default();
  sah.max_leaf_size = config->max_leaf_size;
  sah.bins = config->sah_bins;
  sah.traversal_cost = config->traversal_cost;
  return sah;
}

/* The statistics every structure reports the same way; the entry adds its own. */
static void put_stats(lt_structure *s, lt_stats *stats) {
  lt__stats_text(stats, "structure", s->cls->name);
  lt__stats_text(stats, "build", lt_build_mode_name(s->config.build));
  lt__stats_text(stats, "device", s->ctx->name);
  lt__stats_text(stats, "intersect", lt_intersect_kind_name(s->config.intersect));
  lt__stats_put(stats, LT_STAT_TRIANGLES, (double)lt_scene_triangle_count(s->scene));
  lt__stats_put(stats, LT_STAT_SKIPPED_TRIANGLES, (double)lt_scene_skipped_triangles(s->scene));
  lt__stats_put(stats, LT_STAT_COMPILE_MS, s->ctx->compile_ms);
  s->cls->put_stats(s, stats);
}

/* An empty structure of the entry's class, config resolved; nothing built yet. */
static lt_status make(lt_context *ctx, const lt_scene *scene, const lt_structure_config *config,
                      const lt__structure_class *cls, lt_structure **out) {
  lt_structure *s = calloc(1, sizeof *s);
  void *state = calloc(1, cls->state_size ? cls->state_size : 1);
  if (!s || !state) {
    free(s), free(state);
    return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory for a structure");
  }
  s->ctx = ctx, s->cls = cls, s->scene = scene, s->state = state;
  s->config = resolve(config, cls);
  s->config.kind = config->kind;
  s->flags = s->config.intersect == LT_INTERSECT_FAST ? LT_QUERY_FLAG_FAST_TRIANGLES : 0;
  *out = s;
  return LT_OK;
}

lt_status lt_structure_create(lt_context *ctx, const lt_scene *scene, const lt_structure_config *config,
                              lt_stats *stats, lt_structure **out) {
  lt_structure_config defaults;
  memset(&defaults, 0, sizeof defaults);
  if (!ctx || !scene || !out) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt_structure_create: NULL argument");
  if (!config) config = &defaults;
  const lt__structure_class *cls = lt__structure_class_of(config->kind);
  if (!cls) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "unknown structure kind %d", (int)config->kind);
  if ((unsigned)config->intersect > LT_INTERSECT_FAST)
    return lt__fail(LT_ERROR_INVALID_ARGUMENT, "unknown intersection test %d", (int)config->intersect);
  if ((unsigned)config->build > LT_BUILD_SPECULATIVE)
    return lt__fail(LT_ERROR_INVALID_ARGUMENT, "unknown build mode %d", (int)config->build);
  if (config->build != LT_BUILD_DEFAULT && !(cls->modes & (1u << config->build)))
    return lt__fail(LT_ERROR_UNSUPPORTED, "the %s is %s, not %s (--build %s)", cls->name,
                    cls->modes == 1u << LT_BUILD_FULL ? "built in full only" : "not built that way",
                    lt_build_mode_name(config->build), lt_build_mode_name(config->build));
  if (config->max_leaf_size < 0 || config->sah_bins < 0 || config->pool_capacity < 0 ||
      !(config->traversal_cost >= 0.0f && config->traversal_cost < INFINITY) ||
      !(config->grid_density >= 0.0f && config->grid_density < INFINITY))
    return lt__fail(LT_ERROR_INVALID_ARGUMENT,
                    "bad structure config (leaf size %d, bins %d, pool %d, traversal cost %g, grid density %g): "
                    "each must be 0 for the default or a positive finite value",
                    config->max_leaf_size, config->sah_bins, config->pool_capacity, (double)config->traversal_cost,
                    (double)config->grid_density);
  if ((unsigned)config->bvh_builder > LT_BVH_BUILDER_GOLDSMITH_SALMON)
    return lt__fail(LT_ERROR_INVALID_ARGUMENT, "bad BVH builder %d: see LT_BVH_BUILDER_* in lazytrace.h",
                    config->bvh_builder);
  if ((unsigned)config->bvh_top > LT_BVH_TOP_MORTON || config->bvh_morton_above < 0)
    return lt__fail(LT_ERROR_INVALID_ARGUMENT, "bad BVH top %d (see LT_BVH_TOP_* in lazytrace.h) or Morton bound %d",
                    config->bvh_top, config->bvh_morton_above);
  if ((unsigned)config->kd_traversal > LT_KD_TRAVERSAL_BACKTRACK || (unsigned)config->kd_split > LT_KD_SPLIT_SWEEP ||
      (unsigned)config->kd_clip > LT_KD_CLIP_ON)
    return lt__fail(LT_ERROR_INVALID_ARGUMENT, "bad kd-tree choice (traversal %d, split %d, clip %d): see LT_KD_* in lazytrace.h",
                    config->kd_traversal, config->kd_split, config->kd_clip);
  if (!(config->irgrid_top_density >= 0.0f && config->irgrid_top_density < INFINITY) ||
      !(config->irgrid_cell_density >= 0.0f && config->irgrid_cell_density < INFINITY) ||
      !(config->irgrid_merge_alpha >= 0.0f && config->irgrid_merge_alpha <= 1.0f) ||
      (unsigned)config->irgrid_merge > LT_IRGRID_MERGE_TOP ||
      (unsigned)config->irgrid_expansion_passes > LT_IRGRID_PASSES(LT_IRGRID_MAX_PASSES))
    return lt__fail(LT_ERROR_INVALID_ARGUMENT,
                    "bad irregular grid config (top density %g, cell density %g, merge %d, alpha %g, expansion %d): "
                    "densities positive and finite, alpha in (0, 1], see LT_IRGRID_* in lazytrace.h",
                    (double)config->irgrid_top_density, (double)config->irgrid_cell_density, config->irgrid_merge,
                    (double)config->irgrid_merge_alpha, config->irgrid_expansion_passes);
  if (lt_scene_triangle_count(scene) == 0) return lt__fail(LT_ERROR_EMPTY_SCENE, "the scene has no triangles");

  lt_structure *s;
  lt_status status = make(ctx, scene, config, cls, &s);
  if (status) return status;
  status = cls->create(s, stats);
  if (status) {
    lt_structure_destroy(s);
    return status;
  }
  if (stats) put_stats(s, stats);
  *out = s;
  return LT_OK;
}

void lt__structure_set_flags(lt_structure *s, int flags) { s->flags |= flags & ~LT_QUERY_FLAG_ANY; }

int lt__structure_flags(const lt_structure *s, int query) {
  return s->flags | (query == LT_QUERY_ANY ? LT_QUERY_FLAG_ANY : 0);
}

void lt_structure_destroy(lt_structure *s) {
  if (!s) return;
  s->cls->release(s);
  free(s->state);
  free(s);
}

lt_status lt_structure_trace(lt_structure *s, const lt_ray *rays, size_t count, int query, lt_hit *hits,
                             lt_stats *stats) {
  if (!s || (count && (!rays || !hits))) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt_structure_trace: NULL argument");
  if (query != LT_QUERY_CLOSEST && query != LT_QUERY_ANY)
    return lt__fail(LT_ERROR_INVALID_ARGUMENT, "unknown query kind %d", query);
  if (count > (size_t)INT32_MAX / 8) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "%zu rays in one batch is too many", count);
  if (count == 0) return LT_OK;

  lt_status status = s->cls->trace(s, rays, (int)count, lt__structure_flags(s, query), hits, stats);
  if (!status && stats) {
    lt__stats_add(stats, LT_STAT_RAYS, (double)count);
    double build = lt_stats_get(stats, "build_ms");
    lt__stats_put(stats, LT_STAT_TOTAL_MS, (build > 0 ? build : 0) + lt_stats_get(stats, "trace_ms"));
    put_stats(s, stats);
  }
  return status;
}

lt_status lt__structure_wrap(lt_context *ctx, const lt_scene *scene, const lt_structure_config *config,
                             lt_structure **out) {
  const lt__structure_class *cls = lt__structure_class_of(config->kind);
  if (!ctx || !scene || !out || !cls) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt__structure_wrap: bad argument");
  return make(ctx, scene, config, cls, out);
}
