/* lazytrace: batches of ray queries against triangle scenes, with acceleration structures
 * built on demand (Vinkler et al. 2016) or in full. This is the one public header.
 *
 * Conventions: opaque handles come in _create/_destroy pairs; a NULL config means defaults;
 * every call that can fail returns an lt_status, and lt_last_error() then holds a sentence
 * that names what was wrong (file, line, option). */
#ifndef LAZYTRACE_H
#define LAZYTRACE_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The version of this header; lt_version() gives the library's, which may differ when a
 * program runs against another build of the shared library. The build reads these lines. */
#define LT_VERSION_MAJOR 0
#define LT_VERSION_MINOR 1
#define LT_VERSION_PATCH 0
#define LT_VERSION (LT_VERSION_MAJOR * 10000 + LT_VERSION_MINOR * 100 + LT_VERSION_PATCH)
/* The library's version as "MAJOR.MINOR.PATCH". */
const char *lt_version(void);

/* Status codes: one list generates the enum, lt_status_str() and lt_status_name(). */
#define LT_STATUS_LIST(X)                                                                   \
  X(LT_OK, "success")                                                                       \
  X(LT_ERROR_INVALID_ARGUMENT, "invalid argument")                                          \
  X(LT_ERROR_OUT_OF_MEMORY, "out of host memory")                                           \
  X(LT_ERROR_IO, "file could not be read or written")                                       \
  X(LT_ERROR_PARSE, "malformed input file")                                                 \
  X(LT_ERROR_UNKNOWN_GENERATOR, "unknown scene generator")                                  \
  X(LT_ERROR_UNSUPPORTED, "capability not available yet")                                   \
  X(LT_ERROR_NO_DEVICE, "no compute device found")                                          \
  X(LT_ERROR_OPENCL, "OpenCL call failed")                                                  \
  X(LT_ERROR_PROGRAM_BUILD, "kernel program failed to build")                               \
  X(LT_ERROR_DEVICE_MEMORY, "device memory allocation failed")                              \
  X(LT_ERROR_CAPACITY, "a fixed-size buffer is full; retry with a larger one")             \
  X(LT_ERROR_SCHEDULER, "scheduler error: a wait exceeded its cap")                        \
  X(LT_ERROR_EMPTY_SCENE, "scene has no valid triangles")

typedef enum {
#define LT_STATUS_ENUM(name, text) name,
  LT_STATUS_LIST(LT_STATUS_ENUM)
#undef LT_STATUS_ENUM
      LT_STATUS_COUNT
} lt_status;

/* A short sentence for a status code ("invalid argument"). */
const char *lt_status_str(lt_status status);
/* The identifier of a status code ("LT_ERROR_INVALID_ARGUMENT"). */
const char *lt_status_name(lt_status status);
/* The detailed message of the last failing call on this thread, or "" if none. */
const char *lt_last_error(void);

/* ---- Rays and hits: the binary record formats of the ray and hit files. ---- */

/* 32 bytes: origin, tmin, direction (need not be unit length), tmax; t in direction lengths. */
typedef struct lt_ray {
  float org[3]; /* 12 bytes */
  float tmin;   /* 4 bytes */
  float dir[3]; /* 12 bytes */
  float tmax;   /* 4 bytes */
} lt_ray;

/* 16 bytes: hit point = (1-u-v)*v0 + u*v1 + v*v2 of triangle prim; prim = -1 on a miss. */
typedef struct lt_hit {
  float t;      /* 4 bytes */
  float u;      /* 4 bytes */
  float v;      /* 4 bytes */
  int32_t prim; /* 4 bytes */
} lt_hit;

/* Reads a ray file; *rays is malloc'ed and owned by the caller. A size that is not a multiple
 * of 32 bytes is LT_ERROR_PARSE. */
lt_status lt_rays_read(const char *path, lt_ray **rays, size_t *count);
/* Reads one share of a ray file, for a process that traces part of a batch (an MPI rank): of the
 * file's *total rays, the part-th of `parts` nearly equal contiguous ranges, rays [*first,
 * *first + *count) with *first = total * part / parts. Only that range is read. */
lt_status lt_rays_read_part(const char *path, size_t part, size_t parts, lt_ray **rays, size_t *count, size_t *first,
                            size_t *total);
