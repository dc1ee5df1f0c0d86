/* The QBVH against the binary BVH it collapses (Bogolepov and Ulyanov's comparison): trace
 * throughput for primary rays and for incoherent diffuse rays (one cosine-weighted bounce from
 * each primary hit, unbounded, closest hit), node memory and depth (the stack bound), on both
 * backends, with Embree 3 beside where it is installed. Each run traces every method once,
 * methods interleaved; the table gives medians. Prints one markdown table per scene.
 *
 *   bench_qbvh SCENE[@camera] [--size N] [--runs R]     (defaults: 1024, 5)
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "benchmarks/median.h"
#include "builders/host/qbvh_collapse.h"
#include "lazytrace.h"
#include "runtime/structure_internal.h"
#include "traversal/qbvh_traverse.h"
#ifdef LT_HAVE_EMBREE
#include "benchmarks/embree_peer.h"
#endif

#define MAX_RUNS 32
enum { BVH2, QBVH, QBVH8, POOL_BVH, METHODS };
static const char *const method_names[METHODS] = {"BVH2 (the SAH tree collapsed)", "QBVH", "QBVH, 8 wide (native default)",
                                                  "bvh --build full (pool)"};

typedef struct method {
  lt_structure *s;
  double ms[2][MAX_RUNS]; /* primary, diffuse */
} method;

/* The structure of method m on ctx: the host SAH BVH traced by the binary kernel, its QBVH (4
 * wide, the paper's layout), the QBVH as `--structure qbvh` makes it (8 wide natively where AVX2
 * is there; OpenCL has the 4-wide one only, so that method is native only), or the pool's full
 * build. */
static lt_structure *make(lt_context *ctx, const lt_scene *scene, int m) {
  lt_structure *s = NULL;
  if (m == BVH2) {
    lt__bvh bvh;
    lt__sah_config sah = lt__sah_config_default();
    if (lt__bvh_build_sah(lt_scene_triangles(scene), lt_scene_triangle_count(scene), &sah, &bvh)) return NULL;
    if (lt__structure_from_bvh(ctx, scene, &bvh, &s)) return lt__bvh_free(&bvh), NULL;
  } else {
    /* The paper's 4-wide layout on both backends, and natively the default width too
     * (benchmarks/bench_wide_simd.c compares the widths with AO rays). */
    lt_structure_config c = lt_structure_config_default(m == POOL_BVH ? LT_STRUCTURE_BVH : LT_STRUCTURE_QBVH);
    c.build = LT_BUILD_FULL;
    if (m != QBVH8) setenv("LT_QBVH_WIDTH", "4", 1);
    lt_status status = lt_structure_create(ctx, scene, &c, NULL, &s);
    unsetenv("LT_QBVH_WIDTH");
    if (status) return fprintf(stderr, "%s\n", lt_last_error()), NULL;
  }
  return s;
}

/* The most stack entries the QBVH traversal holds on these rays, traced on the host. */
static int qbvh_deepest(const lt_scene *scene, const lt_ray *rays, size_t n, int *binary_depth, int *qbvh_depth) {
  lt__bvh bvh;
  lt__qbvh q;
  lt__sah_config sah = lt__sah_config_default();
  if (lt__bvh_build_sah(lt_scene_triangles(scene), lt_scene_triangle_count(scene), &sah, &bvh)) return -1;
  if (lt__qbvh_collapse(&bvh, LT_QBVH_MAX_NODES, &q)) return lt__bvh_free(&bvh), -1;
  lt_i32 deepest = 0;
  lt_trace_counters c = {0, 0};
  for (size_t i = 0; i < n; i++) {
    const lt_ray *ray = &rays[i];
    lt_ray_setup r = lt_ray_prepare(ray->org[0], ray->org[1], ray->org[2], ray->tmin, ray->dir[0], ray->dir[1],
                                    ray->dir[2], ray->tmax);
    lt_hit_record hit;
    lt_qbvh_traverse(q.nodes, bvh.tris, &r, &hit, &c, &deepest);
  }
  *binary_depth = bvh.max_depth, *qbvh_depth = q.max_depth;
  lt__qbvh_free(&q);
  lt__bvh_free(&bvh);
  return deepest;
}

