/* The QBVH's native 8-wide AVX2 path against the 4-wide QBVH, the binary SAH BVH they both
 * collapse, and Embree 3 (robust flag, default build, as many threads): trace throughput on
 * the native backend for primary rays (closest hit) and ambient-occlusion rays (any hit,
 * `--ao` samples per primary hit up to 5% of the scene's diagonal, as Table 1's AO rows).
 * Each run traces every method once per ray set, Embree included, in the same order; the
 * first run warms up and is not counted; the table gives medians. Prints one markdown table.
 *
 *   bench_wide_simd SCENE[@camera] [--size N] [--runs R] [--ao S]     (defaults 1024, 5, 2)
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "benchmarks/median.h"
#include "lazytrace.h"
#include "runtime/structure_internal.h"
#ifdef LT_HAVE_EMBREE
#include "benchmarks/embree_peer.h"
#endif

#define MAX_RUNS 32
enum { BVH2, QBVH4, QBVH8, EMBREE, METHODS };
static const char *const method_names[METHODS] = {"BVH2 (the host SAH tree)", "QBVH, 4 wide (LT_QBVH_WIDTH=4)",
                                                  "QBVH, native 8 wide (AVX2)", "Embree 3 (robust)"};
enum { PRIMARY, AO, SETS };

/* The structure of method m: the host SAH BVH traced by the binary kernel, or the QBVH with
 * the 4-wide path forced or the native default. */
static lt_structure *make(lt_context *ctx, const lt_scene *scene, int m) {
  lt_structure *s = NULL;
  if (m == BVH2) {
    lt__bvh bvh;
    lt__sah_config sah = lt__sah_config_default();
    if (lt__bvh_build_sah(lt_scene_triangles(scene), lt_scene_triangle_count(scene), &sah, &bvh)) return NULL;
    if (lt__structure_from_bvh(ctx, scene, &bvh, &s)) return lt__bvh_free(&bvh), NULL;
    return s;
  }
  lt_structure_config c = lt_structure_config_default(LT_STRUCTURE_QBVH);
  if (m == QBVH4) setenv("LT_QBVH_WIDTH", "4", 1);
  lt_status status = lt_structure_create(ctx, scene, &c, NULL, &s);
  unsetenv("LT_QBVH_WIDTH");
  if (status) fprintf(stderr, "%s\n", lt_last_error());
  return status ? NULL : s;
}

