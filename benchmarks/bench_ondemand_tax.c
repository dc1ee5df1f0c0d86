/* The persistent kernel's tax on a finished tree (issue 16): a tree built completely through
 * the pool, then the same rays traced once through the persistent (on-demand) kernel and once
 * through the plain trace kernel of finished trees, run by run alternated, on primary rays and
 * on ambient-occlusion rays from their hits. Both are timed around the whole call (uploads,
 * launch, read-back), as a caller sees them, in wall-clock time and in CPU time summed over the
 * process's threads (which a machine shared with other work disturbs less); hits must be
 * identical. Prints one table row per backend and ray set: medians of the runs and the median
 * of the paired ratios.
 *
 *   bench_ondemand_tax SCENE[@camera] [--structure bvh|kdtree] [--size N] [--runs R]
 *                      [--device native|opencl|both] [--groups G]
 *                      (defaults: bvh, 1024, 5, both, as many work-groups as run at once)
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#include "benchmarks/median.h"
#include "lazytrace.h"
#include "runtime/bvh_ondemand_host.h"
#include "runtime/kd_ondemand_host.h"

#define MAX_RUNS 64
enum { PRIMARY, AO, SETS };
static const char *const set_names[SETS] = {"primary", "AO (1 ray per hit)"};

/* CPU time of every thread of the process so far, in ms. */
static double cpu_ms(void) {
  struct rusage u;
  getrusage(RUSAGE_SELF, &u);
  return (u.ru_utime.tv_sec + u.ru_stime.tv_sec) * 1e3 + (u.ru_utime.tv_usec + u.ru_stime.tv_usec) * 1e-3;
}

/* One trace of the finished tree through the persistent kernel (no building: every link is
 * built, and speculation is off). */
static lt_status trace_persistent(lt_structure *s, int kd, const lt_ray *rays, size_t n, lt_hit *hits) {
  if (kd) return lt__kd_launch(lt__structure_kd(s), rays, (int)n, LT_QUERY_CLOSEST, hits, 0, NULL);
  return lt__ondemand_launch(lt__structure_ondemand(s), rays, (int)n, LT_QUERY_CLOSEST, hits, 0, NULL);
}

