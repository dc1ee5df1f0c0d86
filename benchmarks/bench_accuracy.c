/* What accuracy costs (issue 5; DESIGN.md, "Numerics"): for each accuracy knob, what it buys
 * (leaks on closed-mesh rays, hit disagreements against a double-precision brute-force
 * reference, the tree's SAH cost) and what it costs (build and trace time), with Embree 3 beside
 * it when installed.
 *
 *   bench_accuracy [--runs R] [--scene SPEC] [--size N] [--csv FILE]
 *       (defaults: 3 runs, timings on `house` with NxN = 512x512 primary rays)
 *
 * Closed-mesh rays: 50,000 rays from inside sphere:6 (81,920 triangles) aimed exactly at its
 * vertices (half from the centre, half from points inside), and 9,000 more at the vertices,
 * edge midpoints and random directions of a torus, a cube of shared edges and a sphere moved
 * to 1e6 (tests/hard_cases.c). Disagreements: camera and random rays on the timing scene plus
 * closed-mesh rays on sphere:4, against brute force in double. Timings are medians of R runs,
 * settings interleaved run by run, native backend. Markdown goes to stdout, CSV to --csv. */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "builders/host/bvh_sweep.h"
#include "lazytrace.h"
#include "runtime/bvh_ondemand_host.h"
#include "runtime/structure_internal.h"
#include "tests/hard_cases.h"
#include "tests/support.h"
#include "traversal/ray.h"
#ifdef LT_HAVE_EMBREE
#include "benchmarks/embree_peer.h"
#endif

#define MAX_RUNS 16

static int compare_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}
static double median(const double *v, int n) {
  double s[MAX_RUNS];
  memcpy(s, v, n * sizeof *s);
  qsort(s, n, sizeof *s, compare_double);
  return n % 2 ? s[n / 2] : 0.5 * (s[n / 2 - 1] + s[n / 2]);
}

/* ---- Ray sets ---- */

typedef struct ray_set {
  const lt_scene *scene;
  lt_ray *rays;
  size_t count;
} ray_set;

/* The closed-mesh ray sets: [0] sphere:6 vertex rays, [1..3] torus, cube, far sphere. */
#define CLOSED_SETS 4
static lt_hc_mesh closed_mesh[CLOSED_SETS];
static ray_set closed[CLOSED_SETS];

static void make_closed_sets(void) {
  lt_hc_mesh far = lt_hc_sphere(3, 23);
  closed_mesh[0] = lt_hc_sphere(6, 7);
  closed_mesh[1] = lt_hc_torus(48, 24);
  closed_mesh[2] = lt_hc_cube(16, 5);
  closed_mesh[3] = lt_hc_transform(&far, 100.0f, 1e6f);
  lt_hc_free(&far);

  /* Exactly at the vertices: from the centre the ray passes through the vertex itself. */
  float *verts;
  size_t nv = lt_hc_vertices(closed_mesh[0].scene, &verts), n = 50000;
  closed[0] = (ray_set){closed_mesh[0].scene, malloc(n * sizeof(lt_ray)), n};
  lt_hc_rays_to_targets(&closed_mesh[0], verts, nv, n, closed[0].rays);
  for (size_t i = 0; i < n; i += 2) {
    closed[0].rays[i].org[0] = closed[0].rays[i].org[1] = closed[0].rays[i].org[2] = 0.0f;
    for (int k = 0; k < 3; k++) closed[0].rays[i].dir[k] = verts[3 * ((i / 2) % nv) + k];
  }
  free(verts);
  for (int s = 1; s < CLOSED_SETS; s++) {
    closed[s] = (ray_set){closed_mesh[s].scene, malloc(3000 * sizeof(lt_ray)), 3000};
    lt_hc_closed_rays(&closed_mesh[s], 11, 3000, closed[s].rays);
  }
}

/* ---- The double-precision reference ---- */

/* A hit in double: the watertight test (Woop, Benthin and Wald 2013) carried out in double,
 * with edge functions of exactly 0 recomputed in long double, so that the reference itself
 * never lets a ray through a shared edge or vertex. Returns 1 and the distance in *out_t. */