lt_status lt_rays_write(const char *path, const lt_ray *rays, size_t count);
lt_status lt_hits_read(const char *path, lt_hit **hits, size_t *count);
lt_status lt_hits_write(const char *path, const lt_hit *hits, size_t count);
/* Every file lazytrace writes is written whole or not at all: to a temporary file beside it,
 * renamed over it once the write and the close succeeded, so a failure (a full disk) leaves an
 * existing file as it was. lt_file_write does so for bytes (images, statistics). */
lt_status lt_file_write(const char *path, const void *data, size_t bytes);
/* Whether two paths name the same existing file (an output must not overwrite an input). */
int lt_files_same(const char *a, const char *b);

/* ---- Devices and contexts ---- */

typedef enum { LT_DEVICE_AUTO = 0, LT_DEVICE_OPENCL, LT_DEVICE_NATIVE } lt_device_kind;

typedef struct lt_context_config {
  lt_device_kind device; /* default AUTO: OpenCL if a device exists, else native (said on stderr) */
  int opencl_index;      /* which OpenCL device, counted over all platforms; default 0 */
  int work_groups;       /* 0: as many as run concurrently (compute units, or native threads) */
  int local_size;        /* OpenCL work-group size; 0: backend default. Native is always 1. */
  int quiet;             /* nonzero: no notes on stderr (fallback to native, ...) */
} lt_context_config;

typedef struct lt_context lt_context;

lt_status lt_context_create(const lt_context_config *config, lt_context **out);
void lt_context_destroy(lt_context *ctx);
/* "opencl:0 (pthread-...)" or "native (2 threads)". */
const char *lt_context_device_name(const lt_context *ctx);
lt_device_kind lt_context_device_kind(const lt_context *ctx);
/* Persistent work-groups a launch uses (what runs concurrently, unless configured). */
int lt_context_work_groups(const lt_context *ctx);
/* Time spent compiling kernels in this context, in milliseconds (0 on native). */
double lt_context_compile_ms(const lt_context *ctx);
/* The OpenCL build log of the last program build, or "" if none. */
const char *lt_context_build_log(const lt_context *ctx);
/* Writes one line per device found (OpenCL devices and the native backend) to out. */
lt_status lt_devices_print(FILE *out);

/* ---- Scenes ---- */

typedef struct lt_camera {
  float eye[3];
  float look[3];
  float up[3];
  float fov_deg; /* vertical field of view */
} lt_camera;

typedef struct lt_scene lt_scene;

/* Loads a scene from a spec: a generator ("house-grid:3x3", "sphere:4"; an optional "@camera"
 * suffix picks the camera) or a mesh file (.obj by lazytrace's own reader, other formats
 * through assimp). Triangles with NaN or infinite coordinates are skipped and counted. */
lt_status lt_scene_load(const char *spec, lt_scene **out);
/* A scene from n triangles of 9 floats each (v0 v1 v2), copied. */
lt_status lt_scene_from_triangles(const float *tris, size_t n, lt_scene **out);
void lt_scene_destroy(lt_scene *scene);
size_t lt_scene_triangle_count(const lt_scene *scene);
/* 9 floats per triangle, in triangle-number order. */
const float *lt_scene_triangles(const lt_scene *scene);
/* Number of triangles dropped at load because a coordinate was NaN or infinite. */
size_t lt_scene_skipped_triangles(const lt_scene *scene);
/* Triangles where float arithmetic cannot serve rays: a coordinate beyond 1e12 or a size below
 * 1e-12, where the intersection test's products overflow or vanish, so rays may miss them.
 * The command line warns about them; they are kept, and answered as well as float allows. */
size_t lt_scene_unservable_triangles(const lt_scene *scene);
/* The camera named in the spec, or the scene's first ("outer"), or one framing the bounds. */
lt_camera lt_scene_camera(const lt_scene *scene);
/* Looks up a camera by name; LT_ERROR_INVALID_ARGUMENT if the scene has none of that name. */
lt_status lt_scene_named_camera(const lt_scene *scene, const char *name, lt_camera *out);
void lt_scene_bounds(const lt_scene *scene, float lo[3], float hi[3]);
/* Writes the triangles as OBJ, one face per triangle in number order. */
lt_status lt_scene_write_obj(const lt_scene *scene, const char *path);
/* A comma-separated list of the generators, for help text. */
const char *lt_generator_names(void);