int main(int argc, char **argv) {
  const char *spec = NULL, *device = "both";
  int size = 1024, runs = 5, kd = 0, groups = 0;
  for (int i = 1; i < argc; i++) {
    if (strcmp(argv[i], "--size") == 0 && i + 1 < argc) size = atoi(argv[++i]);
    else if (strcmp(argv[i], "--runs") == 0 && i + 1 < argc) runs = atoi(argv[++i]);
    else if (strcmp(argv[i], "--structure") == 0 && i + 1 < argc) kd = strcmp(argv[++i], "kdtree") == 0;
    else if (strcmp(argv[i], "--device") == 0 && i + 1 < argc) device = argv[++i];
    else if (strcmp(argv[i], "--groups") == 0 && i + 1 < argc) groups = atoi(argv[++i]);
    else if (argv[i][0] != '-') spec = argv[i];
    else spec = NULL, i = argc;
  }
  if (!spec || runs < 1 || runs > MAX_RUNS || size < 1 || groups < 0)
    return fprintf(stderr,
                   "usage: bench_ondemand_tax SCENE[@camera] [--structure bvh|kdtree] [--size N] [--runs R (1-%d)] "
                   "[--device native|opencl|both] [--groups G]\n",
                   MAX_RUNS),
           2;

  /* The rays: primary, and one AO ray from every primary hit (found by a host reference). */
  lt_scene *scene;
  if (lt_scene_load(spec, &scene) != LT_OK) return fprintf(stderr, "%s\n", lt_last_error()), 1;
  size_t n = (size_t)size * size, counts[SETS] = {n, 0};
  lt_ray *rays[SETS] = {malloc(n * sizeof(lt_ray)), malloc(n * sizeof(lt_ray))};
  lt_hit *hits[2] = {malloc(n * sizeof(lt_hit)), malloc(n * sizeof(lt_hit))};
  if (!rays[0] || !rays[1] || !hits[0] || !hits[1]) return fprintf(stderr, "out of memory\n"), 1;
  lt_camera camera = lt_scene_camera(scene);
  lt_camera_primary_rays(&camera, size, size, rays[PRIMARY]);

  printf("Scene `%s`: %zu triangles, %s built in full through the pool; %dx%d primary rays; %d runs, "
         "persistent and plain alternated run by run; ms around the whole trace call.\n\n",
         spec, lt_scene_triangle_count(scene), kd ? "kd-tree" : "BVH", size, size, runs);
  printf("| backend | rays | count | persistent ms | plain ms | persistent / plain (median of paired ratios) "
         "| persistent CPU ms | plain CPU ms | CPU persistent / plain |\n");
  printf("|---|---|---:|---:|---:|---:|---:|---:|---:|\n");
  int mismatches = 0;
  for (int b = 0; b < 2; b++) {
    if (strcmp(device, "both") != 0 && strcmp(device, b ? "opencl" : "native") != 0) continue;
    lt_context_config config = {b ? LT_DEVICE_OPENCL : LT_DEVICE_NATIVE, 0, groups, 0, 1};
    lt_context *ctx;
    if (lt_context_create(&config, &ctx) != LT_OK) {
      fprintf(stderr, "%s: %s\n", b ? "OpenCL" : "native", lt_last_error());
      continue;
    }
    lt_structure_config sc = lt_structure_config_default(kd ? LT_STRUCTURE_KDTREE : LT_STRUCTURE_BVH);
    sc.build = LT_BUILD_FULL;
    lt_structure *s;
    if (lt_structure_create(ctx, scene, &sc, NULL, &s) != LT_OK) return fprintf(stderr, "%s\n", lt_last_error()), 1;
    if (lt_structure_trace(s, rays[PRIMARY], n, LT_QUERY_CLOSEST, hits[0], NULL)) return 1;
    if (counts[AO] == 0) counts[AO] = lt_ao_rays(scene, rays[PRIMARY], hits[0], n, 1, INFINITY, 7, rays[AO]);

    for (int set = 0; set < SETS; set++) {
      /* Runs: persistent then plain, or plain then persistent, alternating; the first pair
       * warms up (kernel compiles, page faults) and is not counted. */
      double ms[2][MAX_RUNS], ratio[MAX_RUNS], cpu[2][MAX_RUNS], cpu_ratio[MAX_RUNS];
      for (int run = -1; run < runs; run++) {
        for (int k = 0; k < 2; k++) {
          int persistent = (k + run) % 2 == 0;
          double begin = lt_now_ms(), cpu_begin = cpu_ms();
          lt_status status = persistent ? trace_persistent(s, kd, rays[set], counts[set], hits[persistent])
                                        : lt_structure_trace(s, rays[set], counts[set], LT_QUERY_CLOSEST,
                                                             hits[persistent], NULL);
          double t = lt_now_ms() - begin, c = cpu_ms() - cpu_begin;
          if (status) return fprintf(stderr, "%s\n", lt_last_error()), 1;
          if (run >= 0) ms[persistent ? 0 : 1][run] = t, cpu[persistent ? 0 : 1][run] = c;
        }
        if (run < 0) mismatches += memcmp(hits[0], hits[1], counts[set] * sizeof(lt_hit)) != 0;
        else ratio[run] = ms[0][run] / ms[1][run], cpu_ratio[run] = cpu[0][run] / cpu[1][run];
      }
      printf("| %s | %s | %zu | %.1f | %.1f | %.2f | %.1f | %.1f | %.2f |\n", b ? "OpenCL" : "native", set_names[set],
             counts[set], lt_bench_median(ms[0], runs), lt_bench_median(ms[1], runs), lt_bench_median(ratio, runs),
             lt_bench_median(cpu[0], runs), lt_bench_median(cpu[1], runs), lt_bench_median(cpu_ratio, runs));
    }
    lt_structure_destroy(s);
    lt_context_destroy(ctx);
  }
  printf("\nHits of the persistent and the plain kernel %s.\n", mismatches ? "DIFFER" : "are identical");
  free(rays[0]), free(rays[1]), free(hits[0]), free(hits[1]);
  lt_scene_destroy(scene);
  return mismatches != 0;
}