static int hit_double(const lt_ray *ray, const float *t, double *out_t) {
  double d[3] = {ray->dir[0], ray->dir[1], ray->dir[2]}, ad[3];
  for (int k = 0; k < 3; k++) ad[k] = fabs(d[k]);
  int kz = ad[0] > ad[1] ? (ad[0] > ad[2] ? 0 : 2) : (ad[1] > ad[2] ? 1 : 2);
  int kx = kz == 2 ? 0 : kz + 1, ky = kx == 2 ? 0 : kx + 1;
  if (d[kz] < 0.0) {
    int swap = kx;
    kx = ky, ky = swap;
  }
  double sx = d[kx] / d[kz], sy = d[ky] / d[kz], sz = 1.0 / d[kz];
  double x[3], y[3], z[3];
  for (int v = 0; v < 3; v++) {
    double a[3];
    for (int k = 0; k < 3; k++) a[k] = (double)t[3 * v + k] - ray->org[k];
    x[v] = a[kx] - sx * a[kz], y[v] = a[ky] - sy * a[kz], z[v] = sz * a[kz];
  }
  double e0 = x[2] * y[1] - y[2] * x[1], e1 = x[0] * y[2] - y[0] * x[2], e2 = x[1] * y[0] - y[1] * x[0];
  if (e0 == 0.0 || e1 == 0.0 || e2 == 0.0) {
    e0 = (double)((long double)x[2] * y[1] - (long double)y[2] * x[1]);
    e1 = (double)((long double)x[0] * y[2] - (long double)y[0] * x[2]);
    e2 = (double)((long double)x[1] * y[0] - (long double)y[1] * x[0]);
  }
  if ((e0 < 0 || e1 < 0 || e2 < 0) && (e0 > 0 || e1 > 0 || e2 > 0)) return 0;
  double det = e0 + e1 + e2;
  if (det == 0.0) return 0;
  *out_t = (e0 * z[0] + e1 * z[1] + e2 * z[2]) / det;
  return 1;
}

typedef struct reference_job {
  const ray_set *set;
  size_t begin, end;
  double *t;
  int *prim;
} reference_job;

static void *reference_range(void *arg) {
  reference_job *j = arg;
  size_t n = lt_scene_triangle_count(j->set->scene);
  const float *tris = lt_scene_triangles(j->set->scene);
  for (size_t i = j->begin; i < j->end; i++) {
    const lt_ray *r = &j->set->rays[i];
    double best = INFINITY, t;
    int prim = -1;
    for (size_t p = 0; p < n; p++)
      if (hit_double(r, tris + 9 * p, &t) && t >= r->tmin && t <= r->tmax && t < best) best = t, prim = (int)p;
    /* Rays outside the contract's valid set miss, as in lazytrace. */
    lt_ray_setup setup = lt_ray_prepare(r->org[0], r->org[1], r->org[2], r->tmin, r->dir[0], r->dir[1], r->dir[2], r->tmax);
    if (!setup.valid) best = INFINITY, prim = -1;
    j->t[i] = best, j->prim[i] = prim;
  }
  return NULL;
}

/* The disagreement set and its reference. */
static ray_set disagree;
static lt_scene *disagree_sphere;
static double *reference_t;
static int *reference_prim;

static void make_reference(const lt_scene *scene, int threads) {
  size_t cam = 64 * 64, random = 2000, sphere_rays = 3000;
  lt_hc_mesh sphere = lt_hc_sphere(4, 3);
  disagree_sphere = sphere.scene;
  /* Two scenes in one set would need two references: the sphere's rays get their own below. */
  disagree = (ray_set){scene, malloc((cam + random) * sizeof(lt_ray)), cam + random};
  lt_test_camera_rays(scene, "close", 64, 64, disagree.rays);
  lt_test_random_rays(scene, 13, random, disagree.rays + cam);
  ray_set sph = {sphere.scene, malloc(sphere_rays * sizeof(lt_ray)), sphere_rays};
  lt_hc_closed_rays(&sphere, 17, sphere_rays, sph.rays);
  free(sphere.inside);

  size_t total = disagree.count + sph.count;
  reference_t = malloc(total * sizeof *reference_t);
  reference_prim = malloc(total * sizeof *reference_prim);
  const ray_set *sets[2] = {&disagree, &sph};
  size_t at = 0;
  for (int s = 0; s < 2; s++) {
    pthread_t workers[16];
    reference_job jobs[16];
    for (int w = 0; w < threads; w++) {
      jobs[w] = (reference_job){sets[s], sets[s]->count * w / threads, sets[s]->count * (w + 1) / threads,
                                reference_t + at, reference_prim + at};
      pthread_create(&workers[w], NULL, reference_range, &jobs[w]);
    }
    for (int w = 0; w < threads; w++) pthread_join(workers[w], NULL);
    at += sets[s]->count;
  }

  /* Keep the sphere's rays behind the scene's, in one array, and remember where they start. */
  disagree.rays = realloc(disagree.rays, total * sizeof(lt_ray));
  memcpy(disagree.rays + disagree.count, sph.rays, sph.count * sizeof(lt_ray));
  free(sph.rays);
}
static size_t disagree_scene_rays(void) { return 64 * 64 + 2000; }
static size_t disagree_total(void) { return disagree_scene_rays() + 3000; }