int main(int argc, char **argv) {
  const char *spec = NULL;
  int size = 1024, runs = 5, ao = 2;
  for (int i = 1; i < argc; i++) {
    if (strcmp(argv[i], "--size") == 0 && i + 1 < argc)
      size = atoi(argv[++i]);
    else if (strcmp(argv[i], "--runs") == 0 && i + 1 < argc)
      runs = atoi(argv[++i]);
    else if (strcmp(argv[i], "--ao") == 0 && i + 1 < argc)
      ao = atoi(argv[++i]);
    else if (argv[i][0] != '-')
      spec = argv[i];
    else
      spec = NULL, i = argc;
  }
  if (!spec || runs < 1 || runs > MAX_RUNS || size < 1 || ao < 1)
    return fprintf(stderr, "usage: bench_wide_simd SCENE[@camera] [--size N] [--runs R (1-%d)] [--ao S]\n", MAX_RUNS),
           2;

  /* The native context and the three structures. */
  lt_scene *scene;
  if (lt_scene_load(spec, &scene) != LT_OK) return fprintf(stderr, "%s\n", lt_last_error()), 1;
  lt_context *ctx;
  lt_context_config config = {LT_DEVICE_NATIVE, 0, 0, 0, 1};
  if (lt_context_create(&config, &ctx) != LT_OK) return fprintf(stderr, "%s\n", lt_last_error()), 1;
  lt_structure *s[METHODS] = {NULL};
  for (int m = 0; m < EMBREE; m++)
    if (!(s[m] = make(ctx, scene, m))) return fprintf(stderr, "%s failed\n", method_names[m]), 1;

  /* The rays: primary, then AO from every primary hit. */
  size_t n = (size_t)size * size;
  lt_ray *rays[SETS] = {malloc(n * sizeof(lt_ray)), malloc(n * (size_t)ao * sizeof(lt_ray))};
  lt_hit *ref[SETS] = {malloc(n * sizeof(lt_hit)), malloc(n * (size_t)ao * sizeof(lt_hit))};
  lt_hit *check = malloc(n * (size_t)ao * sizeof(lt_hit));
  if (!rays[PRIMARY] || !rays[AO] || !ref[PRIMARY] || !ref[AO] || !check) return 1;
  lt_camera camera = lt_scene_camera(scene);
  lt_camera_primary_rays(&camera, size, size, rays[PRIMARY]);
  size_t counts[SETS] = {n, 0};
  float lo[3], hi[3];
  lt_scene_bounds(scene, lo, hi);
  float diag =
      sqrtf((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
  if (lt_structure_trace(s[BVH2], rays[PRIMARY], n, LT_QUERY_CLOSEST, ref[PRIMARY], NULL)) return 1;
  counts[AO] = lt_ao_rays(scene, rays[PRIMARY], ref[PRIMARY], n, ao, 0.05f * diag, 1, rays[AO]);
  const int query[SETS] = {LT_QUERY_CLOSEST, LT_QUERY_ANY};

#ifdef LT_HAVE_EMBREE
  double embree_build_ms;
  lt_embree *e = lt_embree_build(scene, lt_context_work_groups(ctx), &embree_build_ms);
#endif

  /* Runs: every method and ray set once per run, in the same order; run -1 warms up. Our
   * methods' hits must be the binary BVH's (closest: bit for bit; AO: the same occlusion). */
  double ms[METHODS][SETS][MAX_RUNS] = {{{0}}};
  double steps[METHODS][SETS] = {{0}}, tests[METHODS][SETS] = {{0}}, node_bytes[METHODS] = {0};
  int mismatches = 0;
  size_t embree_disagree[SETS] = {0, 0};
  if (lt_structure_trace(s[BVH2], rays[AO], counts[AO], LT_QUERY_ANY, ref[AO], NULL)) return 1;
  for (int run = -1; run < runs; run++)
    for (int set = 0; set < SETS; set++)
      for (int m = 0; m < METHODS; m++) {
        if (m == EMBREE) {
#ifdef LT_HAVE_EMBREE
          if (!e) continue;
          double t = lt_embree_trace(e, rays[set], counts[set], set == AO, check);
          if (run >= 0) ms[m][set][run] = t;
          for (size_t i = 0; run < 0 && i < counts[set]; i++)
            embree_disagree[set] +=
                set == AO ? (check[i].prim >= 0) != (ref[set][i].prim >= 0) : check[i].prim != ref[set][i].prim;
#endif
          continue;
        }
        lt_stats *stats;
        lt_stats_create(&stats);
        if (lt_structure_trace(s[m], rays[set], counts[set], query[set], check, stats)) return 1;
        if (run >= 0) ms[m][set][run] = lt_stats_get(stats, "trace_ms");
        steps[m][set] = lt_stats_get(stats, "traversal_steps") / (double)counts[set];
        tests[m][set] = lt_stats_get(stats, "intersections") / (double)counts[set];
        node_bytes[m] = lt_stats_get(stats, "node_bytes");
        lt_stats_destroy(stats);
        for (size_t i = 0; run < 0 && i < counts[set]; i++)
          mismatches += set == AO ? (check[i].prim >= 0) != (ref[set][i].prim >= 0)
                                  : memcmp(&check[i], &ref[set][i], sizeof check[i]) != 0;
      }

  /* The table: rates and ratios of medians, steps and triangle tests per ray. */
  printf(
      "Scene `%s`: %zu triangles, %dx%d primary rays, %zu AO rays (%d a hit, any hit); native, %d threads; "
      "trace only, %d runs, medians.\n\n",
      spec, lt_scene_triangle_count(scene), size, size, counts[AO], ao, lt_context_work_groups(ctx), runs);
  printf(
      "| method | node bytes | primary Mrays/s | AO Mrays/s | primary vs Embree | AO vs Embree | primary vs QBVH "
      "| AO vs QBVH | steps / tests per primary ray | steps / tests per AO ray |\n");
  printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  double rate[METHODS][SETS];
  for (int m = 0; m < METHODS; m++)
    for (int set = 0; set < SETS; set++) {
      double med = lt_bench_median(ms[m][set], runs);
      rate[m][set] = med > 0 ? counts[set] / 1e3 / med : 0;
    }
  for (int m = 0; m < METHODS; m++) {
    if (rate[m][PRIMARY] == 0) continue;
    char bytes[32] = "-", per[SETS][48] = {"-", "-"};
    if (m != EMBREE) {
      snprintf(bytes, sizeof bytes, "%.0f", node_bytes[m]);
      for (int set = 0; set < SETS; set++)
        snprintf(per[set], sizeof per[set], "%.2f / %.2f", steps[m][set], tests[m][set]);
    }
    double e_p = rate[EMBREE][PRIMARY], e_a = rate[EMBREE][AO];
    printf("| %s | %s | %.2f | %.2f | %s%.2fx | %s%.2fx | %.2fx | %.2fx | %s | %s |\n", method_names[m], bytes,
           rate[m][PRIMARY], rate[m][AO], e_p > 0 ? "" : "(no Embree) ", e_p > 0 ? rate[m][PRIMARY] / e_p : 0,
           e_a > 0 ? "" : "(no Embree) ", e_a > 0 ? rate[m][AO] / e_a : 0, rate[m][PRIMARY] / rate[QBVH4][PRIMARY],
           rate[m][AO] / rate[QBVH4][AO], per[PRIMARY], per[AO]);
  }
  printf(
      "\nHits: the three lazytrace methods %s (closest hits bit for bit, AO occlusion). Embree differs from them on "
      "%zu primary rays (triangle hit) and %zu AO rays (occlusion).\n",
      mismatches ? "DIFFER" : "agree", embree_disagree[PRIMARY], embree_disagree[AO]);

#ifdef LT_HAVE_EMBREE
  if (e) lt_embree_release(e);
#endif
  for (int m = 0; m < EMBREE; m++) lt_structure_destroy(s[m]);
  lt_context_destroy(ctx);
  free(rays[0]), free(rays[1]), free(ref[0]), free(ref[1]), free(check);
  lt_scene_destroy(scene);
  return mismatches != 0;
}