/* Animated scenes: a scene file's instances with "keyframes" (rigid transforms interpolated
 * over time) and the generator "explode:BASE" (BASE's triangles fly apart) move with time, a
 * number from 0 (the first frame, the pose lt_scene_load gives) to 1 (the last). Whether the
 * scene moves at all: */
int lt_scene_is_animated(const lt_scene *scene);
/* Moves every triangle to where it is at `time` (clamped to [0, 1]; NaN is 0). The triangle
 * count and numbering never change; time 0 restores the loaded pose exactly. A structure built
 * over the scene must be destroyed first, or rebuilt after: it reads the triangles it was built
 * from. No-op on a scene that does not move. */
void lt_scene_set_time(lt_scene *scene, double time);
/* Frame `frame` of `frames` as a time: frames spread evenly from 0 to 1 (a single frame: 0). */
double lt_frame_time(int frame, int frames);

/* Primary rays through pixel centres, row by row from the top; out holds width*height rays. */
void lt_camera_primary_rays(const lt_camera *camera, int width, int height, lt_ray *out);

/* Ambient-occlusion rays: for every primary hit, `samples` cosine-weighted directions around
 * the geometric normal (turned towards the viewer), from the hit point, up to `distance`.
 * out holds count * samples rays; returns how many were written. */
size_t lt_ao_rays(const lt_scene *scene, const lt_ray *primary, const lt_hit *hits, size_t count, int samples,
                  float distance, uint64_t seed, lt_ray *out);
/* Collision agents (the on-demand paper, section 5): paths holds 6 floats per agent, a
 * segment between two random points of the scene's bounds. */
void lt_collision_paths(const lt_scene *scene, int agents, uint64_t seed, float *paths);
/* Frame `frame` of `frames`: each agent shoots rays_per_agent rays in uniformly random
 * directions from its position, bounded by the distance to its next position. */
void lt_collision_rays(const float *paths, int agents, int rays_per_agent, int frame, int frames, uint64_t seed,
                       lt_ray *out);

/* ---- Statistics ---- */

typedef struct lt_stats lt_stats;

lt_status lt_stats_create(lt_stats **out);
void lt_stats_destroy(lt_stats *stats);
void lt_stats_reset(lt_stats *stats);
/* Copies every value and name (structure, build, device) of src into dst; dst keeps its own
 * frame records (lt_stats_add_frame). */
void lt_stats_copy(lt_stats *dst, const lt_stats *src);
/* A counter or time by its contract key ("trace_ms", "nodes_built", "pool.stalls", ...);
 * returns -1 for a key that does not apply (written as null). */
double lt_stats_get(const lt_stats *stats, const char *key);
/* The numeric keys lt_stats_get knows, in the order the JSON object lists them: the i-th, or
 * NULL past the last; dotted keys ("pool.tasks") are the nested objects' members. */
const char *lt_stats_key(size_t i);
/* The text values by key: "structure", "build", "device" or "intersect"; "" where unset,
 * NULL for any other key. */
const char *lt_stats_text(const lt_stats *stats, const char *key);
/* Sets a value the caller measured itself (load_ms, for example). */
lt_status lt_stats_set(lt_stats *stats, const char *key, double value);
/* Writes one JSON object with every key of the contract. */
lt_status lt_stats_write_json(const lt_stats *stats, FILE *out);
/* Records frame (the statistics of one frame of an animation) as the next entry of the
 * "frames" array of stats: its rays, build_ms, trace_ms, total_ms and nodes_built. Up to
 * LT_STATS_MAX_FRAMES are kept; later ones are only counted ("frames_not_recorded"). */
#define LT_STATS_MAX_FRAMES 1024
void lt_stats_add_frame(lt_stats *stats, const lt_stats *frame);

/* ---- Acceleration structures ---- */

/* The structures this library implements, one line each: its kind and its entry in the host
 * registry (runtime/registry.c), which holds its name, parameters with defaults, help, and
 * functions. Adding a structure adds its own files and one line here. */