/* A ray disagrees when it hits where the reference misses or the other way round, or when its
 * hit point lies measurably elsewhere along the ray: by more than 1e-5 of the coordinates'
 * magnitude (float carries 6e-8 of it).
 * A different triangle at the same distance, at a shared edge or vertex, is no disagreement. */
static int far_apart(const lt_ray *r, double t, double ref) {
  double o = 0, d = 0;
  for (int k = 0; k < 3; k++) o = fmax(o, fabs(r->org[k])), d = fmax(d, fabs(r->dir[k]));
  return fabs(t - ref) * d > 1e-5 * (o + fabs(ref) * d);
}

static size_t count_disagreements(const lt_hit *hits) {
  size_t bad = 0;
  for (size_t i = 0; i < disagree_total(); i++) {
    int ours = hits[i].prim, ref = reference_prim[i];
    if ((ours < 0) != (ref < 0)) bad++;
    else if (ours >= 0 && far_apart(&disagree.rays[i], hits[i].t, reference_t[i])) bad++;
  }
  if (getenv("LT_ACCURACY_DEBUG"))
    for (size_t i = 0; i < disagree_total(); i++)
      if ((hits[i].prim < 0) != (reference_prim[i] < 0) ||
          (hits[i].prim >= 0 && far_apart(&disagree.rays[i], hits[i].t, reference_t[i])))
        fprintf(stderr, "ray %zu: ours %d t %.9g, double %d t %.9g\n", i, hits[i].prim, hits[i].t, reference_prim[i], reference_t[i]);
  return bad;
}

/* ---- Settings ---- */

enum { POOL, LBVH, HOST, KD, GRID, IRGRID, EMBREE };

typedef struct setting {
  const char *knob, *value, *builder;
  int how;            /* POOL, LBVH, HOST (bins 0: sweep), KD or EMBREE */
  int bins, leaf;
  int kd_split, kd_clip, kd_traversal; /* the kd-tree's choices (KD) */
  float density, top_density, cell_density; /* the grids' densities (GRID, IRGRID; 0: default) */
  int merge;                           /* the irregular grid's merging (0: default) */
  lt_build_mode build;
  int flags;          /* LT_QUERY_FLAG_FAST_TRIANGLES, LT_QUERY_FLAG_PLAIN_SLABS */
  /* measured */
  size_t leaks_vertex, leaks_other, disagreements;
  double sah_cost, references;
  double steps, tests, memory; /* per ray, per ray, bytes (grids; deterministic) */
  double build_ms[MAX_RUNS], trace_ms[MAX_RUNS];
  int ok;
} setting;

static lt_context *native;

/* The SAH cost of a pool-built tree: node 0 is the super-root whose left child is the root. */
static double subtree_cost(const lt_bvh_node *nodes, int link, int count, const float lo[3], const float hi[3],
                           double *inner, double *leaves) {
  double d[3];
  for (int k = 0; k < 3; k++) d[k] = hi[k] > lo[k] ? (double)hi[k] - lo[k] : 0.0;
  double area = 2.0 * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0]);
  if (count > 0) return *leaves += count * area, area;
  if (link < 0) return 0.0;
  *inner += area;
  const lt_bvh_node *n = &nodes[link];
  float llo[3] = {n->left_xy.x, n->left_xy.z, n->lr_z.x}, lhi[3] = {n->left_xy.y, n->left_xy.w, n->lr_z.y};
  float rlo[3] = {n->right_xy.x, n->right_xy.z, n->lr_z.z}, rhi[3] = {n->right_xy.y, n->right_xy.w, n->lr_z.w};
  subtree_cost(nodes, n->link[0], n->link[2], llo, lhi, inner, leaves);
  subtree_cost(nodes, n->link[1], n->link[3], rlo, rhi, inner, leaves);
  return area;
}

static double pool_tree_cost(lt_structure *s) {
  lt_bvh_node *nodes;
  int count, *index;
  if (lt__ondemand_snapshot(lt__structure_ondemand(s), &nodes, &count, &index) != LT_OK) return -1;
  const lt_bvh_node *root = &nodes[0];
  float lo[3] = {root->left_xy.x, root->left_xy.z, root->lr_z.x}, hi[3] = {root->left_xy.y, root->left_xy.w, root->lr_z.y};
  double inner = 0, leaves = 0;
  double area = subtree_cost(nodes, root->link[0], root->link[2], lo, hi, &inner, &leaves);
  free(nodes), free(index);
  return area > 0 ? (inner + leaves) / area : 0.0;
}

