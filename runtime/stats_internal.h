/* The statistics the library keeps, by contract key. A value below 0 means "does not apply"
 * and is written as null. Keys starting with "pool." go into the nested "pool" object. */
#ifndef LT_STATS_INTERNAL_H
#define LT_STATS_INTERNAL_H

#include "lazytrace.h"

#define LT_STAT_LIST(X)                      \
  X(LT_STAT_TRIANGLES, "triangles")          \
  X(LT_STAT_RAYS, "rays")                    \
  X(LT_STAT_LOAD_MS, "load_ms")              \
  X(LT_STAT_COMPILE_MS, "compile_ms")        \
  X(LT_STAT_BUILD_MS, "build_ms")            \
  X(LT_STAT_TRACE_MS, "trace_ms")            \
  X(LT_STAT_TOTAL_MS, "total_ms")            \
  X(LT_STAT_NODES_BUILT, "nodes_built")      \
  X(LT_STAT_NODES_FULL, "nodes_full")        \
  X(LT_STAT_REFERENCES, "references")        \
  X(LT_STAT_SORT_OPS, "sort_ops")            \
  X(LT_STAT_TRAVERSAL_STEPS, "traversal_steps") \
  X(LT_STAT_INTERSECTIONS, "intersections")  \
  X(LT_STAT_MEMORY_BYTES, "memory_bytes")    \
  X(LT_STAT_NODE_BYTES, "node_bytes")        \
  X(LT_STAT_REFERENCE_BYTES, "reference_bytes") \
  X(LT_STAT_POOL_BYTES, "pool_bytes")        \
  X(LT_STAT_MAX_DEPTH, "max_depth")          \
  X(LT_STAT_SAH_COST, "sah_cost")            \
  X(LT_STAT_SKIPPED_TRIANGLES, "skipped_triangles") \
  X(LT_STAT_MORTON_NODES, "morton_nodes")    \
  X(LT_STAT_WIDE_NODES, "wide.nodes")        \
  X(LT_STAT_WIDE_BYTES, "wide.bytes")        \
  X(LT_STAT_WIDE_MS, "wide.ms")              \
  X(LT_STAT_MAP_BYTES, "map_bytes")          \
  X(LT_STAT_CELLS_TOP, "cells.top")          \
  X(LT_STAT_CELLS_TOP_BUILT, "cells.top_built") \
  X(LT_STAT_CELLS_INITIAL, "cells.initial")  \
  X(LT_STAT_CELLS_FINAL, "cells.final")      \
  X(LT_STAT_CELLS_MERGES, "cells.merges")    \
  X(LT_STAT_CELLS_EXPANSIONS, "cells.expansions") \
  X(LT_STAT_POOL_TASKS, "pool.tasks")        \
  X(LT_STAT_POOL_REQUESTED, "pool.requested") \
  X(LT_STAT_POOL_SPECULATIVE, "pool.speculative") \
  X(LT_STAT_POOL_STALLS, "pool.stalls")      \
  X(LT_STAT_POOL_CACHE_HITS, "pool.cache_hits") \
  X(LT_STAT_POOL_CACHE_MISSES, "pool.cache_misses") \
  X(LT_STAT_POOL_SCANS, "pool.scans")        \
  X(LT_STAT_POOL_EMPTY_HITS, "pool.empty_cache_hits") \
  X(LT_STAT_POOL_CHUNKS, "pool.chunks")      \
  X(LT_STAT_POOL_IDLE, "pool.idle_polls")  \
  LT_STAT_EFFECT_LIST(X)

/* Rays traced and milliseconds (build plus trace) spent per effect by lt_render; null for
 * commands that render nothing. Keys before the dot name a nested JSON object. */
#define LT_STAT_EFFECT_LIST(X)                               \
  X(LT_STAT_RAYS_PRIMARY, "rays_by_effect.primary")          \
  X(LT_STAT_RAYS_SHADOWS, "rays_by_effect.shadows")          \
  X(LT_STAT_RAYS_AO, "rays_by_effect.ao")                    \
  X(LT_STAT_RAYS_DIFFUSE, "rays_by_effect.diffuse")          \
  X(LT_STAT_RAYS_MIRROR, "rays_by_effect.mirror")            \
  X(LT_STAT_RAYS_COLLISION, "rays_by_effect.collision")      \
  X(LT_STAT_MS_PRIMARY, "ms_by_effect.primary")              \
  X(LT_STAT_MS_SHADOWS, "ms_by_effect.shadows")              \
  X(LT_STAT_MS_AO, "ms_by_effect.ao")                        \
  X(LT_STAT_MS_DIFFUSE, "ms_by_effect.diffuse")              \
  X(LT_STAT_MS_MIRROR, "ms_by_effect.mirror")                \
  X(LT_STAT_MS_COLLISION, "ms_by_effect.collision")

typedef enum {
#define LT_STAT_ENUM(id, key) id,
  LT_STAT_LIST(LT_STAT_ENUM)
#undef LT_STAT_ENUM
      LT_STAT_COUNT
} lt_stat_id;

/* A device counter that feeds no statistic of its own (LT_BVH_STAT_LIST, ...). */
#define LT_STAT_NONE (-1)

/* One traced batch of a render: which effect, how many rays, build plus trace time, and the
 * nodes built once it was done (null where unknown). Written as the "batches" array. */
#define LT_STATS_MAX_BATCHES 256
typedef struct lt__batch_record {
  char effect[16];
  double rays, ms, nodes_built;
} lt__batch_record;

/* One frame of an animation (lt_stats_add_frame), written as the "frames" array. */
typedef struct lt__frame_record {
  double rays, build_ms, trace_ms, total_ms, nodes_built;
} lt__frame_record;

struct lt_stats {
  char structure[64];
  char build[64];
  char device[192];
  char intersect[16];
  double value[LT_STAT_COUNT];
  int batch_count;   /* records kept */
  long batches_more; /* batches past LT_STATS_MAX_BATCHES: counted in the totals, not recorded */
  lt__batch_record batches[LT_STATS_MAX_BATCHES];
  int frame_count;  /* frame records kept */
  long frames_more; /* frames past LT_STATS_MAX_FRAMES: counted, not recorded */
  lt__frame_record frames[LT_STATS_MAX_FRAMES];
};

/* Adds to a counter (a "does not apply" counter starts from 0); no-op on a NULL stats. */
void lt__stats_add(lt_stats *stats, lt_stat_id id, double value);
/* Overwrites a value; no-op on a NULL stats. */
void lt__stats_put(lt_stats *stats, lt_stat_id id, double value);
/* Records one batch of a render (kept up to LT_STATS_MAX_BATCHES, then only counted). */
void lt__stats_batch(lt_stats *stats, const char *effect, double rays, double ms, double nodes_built);
/* Sets "structure", "build", "device" or "intersect". */
void lt__stats_text(lt_stats *stats, const char *key, const char *text);

#endif