#define LT_STRUCTURE_LIST(X)                                                                   \
  X(LT_STRUCTURE_BVH, bvh)   /* binned SAH BVH through the task pool: full or on demand */   \
  X(LT_STRUCTURE_LBVH, lbvh) /* Morton-code LBVH with an SAH top, built on the host: full */ \
  X(LT_STRUCTURE_GRID, grid) /* uniform grid (Thrane and Simonsen 2005), on the host: full */ \
  X(LT_STRUCTURE_KDTREE, kdtree) /* binned SAH kd-tree through the task pool: full or on demand */ \
  X(LT_STRUCTURE_IRGRID, irgrid) /* irregular grid through the task pool: full or top cells on demand */ \
  X(LT_STRUCTURE_QBVH, qbvh) /* SAH BVH collapsed to a 4-ary tree (Bogolepov and Ulyanov), on the host: full */ \
  X(LT_STRUCTURE_ESCAPE_BVH, escape_bvh) /* SAH BVH with escape indices, stackless (Thrane and Simonsen), on the host: full */

typedef enum {
#define LT_STRUCTURE_ENUM(kind, entry) kind,
  LT_STRUCTURE_LIST(LT_STRUCTURE_ENUM)
#undef LT_STRUCTURE_ENUM
      LT_STRUCTURE_COUNT
} lt_structure_kind;

/* How a structure is built. LT_BUILD_DEFAULT (the zero value) is the structure's own default:
 * speculative where it can be built on demand, full otherwise. */
typedef enum { LT_BUILD_DEFAULT = 0, LT_BUILD_FULL, LT_BUILD_REQUESTED, LT_BUILD_SPECULATIVE } lt_build_mode;
/* The ray-triangle test. Watertight (Woop, Benthin and Wald 2013) never lets a ray slip
 * between triangles that share an edge or a vertex; fast (Moller-Trumbore 1997) does fewer
 * operations and may. Both give the same hits on every structure, mode and backend. */
typedef enum { LT_INTERSECT_WATERTIGHT = 0, LT_INTERSECT_FAST } lt_intersect_kind;

/* A structure's parameters. Every zero field means that structure's default, so a zeroed
 * config (or NULL) is the default BVH; lt_structure_config_default(kind) spells the defaults
 * out. Each structure reads the fields that apply to it ('lazytrace help' lists them). */
typedef struct lt_structure_config {
  lt_structure_kind kind; /* default BVH */
  lt_build_mode build;    /* default: the structure's (speculative for the BVH, full otherwise) */
  int max_leaf_size;      /* BVH, LBVH: default 16 (the paper's leaf bound) */
  int sah_bins;           /* BVH, LBVH: default 32 (the paper's bin count) */
  float traversal_cost;   /* BVH, LBVH: SAH cost of a node visit relative to one intersection; default 1 */
  int pool_capacity;      /* BVH: task slots to start with; default triangles / 8 (4096 at least).
                             A full pool is retried from scratch with twice the slots. */
  lt_intersect_kind intersect; /* default (0) WATERTIGHT */
  float grid_density;     /* grid: cells along the longest axis per cube root of the triangle
                             count; default 3 (Thrane and Simonsen) */
  int kd_traversal;       /* kd-tree: LT_KD_TRAVERSAL_*; default STACK */
  int kd_split;           /* kd-tree: LT_KD_SPLIT_*; default BINNED */
  int kd_clip;            /* kd-tree: LT_KD_CLIP_*; default OFF */
  float irgrid_top_density;  /* irregular grid: top cells per triangle (lambda1); default 0.12 */
  float irgrid_cell_density; /* irregular grid: sub-voxels per reference of a top cell (lambda2); default 2.4 */
  int irgrid_merge;          /* irregular grid: LT_IRGRID_MERGE_*; default ON */
  float irgrid_merge_alpha;  /* irregular grid: merging stops when a pass merges fewer than
                                1 - alpha of the cells; default 0.995 */
  int irgrid_expansion_passes; /* irregular grid: LT_IRGRID_PASSES(n) for n passes; default 3 */
  int bvh_builder;             /* escape-index BVH: LT_BVH_BUILDER_*; default SAH */
  int bvh_top;                 /* BVH: LT_BVH_TOP_*; default SAH */
  int bvh_morton_above;        /* BVH with the Morton top: nodes of more triangles are split by
                                  Morton code, smaller ones by SAH; default 2048 */
} lt_structure_config;

/* The kd-tree's choices (0 in a config: the default). Traversal: front to back with a stack, or
 * without one (Foley and Sugerman 2005), restarting from the root or backtracking through
 * parent links, on a fully built tree. Split search: 32 bins, or an exact sweep over the sorted
 * box ends of cells of up to 1024 references (bins above). Clipping: classify triangles by
 * their boxes, or by the box of the part inside the cell ("perfect splits"). */