/* Builds the setting's structure over scene on ctx; build time and SAH cost on request. */
static lt_structure *make(setting *st, lt_context *ctx, const lt_scene *scene, double *build_ms, double *sah) {
  lt_structure *s = NULL;
  double start = lt_now_ms();
  if (st->how == HOST) {
    lt__sah_config config = lt__sah_config_default();
    config.max_leaf_size = st->leaf;
    lt__bvh bvh;
    if (lt__bvh_build_sweep(lt_scene_triangles(scene), lt_scene_triangle_count(scene), &config, st->bins, &bvh)) return NULL;
    if (sah) *sah = bvh.sah_cost, st->references = (double)lt_scene_triangle_count(scene);
    if (lt__structure_from_bvh(ctx, scene, &bvh, &s)) return lt__bvh_free(&bvh), NULL;
  } else {
    lt_structure_kind kind = st->how == LBVH     ? LT_STRUCTURE_LBVH
                             : st->how == KD     ? LT_STRUCTURE_KDTREE
                             : st->how == GRID   ? LT_STRUCTURE_GRID
                             : st->how == IRGRID ? LT_STRUCTURE_IRGRID
                                                 : LT_STRUCTURE_BVH;
    lt_structure_config config = lt_structure_config_default(kind);
    config.build = st->build, config.max_leaf_size = st->leaf, config.sah_bins = st->bins;
    config.kd_split = st->kd_split, config.kd_clip = st->kd_clip, config.kd_traversal = st->kd_traversal;
    if (st->density > 0) config.grid_density = st->density;
    if (st->top_density > 0) config.irgrid_top_density = st->top_density;
    if (st->cell_density > 0) config.irgrid_cell_density = st->cell_density;
    if (st->merge) config.irgrid_merge = st->merge, config.irgrid_expansion_passes = LT_IRGRID_PASSES(0);
    lt_stats *stats;
    lt_stats_create(&stats);
    if (lt_structure_create(ctx, scene, &config, stats, &s)) {
      fprintf(stderr, "%s %s: %s\n", st->knob, st->value, lt_last_error());
      lt_stats_destroy(stats);
      return NULL;
    }
    if (sah) *sah = st->how == LBVH || st->how == KD ? lt_stats_get(stats, "sah_cost") : st->how >= GRID ? -1 : pool_tree_cost(s);
    if (sah) st->references = lt_stats_get(stats, "references");
    lt_stats_destroy(stats);
  }
  if (build_ms) *build_ms = lt_now_ms() - start;
  lt__structure_set_flags(s, st->flags);
  return s;
}

/* Leaks and disagreements of a setting (deterministic: measured once). */
static void measure_accuracy(setting *st) {
  st->leaks_vertex = st->leaks_other = 0;
  for (int c = 0; c < CLOSED_SETS; c++) {
    lt_hit *hits = malloc(closed[c].count * sizeof *hits);
#ifdef LT_HAVE_EMBREE
    if (st->how == EMBREE) {
      double ms;
      lt_embree *e = lt_embree_build(closed[c].scene, lt_context_work_groups(native), &ms);
      lt_embree_trace(e, closed[c].rays, closed[c].count, 0, hits);
      lt_embree_release(e);
    }
#endif
    if (st->how != EMBREE) {
      lt_structure *s = make(st, native, closed[c].scene, NULL, NULL);
      lt_structure_trace(s, closed[c].rays, closed[c].count, LT_QUERY_CLOSEST, hits, NULL);
      lt_structure_destroy(s);
    }
    size_t misses = lt_hc_count_misses(hits, closed[c].count);
    if (c == 0) st->leaks_vertex = misses;
    else st->leaks_other += misses;
    free(hits);
  }

  /* Disagreements: the scene's rays, then the sphere's. */
  lt_hit *hits = malloc(disagree_total() * sizeof *hits);
  const lt_scene *scenes[2] = {disagree.scene, disagree_sphere};
  size_t begin[2] = {0, disagree_scene_rays()}, count[2] = {disagree_scene_rays(), 3000};
  for (int p = 0; p < 2; p++) {
#ifdef LT_HAVE_EMBREE
    if (st->how == EMBREE) {
      double ms;
      lt_embree *e = lt_embree_build(scenes[p], lt_context_work_groups(native), &ms);
      lt_embree_trace(e, disagree.rays + begin[p], count[p], 0, hits + begin[p]);
      lt_embree_release(e);
    }
#endif
    if (st->how != EMBREE) {
      lt_structure *s = make(st, native, scenes[p], NULL, NULL);
      lt_structure_trace(s, disagree.rays + begin[p], count[p], LT_QUERY_CLOSEST, hits + begin[p], NULL);
      lt_structure_destroy(s);
    }
  }
  st->disagreements = count_disagreements(hits);
  free(hits);
}