int main(int argc, char **argv) {
  const char *spec = NULL;
  int size = 1024, runs = 5;
  for (int i = 1; i < argc; i++) {
    if (strcmp(argv[i], "--size") == 0 && i + 1 < argc) size = atoi(argv[++i]);
    else if (strcmp(argv[i], "--runs") == 0 && i + 1 < argc) runs = atoi(argv[++i]);
    else if (argv[i][0] != '-') spec = argv[i];
    else spec = NULL, i = argc;
  }
  if (!spec || runs < 1 || runs > MAX_RUNS || size < 1)
    return fprintf(stderr, "usage: bench_qbvh SCENE[@camera] [--size N] [--runs R (1-%d)]\n", MAX_RUNS), 2;

  /* The rays: primary, and one diffuse bounce from every primary hit. */
  lt_scene *scene;
  if (lt_scene_load(spec, &scene) != LT_OK) return fprintf(stderr, "%s\n", lt_last_error()), 1;
  size_t n = (size_t)size * size;
  lt_ray *rays[2] = {malloc(n * sizeof(lt_ray)), malloc(n * sizeof(lt_ray))};
  lt_hit *hits = malloc(n * sizeof(lt_hit)), *check = malloc(n * sizeof(lt_hit));
  lt_camera camera = lt_scene_camera(scene);
  lt_camera_primary_rays(&camera, size, size, rays[0]);
  size_t counts[2] = {n, 0};

  /* Contexts and structures: every method on each backend, built once. */
  lt_context *ctx[2] = {NULL, NULL};
  const char *backend[2] = {"native", "OpenCL"};
  method m[2][METHODS];
  memset(m, 0, sizeof m);
  for (int b = 0; b < 2; b++) {
    lt_context_config config = {b ? LT_DEVICE_OPENCL : LT_DEVICE_NATIVE, 0, 0, 0, 1};
    if (lt_context_create(&config, &ctx[b]) != LT_OK) {
      fprintf(stderr, "%s: %s\n", backend[b], lt_last_error());
      ctx[b] = NULL;
      continue;
    }
    for (int k = 0; k < METHODS; k++) {
      if (b == 1 && k == QBVH8) continue;
      m[b][k].s = make(ctx[b], scene, k);
      if (!m[b][k].s) return fprintf(stderr, "%s on %s failed\n", method_names[k], backend[b]), 1;
    }
  }
  lt_structure *first = m[0][BVH2].s;
  if (lt_structure_trace(first, rays[0], n, LT_QUERY_CLOSEST, hits, NULL)) return 1;
  counts[1] = lt_ao_rays(scene, rays[0], hits, n, 1, INFINITY, 7, rays[1]);

  /* Runs: every backend, method and ray set once per run, interleaved; the first run warms
   * up (PoCL compiles a kernel at its first launch) and is not counted. */
  int mismatches = 0;
  for (int run = -1; run < runs; run++)
    for (int set = 0; set < 2; set++)
      for (int b = 0; b < 2; b++)
        for (int k = 0; ctx[b] && k < METHODS; k++) {
          if (!m[b][k].s) continue;
          lt_stats *stats;
          lt_stats_create(&stats);
          if (lt_structure_trace(m[b][k].s, rays[set], counts[set], LT_QUERY_CLOSEST, check, stats)) return 1;
          if (run >= 0) m[b][k].ms[set][run] = lt_stats_get(stats, "trace_ms");
          lt_stats_destroy(stats);
          if (run < 0 && b == 0 && k == 0) memcpy(hits, check, counts[set] * sizeof *hits);
          else if (run < 0) mismatches += memcmp(hits, check, counts[set] * sizeof *hits) != 0;
        }

  /* Embree 3 on the same rays with as many threads as the native backend. */
  double embree[2] = {0, 0};
#ifdef LT_HAVE_EMBREE
  int threads = lt_context_work_groups(ctx[0]);
  lt_embree *e = lt_embree_build(scene, threads, &(double){0});
  for (int set = 0; e && set < 2; set++) {
    double t[MAX_RUNS];
    lt_embree_trace(e, rays[set], counts[set], 0, check);
    for (int run = 0; run < runs; run++) t[run] = lt_embree_trace(e, rays[set], counts[set], 0, check);
    embree[set] = lt_bench_median(t, runs);
  }
  if (e) lt_embree_release(e);
#endif

  /* The table. */
  int binary_depth = 0, qbvh_depth = 0;
  lt_ray *both = malloc((counts[0] + counts[1]) * sizeof *both);
  memcpy(both, rays[0], counts[0] * sizeof *both), memcpy(both + counts[0], rays[1], counts[1] * sizeof *both);
  int deepest = qbvh_deepest(scene, both, counts[0] + counts[1], &binary_depth, &qbvh_depth);
  printf("Scene `%s`: %zu triangles, %dx%d primary rays, %zu diffuse rays; trace only, %d runs, medians.\n\n", spec,
         lt_scene_triangle_count(scene), size, size, counts[1], runs);
  printf("| backend | method | node bytes | memory bytes | depth | primary Mrays/s | diffuse Mrays/s | primary vs BVH2 "
         "| diffuse vs BVH2 |\n");
  printf("|---|---|---:|---:|---:|---:|---:|---:|---:|\n");
  for (int b = 0; b < 2; b++)
    for (int k = 0; ctx[b] && k < METHODS; k++) {
      if (!m[b][k].s) continue;
      lt_stats *stats;
      lt_stats_create(&stats);
      lt_structure_trace(m[b][k].s, rays[0], 1, LT_QUERY_CLOSEST, check, stats);
      double rate[2], base[2];
      for (int set = 0; set < 2; set++) {
        rate[set] = counts[set] / 1e3 / lt_bench_median(m[b][k].ms[set], runs);
        base[set] = counts[set] / 1e3 / lt_bench_median(m[b][BVH2].ms[set], runs);
      }
      char depth[16] = "-";
      if (lt_stats_get(stats, "max_depth") >= 0) snprintf(depth, sizeof depth, "%.0f", lt_stats_get(stats, "max_depth"));
      printf("| %s | %s | %.0f | %.0f | %s | %.2f | %.2f | %.2fx | %.2fx |\n", backend[b], method_names[k],
             lt_stats_get(stats, "node_bytes"), lt_stats_get(stats, "memory_bytes"), depth, rate[0], rate[1],
             rate[0] / base[0], rate[1] / base[1]);
      lt_stats_destroy(stats);
    }
  if (embree[0] > 0) {
    double base[2];
    for (int set = 0; set < 2; set++) base[set] = counts[set] / 1e3 / lt_bench_median(m[0][BVH2].ms[set], runs);
    printf("| native threads | Embree 3 (robust) | - | - | - | %.2f | %.2f | %.2fx | %.2fx |\n", counts[0] / 1e3 / embree[0],
           counts[1] / 1e3 / embree[1], counts[0] / 1e3 / embree[0] / base[0], counts[1] / 1e3 / embree[1] / base[1]);
  }
  printf("\nStack: the binary tree is %d levels deep, the QBVH %d (the most entries each traversal can hold); the "
         "QBVH traversal held at most %d entries on these rays. Hits of every method and backend %s.\n",
         binary_depth, qbvh_depth, deepest, mismatches ? "DIFFER" : "are identical");

  for (int b = 0; b < 2; b++)
    for (int k = 0; ctx[b] && k < METHODS; k++) lt_structure_destroy(m[b][k].s);
  for (int b = 0; b < 2; b++)
    if (ctx[b]) lt_context_destroy(ctx[b]);
  free(rays[0]), free(rays[1]), free(hits), free(check), free(both);
  lt_scene_destroy(scene);
  return mismatches != 0;
}