enum { LT_KD_TRAVERSAL_STACK = 1, LT_KD_TRAVERSAL_RESTART, LT_KD_TRAVERSAL_BACKTRACK };
enum { LT_KD_SPLIT_BINNED = 1, LT_KD_SPLIT_SWEEP };
enum { LT_KD_CLIP_OFF = 1, LT_KD_CLIP_ON };
/* The irregular grid's choices (0 in a config: the default). Merging: on (the paper's passes
 * across the whole grid in a full build; within each top cell when top cells are built on
 * demand), off (the two-level grid), or within top cells only in every mode. Expansion: the
 * number of passes, 0 to 8, written LT_IRGRID_PASSES(n) so that 0 can stay "the default". */
enum { LT_IRGRID_MERGE_ON = 1, LT_IRGRID_MERGE_OFF, LT_IRGRID_MERGE_TOP };
#define LT_IRGRID_PASSES(n) ((n) + 1)
#define LT_IRGRID_MAX_PASSES 8
/* The escape-index BVH's builders (0 in a config: the default): the binned SAH BVH, or the two
 * of Thrane and Simonsen's comparison, Kay-Kajiya (spatial median of the longest axis) and
 * Goldsmith-Salmon (insertion by surface-area cost, best of 15 shuffled orders, fixed seed). */
enum { LT_BVH_BUILDER_SAH = 1, LT_BVH_BUILDER_KAY_KAJIYA, LT_BVH_BUILDER_GOLDSMITH_SALMON };
/* The BVH's top levels (0 in a config: the default): binned SAH all the way, or, for scenes
 * rebuilt every frame, the triangles sorted by Morton code once and the nodes of more than
 * bvh_morton_above triangles split by code (HLBVH applied on demand), SAH below. */
enum { LT_BVH_TOP_SAH = 1, LT_BVH_TOP_MORTON };

/* The defaults of a structure, every field filled in. */
lt_structure_config lt_structure_config_default(lt_structure_kind kind);
/* Parses "bvh", "full", ...; LT_ERROR_INVALID_ARGUMENT for an unknown name and
 * LT_ERROR_UNSUPPORTED for a known name whose capability does not exist yet. */
lt_status lt_structure_kind_parse(const char *name, lt_structure_kind *out);
lt_status lt_build_mode_parse(const char *name, lt_build_mode *out);
const char *lt_structure_kind_name(lt_structure_kind kind);
const char *lt_build_mode_name(lt_build_mode mode);
/* What the registry says of a structure: a one-line summary and its options with their
 * defaults, one line each, for help text; the build modes it can be built in, as bits 1 << mode. */
const char *lt_structure_summary(lt_structure_kind kind);
const char *lt_structure_parameters(lt_structure_kind kind);
unsigned lt_structure_modes(lt_structure_kind kind);
/* Sets the config field behind a structure's command-line option ("--leaf-size", "16"), as
 * the registry lists them; LT_ERROR_INVALID_ARGUMENT for a value out of range and
 * LT_ERROR_UNSUPPORTED for an option no structure takes. */
lt_status lt_structure_option(lt_structure_config *config, const char *option, const char *value);
/* Every structure and build mode this library implements, in registry order, as pairs in
 * kinds[i], modes[i] (up to max of them); returns how many there are. Tests and benchmarks
 * that try everything take their list from here. */
size_t lt_structure_variants(lt_structure_kind *kinds, lt_build_mode *modes, size_t max);
/* Names that are planned but not implemented yet, separated by commas (refused by the parser). */
const char *lt_structure_planned(void);
/* "watertight" or "fast". */
lt_status lt_intersect_kind_parse(const char *name, lt_intersect_kind *out);
const char *lt_intersect_kind_name(lt_intersect_kind kind);
typedef struct lt_structure lt_structure;

/* Builds (or, on demand, prepares) a structure over the scene's triangles on ctx's device.
 * Build time and node counts go to stats if it is not NULL. The structure keeps using both:
 * the context and the scene must outlive it (destroy the structure first). */
lt_status lt_structure_create(lt_context *ctx, const lt_scene *scene,
                              const lt_structure_config *config, lt_stats *stats,
                              lt_structure **out);
void lt_structure_destroy(lt_structure *structure);