/* One timed run: build and trace the timing rays. */
static void time_run(setting *st, const lt_scene *scene, const lt_ray *rays, size_t n, lt_hit *hits, int run) {
#ifdef LT_HAVE_EMBREE
  if (st->how == EMBREE) {
    lt_embree_times t;
    if (lt_embree_run(scene, rays, n, lt_context_work_groups(native), hits, &t) == 0)
      st->build_ms[run] = t.build_ms, st->trace_ms[run] = t.trace_ms, st->ok = 1;
    return;
  }
#endif
  if (st->how == EMBREE) return;
  double build_ms, sah;
  lt_structure *s = make(st, native, scene, &build_ms, run == 0 ? &sah : NULL);
  if (!s) return;
  if (run == 0) st->sah_cost = sah;
  lt_stats *stats;
  lt_stats_create(&stats);
  double start = lt_now_ms();
  lt_structure_trace(s, rays, n, LT_QUERY_CLOSEST, hits, stats);
  st->trace_ms[run] = lt_now_ms() - start;
  st->steps = lt_stats_get(stats, "traversal_steps") / (double)n, st->tests = lt_stats_get(stats, "intersections") / (double)n;
  st->memory = lt_stats_get(stats, "memory_bytes");
  lt_stats_destroy(stats);
  st->build_ms[run] = build_ms;
  st->ok = 1;
  lt_structure_destroy(s);
}

/* ---- Leaks on every structure, mode and backend ---- */

static void leak_table(FILE *csv) {
  /* Every structure and build mode the registry lists. */
  struct {
    lt_structure_kind kind;
    lt_build_mode build;
  } variants[3 * LT_STRUCTURE_COUNT];
  lt_structure_kind kinds[3 * LT_STRUCTURE_COUNT];
  lt_build_mode modes[3 * LT_STRUCTURE_COUNT];
  size_t variant_count = lt_structure_variants(kinds, modes, 3 * LT_STRUCTURE_COUNT);
  for (size_t v = 0; v < variant_count; v++) variants[v].kind = kinds[v], variants[v].build = modes[v];
  lt_context *contexts[2] = {native, NULL};
  lt_context_config opencl = {LT_DEVICE_OPENCL, 0, 0, 0, 1};
  if (lt_context_create(&opencl, &contexts[1]) != LT_OK) contexts[1] = NULL;
  size_t other_rays = 0;
  for (int c = 1; c < CLOSED_SETS; c++) other_rays += closed[c].count;

  printf("## Leaks on every structure, build mode and backend\n\n");
  printf("Rays from inside closed meshes that find no triangle. Vertex rays: %zu rays at the vertices of sphere:6 "
         "(%zu triangles); other: %zu rays at the vertices, edge midpoints and random directions of a torus, a cube of "
         "shared edges and a radius-100 sphere moved to 1e6.\n\n",
         closed[0].count, lt_scene_triangle_count(closed[0].scene), other_rays);
  printf("| structure | build | backend | watertight: vertex rays | watertight: other | fast: vertex rays | fast: other |\n");
  printf("|---|---|---|---:|---:|---:|---:|\n");
  for (int x = 0; x < 2; x++) {
    if (!contexts[x]) continue;
    for (size_t v = 0; v < variant_count; v++) {
      size_t leaks[2][2] = {{0, 0}, {0, 0}};
      for (int fast = 0; fast < 2; fast++)
        for (int c = 0; c < CLOSED_SETS; c++) {
          lt_structure_config config = lt_structure_config_default(variants[v].kind);
          config.build = variants[v].build, config.intersect = fast ? LT_INTERSECT_FAST : LT_INTERSECT_WATERTIGHT;
          lt_structure *s;
          lt_hit *hits = malloc(closed[c].count * sizeof *hits);
          if (lt_structure_create(contexts[x], closed[c].scene, &config, NULL, &s) != LT_OK ||
              lt_structure_trace(s, closed[c].rays, closed[c].count, LT_QUERY_CLOSEST, hits, NULL) != LT_OK) {
            fprintf(stderr, "leak table: %s\n", lt_last_error());
            exit(1);
          }
          lt_structure_destroy(s);
          leaks[fast][c > 0] += lt_hc_count_misses(hits, closed[c].count);
          free(hits);
        }
      const char *device = x == 0 ? "native" : "opencl";
      printf("| %s | %s | %s | %zu | %zu | %zu | %zu |\n", lt_structure_kind_name(variants[v].kind),
             lt_build_mode_name(variants[v].build), device, leaks[0][0], leaks[0][1], leaks[1][0], leaks[1][1]);
      if (csv)
        fprintf(csv, "leaks,%s %s %s,%s,%zu,%zu,%zu,%zu,,,,\n", lt_structure_kind_name(variants[v].kind),
                lt_build_mode_name(variants[v].build), device, "watertight/fast", leaks[0][0], leaks[0][1], leaks[1][0],
                leaks[1][1]);
    }
  }
  if (contexts[1]) lt_context_destroy(contexts[1]);

  /* Embree on the same rays; the vertex rays split into those from the centre (exactly through
   * the vertex) and those from other points inside. */
  size_t centre = 0, elsewhere = 0, other = 0;
#ifdef LT_HAVE_EMBREE
  for (int c = 0; c < CLOSED_SETS; c++) {
    lt_hit *hits = malloc(closed[c].count * sizeof *hits);
    double ms;
    lt_embree *e = lt_embree_build(closed[c].scene, lt_context_work_groups(native), &ms);
    if (!e) return;
    lt_embree_trace(e, closed[c].rays, closed[c].count, 0, hits);
    lt_embree_release(e);
    for (size_t i = 0; i < closed[c].count; i++)
      if (hits[i].prim < 0) *(c > 0 ? &other : i % 2 == 0 ? &centre : &elsewhere) += 1;
    free(hits);
  }
  printf("| Embree 3 (robust flag) | | native threads | %zu | %zu | | |\n", centre + elsewhere, other);
  printf("\nEmbree's vertex-ray leaks: %zu of the %zu rays from the centre, %zu of the %zu from other points inside "
         "(lazytrace: none of either).\n",
         centre, (closed[0].count + 1) / 2, elsewhere, closed[0].count / 2);
  if (csv) fprintf(csv, "leaks,Embree 3 robust,embree,%zu,%zu,,,,,,\n", centre + elsewhere, other);
#else
  (void)centre, (void)elsewhere, (void)other;
  printf("\nEmbree 3 is not installed: its leak count is not shown.\n");
#endif
}