enum {
  LT_QUERY_CLOSEST = 0, /* the closest hit; ties in t go to the lower triangle number */
  LT_QUERY_ANY = 1      /* any hit in [tmin, tmax]: prim >= 0 means occluded */
};

/* Traces count rays; hits[i] answers rays[i]. Rays with a NaN or infinite component, a zero
 * direction or tmin > tmax miss. Trace time and counters are added to stats if not NULL. */
lt_status lt_structure_trace(lt_structure *structure, const lt_ray *rays, size_t count,
                             int query, lt_hit *hits, lt_stats *stats);

/* The brute-force reference: every ray against every triangle, in C on the host, with the
 * same (watertight) intersection test and tie rule as the structures. */
lt_status lt_reference_trace(const lt_scene *scene, const lt_ray *rays, size_t count, int query,
                             lt_hit *hits);

/* ---- The task pool and its own workload ---- */

/* Capacities of the task pool (Vinkler et al. 2016, sections 3.2 and 4). */
typedef struct lt_pool_config {
  int capacity;            /* task slots; default 65536. A full pool is LT_ERROR_CAPACITY. */
  int empty_cache_size;    /* ring of recently emptied slots; default 1024 */
  int priority_cache_size; /* ring of slots unlocked by requests; default 1024 */
  int max_idle_polls;      /* searches, while every work-group searches and nothing moves,
                              before LT_ERROR_SCHEDULER; default 200,000,000 (seconds) */
  int order_log_size;      /* entries of the log of task starts (for tests); default 0 */
  int max_stall_seconds;   /* native backend: seconds without progress anywhere, while some
                              work-group is still inside the launch (one that stopped, say),
                              before LT_ERROR_SCHEDULER; default 60 */
} lt_pool_config;

/* A quicksort built on demand through the task pool: the scheduler's test workload. Each task
 * partitions one node of the sort tree (phases: pivot, count, scatter, copy back) and spawns
 * two children; queries ask for the key at a sorted position and walk the tree like rays,
 * requesting the nodes they reach. The pool and the partial sort persist across queries. */
typedef struct lt_lazy_sort lt_lazy_sort;

lt_status lt_lazy_sort_create(lt_context *ctx, const uint32_t *keys, size_t count, lt_build_mode mode,
                              const lt_pool_config *config, lt_lazy_sort **out);
void lt_lazy_sort_destroy(lt_lazy_sort *sort);
/* One launch of the persistent kernel: answers[i] = the key at sorted position positions[i].
 * With count 0 in a full build, runs until the whole array is sorted. Pool counters go to
 * stats ("pool.tasks", ...) if not NULL. */
lt_status lt_lazy_sort_query(lt_lazy_sort *sort, const int32_t *positions, size_t count, uint32_t *answers,
                             lt_stats *stats);
/* The keys as they stand (sorted where the sort got to). */
lt_status lt_lazy_sort_keys(lt_lazy_sort *sort, uint32_t *out);
/* The node ids in the order their tasks were first taken, up to order_log_size. */
lt_status lt_lazy_sort_order(lt_lazy_sort *sort, int32_t *out, size_t capacity, size_t *count);
/* The baseline the scheduler is measured against: the same tasks sorted completely, one
 * kernel launch per tree level, the host unlocking each next level between launches. The
 * sort must have been created in full mode and not queried yet; *levels gets the launches. */
lt_status lt_lazy_sort_by_levels(lt_lazy_sort *sort, lt_stats *stats, int *levels);
/* Nodes built so far (partitioned nodes plus sorted leaves) and tasks still in the pool. */
lt_status lt_lazy_sort_progress(lt_lazy_sort *sort, size_t *nodes_built, size_t *tasks_left);

/* Milliseconds on a monotonic clock, for callers timing their own phases. */
double lt_now_ms(void);

/* ==== Scene descriptions and effects (scene files) ====
 * A scene file (.json, loaded by lt_scene_load) describes meshes, instances, materials, lights,
 * camera, image and the effects to simulate; generators and mesh files get a default
 * description (one grey diffuse material, no lights, primary rays only). lt_render traces only
 * the ray batches the effects call for, each batch through the same structure. */

/* A Lambertian surface with an optional perfect mirror part and emission. */
typedef struct lt_material {
  float diffuse[3];  /* albedo, each in [0, 1]; default 0.8 */
  float mirror;      /* weight of the perfect mirror part, in [0, 1]; default 0 */
  float emission[3]; /* emitted radiance; default 0 */
} lt_material;