int main(int argc, char **argv) {
  const char *spec = "house", *csv_path = NULL;
  int runs = 3, size = 512;
  for (int i = 1; i < argc; i++) {
    if (strcmp(argv[i], "--runs") == 0 && i + 1 < argc) runs = atoi(argv[++i]);
    else if (strcmp(argv[i], "--size") == 0 && i + 1 < argc) size = atoi(argv[++i]);
    else if (strcmp(argv[i], "--scene") == 0 && i + 1 < argc) spec = argv[++i];
    else if (strcmp(argv[i], "--csv") == 0 && i + 1 < argc) csv_path = argv[++i];
    else return fprintf(stderr, "usage: bench_accuracy [--runs R] [--scene SPEC] [--size N] [--csv FILE]\n"), 2;
  }
  if (runs < 1 || runs > MAX_RUNS || size < 1) return fprintf(stderr, "bench_accuracy: bad --runs or --size\n"), 2;
  lt_context_config native_config = {LT_DEVICE_NATIVE, 0, 0, 0, 1};
  if (lt_context_create(&native_config, &native) != LT_OK) return fprintf(stderr, "%s\n", lt_last_error()), 1;
  lt_scene *scene;
  if (lt_scene_load(spec, &scene) != LT_OK) return fprintf(stderr, "%s\n", lt_last_error()), 1;
  FILE *csv = csv_path ? fopen(csv_path, "w") : NULL;
  if (csv)
    fprintf(csv, "knob,setting,builder,leaks_vertex_rays,leaks_other_rays,fast_leaks_vertex_rays,fast_leaks_other_rays,"
                 "disagreements,sah_cost,build_ms,trace_ms,references,steps_per_ray,tests_per_ray,memory_bytes\n");

  fprintf(stderr, "bench_accuracy: closed-mesh rays and the double-precision reference...\n");
  make_closed_sets();
  make_reference(scene, lt_context_work_groups(native));
  leak_table(csv);

  /* Every knob's settings; the first of each knob is the default. */
#define SETTING(k, v, b, h, nbins, nleaf, f) \
  { .knob = k, .value = v, .builder = b, .how = h, .bins = nbins, .leaf = nleaf, .build = LT_BUILD_FULL, .flags = f }
#define KD_SETTING(k, v, nleaf, split, clip, traversal)                                                          \
  {.knob = k, .value = v, .builder = "pool, kd-tree", .how = KD, .bins = 32, .leaf = nleaf, .kd_split = split,          \
   .kd_clip = clip, .kd_traversal = traversal, .build = LT_BUILD_FULL}
#define GRID_SETTING(k, v, d) {.knob = k, .value = v, .builder = "pool, uniform grid", .how = GRID, .density = d, .build = LT_BUILD_FULL}
#define IRGRID_SETTING(k, v, top, cell, m)                                                                    \
  {.knob = k, .value = v, .builder = "pool, irregular grid", .how = IRGRID, .top_density = top, .cell_density = cell, \
   .merge = m, .build = LT_BUILD_FULL}
  static setting settings[] = {
      SETTING("intersection test", "watertight (default)", "pool", POOL, 32, 16, 0),
      SETTING("intersection test", "fast (Moller-Trumbore)", "pool", POOL, 32, 16, LT_QUERY_FLAG_FAST_TRIANGLES),
      SETTING("slab test", "robust (default)", "pool", POOL, 32, 16, 0),
      SETTING("slab test", "plain (no rounding bound)", "pool", POOL, 32, 16, LT_QUERY_FLAG_PLAIN_SLABS),
      SETTING("SAH bins", "4", "pool", POOL, 4, 16, 0),
      SETTING("SAH bins", "8", "pool", POOL, 8, 16, 0),
      SETTING("SAH bins", "16", "pool", POOL, 16, 16, 0),
      SETTING("SAH bins", "32 (default)", "pool", POOL, 32, 16, 0),
      SETTING("SAH bins", "32", "host reference (1 thread)", HOST, 32, 16, 0),
      SETTING("SAH bins", "64", "host reference (1 thread)", HOST, 64, 16, 0),
      SETTING("SAH bins", "full sweep", "host reference (1 thread)", HOST, 0, 16, 0),
      SETTING("leaf size", "1", "pool", POOL, 32, 1, 0),
      SETTING("leaf size", "2", "pool", POOL, 32, 2, 0),
      SETTING("leaf size", "4", "pool", POOL, 32, 4, 0),
      SETTING("leaf size", "8", "pool", POOL, 32, 8, 0),
      SETTING("leaf size", "16 (default)", "pool", POOL, 32, 16, 0),
      SETTING("leaf size", "32", "pool", POOL, 32, 32, 0),
      SETTING("structure", "LBVH", "host LBVH", LBVH, 32, 16, 0),
      KD_SETTING("kd-tree split", "binned, 32 bins (default)", 16, LT_KD_SPLIT_BINNED, LT_KD_CLIP_OFF, 0),
      KD_SETTING("kd-tree split", "exact sweep (cells up to 1024 references)", 16, LT_KD_SPLIT_SWEEP, LT_KD_CLIP_OFF, 0),
      KD_SETTING("kd-tree clipping", "off: triangle boxes (default)", 16, 0, LT_KD_CLIP_OFF, 0),
      KD_SETTING("kd-tree clipping", "on: perfect splits", 16, 0, LT_KD_CLIP_ON, 0),
      KD_SETTING("kd-tree clipping", "on, with the exact sweep", 16, LT_KD_SPLIT_SWEEP, LT_KD_CLIP_ON, 0),
      KD_SETTING("kd-tree leaf size", "4", 4, 0, 0, 0),
      KD_SETTING("kd-tree leaf size", "8", 8, 0, 0, 0),
      KD_SETTING("kd-tree leaf size", "16 (default)", 16, 0, 0, 0),
      KD_SETTING("kd-tree leaf size", "32", 32, 0, 0, 0),
      KD_SETTING("kd-tree traversal", "stack (default)", 16, 0, 0, LT_KD_TRAVERSAL_STACK),
      KD_SETTING("kd-tree traversal", "restart (stackless)", 16, 0, 0, LT_KD_TRAVERSAL_RESTART),
      KD_SETTING("kd-tree traversal", "backtrack (stackless)", 16, 0, 0, LT_KD_TRAVERSAL_BACKTRACK),
      GRID_SETTING("uniform grid density", "1", 1.0f),
      GRID_SETTING("uniform grid density", "3 (default)", 3.0f),
      GRID_SETTING("uniform grid density", "7", 7.0f),
      IRGRID_SETTING("irregular grid lambda1 : lambda2", "0.012 : 0.24", 0.012f, 0.24f, 0),
      IRGRID_SETTING("irregular grid lambda1 : lambda2", "0.04 : 0.8", 0.04f, 0.8f, 0),
      IRGRID_SETTING("irregular grid lambda1 : lambda2", "0.12 : 2.4 (default)", 0.12f, 2.4f, 0),
      IRGRID_SETTING("irregular grid lambda1 : lambda2", "0.3 : 6", 0.3f, 6.0f, 0),
      IRGRID_SETTING("irregular grid lambda2", "0.24", 0, 0.24f, 0),
      IRGRID_SETTING("irregular grid lambda2", "8", 0, 8.0f, 0),
      IRGRID_SETTING("two-level grid lambda1 : lambda2", "0.012 : 0.24", 0.012f, 0.24f, LT_IRGRID_MERGE_OFF),
      IRGRID_SETTING("two-level grid lambda1 : lambda2", "0.12 : 2.4", 0.12f, 2.4f, LT_IRGRID_MERGE_OFF),
      SETTING("peer", "Embree 3 (robust flag)", "Embree", EMBREE, 0, 0, 0),
  };
  int count = (int)(sizeof settings / sizeof settings[0]);
  for (int i = 0; i < count; i++) {
    fprintf(stderr, "bench_accuracy: accuracy of %s = %s\n", settings[i].knob, settings[i].value);
#ifndef LT_HAVE_EMBREE
    if (settings[i].how == EMBREE) continue;
#endif
    measure_accuracy(&settings[i]);
  }

  /* Timings: every setting once per run, in order, so that noise hits them alike. */
  size_t n = (size_t)size * size;
  lt_ray *rays = malloc(n * sizeof *rays);
  lt_hit *hits = malloc(n * sizeof *hits);
  lt_camera camera = lt_scene_camera(scene);
  lt_camera_primary_rays(&camera, size, size, rays);
  for (int r = 0; r < runs; r++)
    for (int i = 0; i < count; i++) {
      fprintf(stderr, "bench_accuracy: run %d: %s = %s\n", r + 1, settings[i].knob, settings[i].value);
      time_run(&settings[i], scene, rays, n, hits, r);
    }

  printf("\n## What each knob buys and costs\n\n");
  printf("Leaks: vertex rays (of %zu) / other closed-mesh rays (of %zu). Disagreements: of %zu rays (%zu camera and "
         "random rays on `%s`, 3000 closed-mesh rays on sphere:4) against brute force in double, counting a hit where "
         "the reference misses (or the other way round) and a hit point more than 1e-5 of the coordinates' "
         "magnitude away from the reference's; the reference is the watertight test carried out in double. SAH "
         "cost: of the tree built over `%s` (%zu triangles), relative to one triangle test, inner nodes costing 1 "
         "(BVH nodes and kd-tree cells alike). References: held by leaves (a kd-tree references a straddling "
         "triangle once per leaf). "
         "Times: `%s`, %dx%d primary rays, native backend (%s), medians of %d runs.\n\n",
         closed[0].count, closed[1].count + closed[2].count + closed[3].count, disagree_total(), disagree_scene_rays(),
         spec, spec, lt_scene_triangle_count(scene), spec, size, size, lt_context_device_name(native), runs);
  printf("| knob | setting | builder | leaks: vertex / other | disagreements | SAH cost | references | build ms | trace ms |\n");
  printf("|---|---|---|---:|---:|---:|---:|---:|---:|\n");
  for (int i = 0; i < count; i++) {
    setting *st = &settings[i];
    if (!st->ok || st->how == GRID || st->how == IRGRID) continue;
    double b = median(st->build_ms, runs), t = median(st->trace_ms, runs);
    char sah[32] = "-";
    if (st->how != EMBREE && st->sah_cost > 0) snprintf(sah, sizeof sah, "%.2f", st->sah_cost);
    char refs[32] = "-";
    if (st->how != EMBREE && st->references > 0) snprintf(refs, sizeof refs, "%.0f", st->references);
    printf("| %s | %s | %s | %zu / %zu | %zu | %s | %s | %.1f | %.1f |\n", st->knob, st->value, st->builder,
           st->leaks_vertex, st->leaks_other, st->disagreements, sah, refs, b, t);
    if (csv)
      fprintf(csv, "%s,%s,%s,%zu,%zu,,,%zu,%.4f,%.2f,%.2f,%.0f\n", st->knob, st->value, st->builder, st->leaks_vertex,
              st->leaks_other, st->disagreements, st->how == EMBREE ? 0.0 : st->sah_cost, b, t, st->references);
  }
  printf("\n## Grid densities: what each buys and costs\n\n");
  printf("The grids' densities change the cells, not the answers (their leaks and disagreements are the default "
         "numerics'). Steps: cells visited per ray; tests: triangle tests per ray; memory: the structure's bytes "
         "(cells, references, voxel map, pool). Same rays and runs as above.\n\n");
  printf("| knob | setting | leaks: vertex / other | disagreements | steps / ray | tests / ray | build ms | trace ms | memory MB |\n");
  printf("|---|---|---:|---:|---:|---:|---:|---:|---:|\n");
  for (int i = 0; i < count; i++) {
    setting *st = &settings[i];
    if (!st->ok || (st->how != GRID && st->how != IRGRID)) continue;
    double b = median(st->build_ms, runs), t = median(st->trace_ms, runs);
    printf("| %s | %s | %zu / %zu | %zu | %.1f | %.1f | %.1f | %.1f | %.1f |\n", st->knob, st->value, st->leaks_vertex,
           st->leaks_other, st->disagreements, st->steps, st->tests, b, t, st->memory / 1e6);
    if (csv)
      fprintf(csv, "%s,%s,%s,%zu,%zu,,,%zu,,%.2f,%.2f,,%.3f,%.3f,%.0f\n", st->knob, st->value, st->builder, st->leaks_vertex,
              st->leaks_other, st->disagreements, b, t, st->steps, st->tests, st->memory);
  }
  if (csv) fclose(csv);
  free(rays), free(hits);
  lt_scene_destroy(scene);
  lt_context_destroy(native);
  return 0;
}