typedef enum { LT_LIGHT_POINT = 0, LT_LIGHT_DIRECTIONAL } lt_light_kind;

typedef struct lt_light {
  lt_light_kind kind;
  float vector[3];    /* the position of a point light, or the direction a directional light shines */
  float intensity[3]; /* point: intensity (irradiance intensity / distance^2); directional: irradiance */
} lt_light;

/* What to simulate. Every effect but collision starts from the primary hits. */
typedef struct lt_effects {
  int primary;          /* camera rays, closest hit */
  int shadows;          /* any-hit rays towards each light from every shaded point (0: unshadowed) */
  int ao_samples;       /* ambient-occlusion rays per camera-path hit, any hit; 0: off */
  float ao_distance;    /* their length */
  int diffuse_samples;  /* cosine-sampled rays per camera-path hit; 0: off */
  int diffuse_bounces;  /* diffuse bounces followed from there, at least 1 */
  int mirror_depth;     /* reflections followed from mirror materials; 0: off */
  int collision_agents; /* collision agents (lt_collision_paths); 0: off */
  int collision_rays;   /* rays per agent and frame */
  int collision_frames; /* frames, each one batch on the same structure */
} lt_effects;

/* Materials of the scene (at least one) and the material of triangle tri. */
size_t lt_scene_material_count(const lt_scene *scene);
const lt_material *lt_scene_materials(const lt_scene *scene);
int lt_scene_triangle_material(const lt_scene *scene, size_t tri);
size_t lt_scene_light_count(const lt_scene *scene);
const lt_light *lt_scene_lights(const lt_scene *scene);
lt_effects lt_scene_effects(const lt_scene *scene);
/* Image size and samples per pixel the scene asks for; 0 where it names none. */
void lt_scene_image(const lt_scene *scene, int *width, int *height, int *spp);
/* Radiance arriving from outside the scene (misses, ambient occlusion, diffuse rays). */
void lt_scene_background(const lt_scene *scene, float rgb[3]);

typedef struct lt_render_config {
  int width, height;         /* 0: the scene's, else 1024 */
  int spp;                   /* camera samples per pixel (jittered when above 1); 0: the scene's, else 1 */
  const lt_effects *effects; /* NULL: the scene's */
  uint64_t seed;             /* every random number derives from it and the pixel; same seed, same image */
  size_t max_batch;          /* rays per batch at most (the image is cut into tiles); 0: 2M */
  int progress;              /* nonzero: progress on stderr once a render has taken 3 s */
} lt_render_config;

/* Renders the scene through structure (NULL: the brute-force reference, lt_reference_trace).
 * rgb gets 3 linear floats per pixel, row by row from the top (width*height*3, allocated by the
 * caller from the size lt_render_size gives). stats, if not NULL, get the structure's counters
 * summed over all batches, rays_by_effect, ms_by_effect and one record per batch. */
lt_status lt_render(lt_structure *structure, const lt_scene *scene, const lt_render_config *config, float *rgb,
                    lt_stats *stats);
/* One part of the same render, for a program that splits an image between processes (MPI ranks,
 * say): the pixels first + j * stride for j < count (row-major indices), written in their places
 * in rgb, which has the whole image's size; no other pixel is touched. Every pixel gets the value
 * lt_render gives it with the same config and seed, whatever the part. Contiguous parts (stride
 * 1, a band of rows) keep each process's rays coherent, so it builds less of the structure;
 * interleaved parts (first = rank, stride = ranks) balance load but each builds nearly all of
 * it. The collision effect, which draws no pixel, is traced only by the part whose first is 0. */
lt_status lt_render_part(lt_structure *structure, const lt_scene *scene, const lt_render_config *config, size_t first,
                         size_t count, size_t stride, float *rgb, lt_stats *stats);
/* The image size and spp lt_render will use for this scene and config. */
void lt_render_size(const lt_scene *scene, const lt_render_config *config, int *width, int *height, int *spp);
/* Linear RGB to 8-bit sRGB (the standard transfer curve), clamped to [0, 1]. */
void lt_image_to_srgb8(const float *rgb, size_t pixels, unsigned char *out);

#ifdef __cplusplus
}
#endif

#endif
