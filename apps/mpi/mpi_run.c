/* lazytrace under mpirun (the MPI build): trace, render and collide split between the ranks.
 * Each rank opens its own context and on-demand structure over the whole scene and answers only
 * its share of the rays, pixels or agents, so it builds only what its own rays reach; the
 * answers are gathered on rank 0, which writes the one output file, whole or not at all.
 *
 * Every rank goes through the same collective steps whatever happens, and after each local step
 * the ranks agree on whether any of them failed: then rank 0 names each failed rank and its
 * cause, nothing is written, and every rank exits 1. This file is a thin layer over the public
 * API (lt_rays_read_part, lt_render_part, lt_structure_trace); the library holds no global state,
 * so nothing else knows about MPI. */
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "apps/cli.h"

#define MESSAGE_BYTES 512

/* One rank's view of the run. */
typedef struct run {
  int rank, ranks;
  int local_ranks; /* ranks on this machine, sharing its cores */
  int work_groups; /* the persistent work-groups this rank launches */
  char error[MESSAGE_BYTES]; /* this rank's first failure: what, then why; "" if none */
  double start_ms, gather_ms;
  double tiles; /* --split queue: the tiles this rank rendered; -1 otherwise */
} run;

int lt_mpi_launched(void) {
  /* Open MPI's launcher sets the first; PMIx and PMI launchers (srun, hydra) the others. */
  return getenv("OMPI_COMM_WORLD_SIZE") || getenv("PMIX_RANK") || getenv("PMI_RANK");
}

/* Records this rank's first failure ("what: cause"); returns 1. */
static int fail(run *m, const char *what, lt_status status) {
  if (!m->error[0])
    snprintf(m->error, sizeof m->error, "%s: %s", what, *lt_last_error() ? lt_last_error() : lt_status_str(status));
  return 1;
}

/* Every rank calls this at the same points. Returns nonzero on every rank if any rank has
 * failed; rank 0 then names each failed rank and its cause. */
static int any_failed(run *m) {
  int mine = m->error[0] != 0, any = 0, done = 0;
  /* A rank that finished its share waits here for the others. Open MPI's blocking collectives
   * poll without pause, which takes a core from the ranks still tracing when ranks share a
   * machine: so the wait polls a non-blocking reduction and sleeps between polls. */
  MPI_Request request;
  MPI_Iallreduce(&mine, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD, &request);
  for (MPI_Test(&request, &done, MPI_STATUS_IGNORE); !done; MPI_Test(&request, &done, MPI_STATUS_IGNORE))
    nanosleep(&(struct timespec){0, 200000}, NULL);
  if (!any) return 0;
  char *all = m->rank == 0 ? calloc((size_t)m->ranks, MESSAGE_BYTES) : NULL;
  MPI_Gather(m->error, MESSAGE_BYTES, MPI_CHAR, all, MESSAGE_BYTES, MPI_CHAR, 0, MPI_COMM_WORLD);
  if (m->rank == 0) {
    for (int r = 0; all && r < m->ranks; r++)
      if (all[(size_t)r * MESSAGE_BYTES])
        fprintf(stderr, "lazytrace: rank %d of %d failed: %.*s\n", r, m->ranks, MESSAGE_BYTES - 1,
                all + (size_t)r * MESSAGE_BYTES);
    fprintf(stderr, "lazytrace: every rank stopped; no output written\n");
    free(all);
  }
  return 1;
}

/* The items (rays, pixels, agents) of this rank: a contiguous share [first, first + count), or
 * with --split interleaved the items first + j * ranks. */
typedef struct share {
  size_t first, count, stride;
} share;

static share share_of(const run *m, const lt_cli *cli, size_t items) {
  size_t q = items / (size_t)m->ranks, rem = items % (size_t)m->ranks, r = (size_t)m->rank;
  if (cli->interleaved)
    return (share){r, r < items ? (items - r + (size_t)m->ranks - 1) / (size_t)m->ranks : 0, (size_t)m->ranks};
  size_t lo = q * r + rem * r / (size_t)m->ranks, hi = q * (r + 1) + rem * (r + 1) / (size_t)m->ranks;
  return (share){lo, hi - lo, 1};
}

/* The scene and a context on every rank. Ranks on one machine share its cores: unless
 * --work-groups is given, each launches cores / local ranks persistent work-groups (at least
 * one), so that the ranks together run what one process would. */
static int open_rank(run *m, lt_cli *cli, lt_context **ctx, lt_scene **scene, lt_stats *stats) {
  *ctx = NULL, *scene = NULL;
  double start = lt_now_ms();
  lt_status status = lt_scene_load(cli->scene, scene);
  if (status) return *scene = NULL, fail(m, "loading the scene", status);
  lt_stats_set(stats, "load_ms", lt_now_ms() - start);
  lt_context_config config = cli->context;
  if (config.work_groups == 0) {
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    config.work_groups = cores / m->local_ranks > 1 ? (int)(cores / m->local_ranks) : 1;
  }
  config.quiet = config.quiet || m->rank > 0;
  status = lt_context_create(&config, ctx);
  if (status) return *ctx = NULL, fail(m, "opening the device", status);
  m->work_groups = lt_context_work_groups(*ctx);
  if (m->rank == 0)
    fprintf(stderr, "lazytrace: %s: %zu triangles; %d ranks (%s), %d work-group%s each on %s\n", cli->scene,
            lt_scene_triangle_count(*scene), m->ranks,
            cli->interleaved                                           ? "interleaved"
            : cli->queue && strcmp(cli->command, "render") == 0 ? "a queue of tiles"
                                                                       : "contiguous shares",
            m->work_groups, m->work_groups == 1 ? "" : "s", lt_context_device_name(*ctx));
  return 0;
}

/* Gathers count records of `bytes` each from every rank to rank 0, in rank order, into all
 * (rank 0 only; it holds the sum of the counts). */
static void gather(run *m, const void *mine, size_t count, size_t bytes, void *all) {
  double start = lt_now_ms();
  MPI_Datatype record;
  MPI_Type_contiguous((int)bytes, MPI_BYTE, &record);
  MPI_Type_commit(&record);
  int n = (int)count, *counts = NULL, *offsets = NULL;
  if (m->rank == 0) counts = calloc((size_t)m->ranks, sizeof *counts), offsets = calloc((size_t)m->ranks, sizeof *offsets);
  MPI_Gather(&n, 1, MPI_INT, counts, 1, MPI_INT, 0, MPI_COMM_WORLD);
  for (int r = 1; m->rank == 0 && r < m->ranks; r++) offsets[r] = offsets[r - 1] + counts[r - 1];
  MPI_Gatherv(mine, n, record, all, counts, offsets, record, 0, MPI_COMM_WORLD);
  MPI_Type_free(&record);
  free(counts), free(offsets);
  m->gather_ms += lt_now_ms() - start;
}

/* Puts items gathered in rank order back in item order (rank 0): the inverse of share_of. */
static void unshare(const run *m, const lt_cli *cli, const char *gathered, size_t items, size_t bytes, char *out) {
  size_t at = 0;
  for (int r = 0; r < m->ranks; r++) {
    run other = *m;
    other.rank = r;
    share s = share_of(&other, cli, items);
    for (size_t j = 0; j < s.count; j++, at++) memcpy(out + (s.first + j * s.stride) * bytes, gathered + at * bytes, bytes);
  }
}

/* ---- Statistics: totals summed, times the slowest rank's, one record per rank ---- */

/* Keys that are the same on every rank (the scene's) or not additive: rank 0's value. */
static int same_on_every_rank(const char *key) {
  static const char *const keys[] = {"triangles", "nodes_full", "skipped_triangles", "cells.top", "sah_cost", NULL};
  for (int i = 0; keys[i]; i++)
    if (strcmp(key, keys[i]) == 0) return 1;
  return 0;
}

/* The per-rank record's keys, in the order "per_rank" lists them; the last is the run's own
 * (--split queue's tiles taken), not a statistic, and listed only where it is known. */
static const char *const rank_keys[] = {"rays", "nodes_built", "build_ms", "trace_ms", "total_ms", "tiles"};
#define RANK_KEYS (sizeof rank_keys / sizeof rank_keys[0])

/* Merges every rank's stats into rank 0's. Build, trace and total time are the slowest rank's
 * (the one with the largest total), so build_ms = total_ms - trace_ms still holds; other times
 * are the largest; counts are sums (nodes_built over ranks counts a node every rank built once
 * per rank). *records gets RANK_KEYS values per rank on rank 0. Collective. */
static void merge_stats(run *m, lt_stats *stats, double **records) {
  size_t keys = 0;
  while (lt_stats_key(keys)) keys++;
  double *mine = malloc((keys + RANK_KEYS) * sizeof *mine);
  double *all = m->rank == 0 ? malloc((keys + RANK_KEYS) * m->ranks * sizeof *all) : NULL;
  if (!mine || (m->rank == 0 && !all)) {
    fprintf(stderr, "lazytrace: rank %d: out of memory for statistics\n", m->rank);
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
  for (size_t k = 0; k < keys; k++) mine[k] = lt_stats_get(stats, lt_stats_key(k));
  for (size_t k = 0; k + 1 < RANK_KEYS; k++) mine[keys + k] = lt_stats_get(stats, rank_keys[k]);
  mine[keys + RANK_KEYS - 1] = m->tiles;
  size_t w = keys + RANK_KEYS;
  MPI_Gather(mine, (int)w, MPI_DOUBLE, all, (int)w, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  free(mine);
  *records = NULL;
  if (m->rank != 0) return;

  size_t total_key = 0;
  while (strcmp(lt_stats_key(total_key), "total_ms") != 0) total_key++;
  int slowest = 0;
  for (int r = 1; r < m->ranks; r++)
    if (all[r * w + total_key] > all[slowest * w + total_key]) slowest = r;
  for (size_t k = 0; k < keys; k++) {
    const char *key = lt_stats_key(k);
    double v = all[k];
    if (strcmp(key, "build_ms") == 0 || strcmp(key, "trace_ms") == 0 || strcmp(key, "total_ms") == 0) {
      v = all[slowest * w + k];
    } else if (strstr(key, "_ms") || strncmp(key, "ms_", 3) == 0 || strcmp(key, "max_depth") == 0) {
      for (int r = 1; r < m->ranks; r++) v = all[r * w + k] > v ? all[r * w + k] : v;
    } else if (!same_on_every_rank(key)) {
      for (int r = 1; r < m->ranks; r++)
        if (all[r * w + k] >= 0) v = (v >= 0 ? v : 0) + all[r * w + k];
    }
    lt_stats_set(stats, key, v);
  }

  /* Each rank's own record, kept for "per_rank". */
  for (int r = 0; r < m->ranks; r++) memmove(all + r * RANK_KEYS, all + r * w + keys, RANK_KEYS * sizeof *all);
  *records = all;
}

/* Rank 0 writes --stats: the merged object, plus "mpi" (ranks, split, work-groups per rank,
 * gather and wall time) and "per_rank" (one record per rank), whole or not at all. */
static int write_stats(run *m, const lt_cli *cli, const lt_stats *stats, const double *records) {
  if (m->rank != 0 || !cli->stats) return 0;
  char *text = NULL;
  size_t bytes = 0;
  FILE *f = open_memstream(&text, &bytes);
  if (!f) return fprintf(stderr, "lazytrace: writing statistics: out of memory\n"), 1;
  lt_status status = lt_stats_write_json(stats, f);
  fflush(f);
  /* The library's object ends with "\n}\n": reopen it to add the ranks. */
  if (!status && bytes >= 3 && strcmp(text + bytes - 3, "\n}\n") == 0) {
    fseeko(f, (off_t)bytes - 3, SEEK_SET);
    fprintf(f, ",\n  \"mpi\": {\"ranks\": %d, \"split\": \"%s\", \"work_groups_per_rank\": %d, \"gather_ms\": %.3f, "
               "\"wall_ms\": %.3f},\n  \"per_rank\": [",
            m->ranks, cli->interleaved ? "interleaved" : cli->queue && strcmp(cli->command, "render") == 0 ? "queue" : "tiles", m->work_groups, m->gather_ms, lt_now_ms() - m->start_ms);
    for (int r = 0; r < m->ranks; r++) {
      fprintf(f, "%s\n    {\"rank\": %d", r ? "," : "", r);
      for (size_t k = 0; k < RANK_KEYS; k++) {
        double v = records[r * RANK_KEYS + k];
        if (v < 0 && k + 1 == RANK_KEYS) continue;
        if (v < 0) fprintf(f, ", \"%s\": null", rank_keys[k]);
        else if (strstr(rank_keys[k], "_ms")) fprintf(f, ", \"%s\": %.3f", rank_keys[k], v);
        else fprintf(f, ", \"%s\": %.0f", rank_keys[k], v);
      }
      fputc('}', f);
    }
    fputs("\n  ]\n}\n", f);
  }
  if (fclose(f) != 0 && !status) status = LT_ERROR_OUT_OF_MEMORY;
  if (!status) {
    if (strcmp(cli->stats, "-") == 0) status = fwrite(text, 1, bytes, stdout) == bytes && fflush(stdout) == 0 ? LT_OK : LT_ERROR_IO;
    else status = lt_file_write(cli->stats, text, bytes);
  }
  free(text);
  return status ? lt_cli_fail("writing statistics", status) : 0;
}

/* The tools' summary line, with the merged figures. */
static void say_totals(const run *m, const lt_stats *stats) {
  if (m->rank != 0) return;
  fprintf(stderr, "lazytrace: %.0f rays on %d ranks: time to image %.0f ms (the slowest rank: build %.0f, trace %.0f); "
                  "%.0f nodes built over all ranks; gather %.1f ms\n",
          lt_stats_get(stats, "rays"), m->ranks, lt_stats_get(stats, "total_ms"), lt_stats_get(stats, "build_ms"),
          lt_stats_get(stats, "trace_ms"), lt_stats_get(stats, "nodes_built"), m->gather_ms);
}

/* ---- trace: the ray file read in shares, the hits gathered in ray order ---- */

static int run_trace(run *m, lt_cli *cli, lt_context *ctx, lt_scene *scene, lt_stats *stats) {
  lt_ray *rays = NULL;
  lt_hit *hits = NULL, *gathered = NULL, *ordered = NULL;
  lt_structure *structure = NULL;
  size_t count = 0, first = 0, total = 0;
  int rc = 1;

  /* Read this rank's share: only its range, or the whole file when interleaved. */
  if (!m->error[0]) {
    lt_status status;
    if (cli->interleaved) {
      status = lt_rays_read(cli->rays, &rays, &total);
      if (!status) {
        share s = share_of(m, cli, total);
        for (size_t j = 0; j < s.count; j++) rays[j] = rays[s.first + j * s.stride];
        count = s.count;
      }
    } else {
      status = lt_rays_read_part(cli->rays, (size_t)m->rank, (size_t)m->ranks, &rays, &count, &first, &total);
    }
    if (status) fail(m, "reading rays", status);
  }
  if (any_failed(m)) goto done;
  /* Every rank must have read the same batch (launched with different files, they may not). */
  unsigned long long n = total, first_rank = total;
  MPI_Bcast(&first_rank, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD);
  if (n != first_rank)
    snprintf(m->error, sizeof m->error, "reading rays: %s holds %llu rays, rank 0's ray file %llu", cli->rays, n,
             first_rank);
  if (any_failed(m)) goto done;

  /* Trace this rank's share on its own structure. */
  hits = malloc((count ? count : 1) * sizeof *hits);
  if (!hits) fail(m, "tracing", LT_ERROR_OUT_OF_MEMORY);
  lt_status status = m->error[0] ? LT_OK : lt_structure_create(ctx, scene, &cli->structure, stats, &structure);
  if (status) fail(m, "building the structure", status);
  if (!m->error[0]) {
    status = lt_structure_trace(structure, rays, count, cli->any ? LT_QUERY_ANY : LT_QUERY_CLOSEST, hits, stats);
    if (status) fail(m, "tracing", status);
  }
  lt_stats_set(stats, "rays", (double)count);
  if (m->rank == 0 && !(gathered = malloc((total ? total : 1) * sizeof *gathered)))
    fail(m, "gathering hits", LT_ERROR_OUT_OF_MEMORY);
  if (m->rank == 0 && cli->interleaved && !(ordered = malloc((total ? total : 1) * sizeof *ordered)))
    fail(m, "gathering hits", LT_ERROR_OUT_OF_MEMORY);
  if (any_failed(m)) goto done;

  /* Rank 0 gathers the hits in ray order and writes the one file. */
  gather(m, hits, count, sizeof *hits, gathered);
  if (m->rank == 0) {
    if (ordered) unshare(m, cli, (const char *)gathered, total, sizeof *gathered, (char *)ordered);
    status = lt_hits_write(cli->hits, ordered ? ordered : gathered, total);
    if (status) fail(m, "writing hits", status);
  }
  if (any_failed(m)) goto done;
  double *records;
  merge_stats(m, stats, &records);
  if (m->rank == 0) {
    lt_stats_set(stats, "rays", (double)total);
    say_totals(m, stats);
    fprintf(stderr, "lazytrace: hits in %s\n", cli->hits);
  }
  rc = write_stats(m, cli, stats, records);
  free(records);

done:
  free(rays), free(hits), free(gathered), free(ordered);
  lt_structure_destroy(structure);
  return rc;
}

/* ---- render --split queue: bands of rows handed out one at a time ---- */

/* The pixels every lt_render_part reports per effect; each call restarts them, so a rank that
 * renders many tiles sums them itself. */
static const char *const effect_names[] = {"primary", "shadows", "ao", "diffuse", "mirror", "collision"};
#define EFFECTS (sizeof effect_names / sizeof effect_names[0])

static void effect_stats(const lt_stats *stats, double rays_ms[2 * EFFECTS], int add) {
  for (size_t e = 0; e < EFFECTS; e++) {
    char key[64];
    snprintf(key, sizeof key, "rays_by_effect.%s", effect_names[e]);
    double rays = lt_stats_get(stats, key);
    snprintf(key, sizeof key, "ms_by_effect.%s", effect_names[e]);
    double ms = lt_stats_get(stats, key);
    if (add) rays_ms[2 * e] += rays > 0 ? rays : 0, rays_ms[2 * e + 1] += ms > 0 ? ms : 0;
  }
}

/* The queue's tiles, bands of full rows from the top, shrinking as they go (guided): each is
 * half the rows left over the ranks, and at least height / (16 ranks) rows (1 to 32). The large
 * first tiles keep each rank's rays coherent (a rank reaches little of the tree beyond its own
 * rows); the small last ones even out the ranks' finishing times. Returns the number of tiles;
 * tile number `tile`, if there is one, is rows [*row0, *row1). */
static size_t queue_tile(const run *m, int height, size_t tile, size_t *row0, size_t *row1) {
  size_t h = height > 0 ? (size_t)height : 0, least = h / (16 * (size_t)m->ranks), at = 0, t = 0;
  least = least < 1 ? 1 : least > 32 ? 32 : least;
  for (; at < h; t++) {
    size_t rows = (h - at + 2 * (size_t)m->ranks - 1) / (2 * (size_t)m->ranks);
    rows = rows < least ? least : rows;
    rows = rows < h - at ? rows : h - at;
    if (t == tile) *row0 = at, *row1 = at + rows;
    at += rows;
  }
  return t;
}

/* Renders the tiles this rank takes from the counter on rank 0 (one-sided atomics: the counter
 * lives in a window on rank 0 and each rank fetches and increments it with no help from rank 0),
 * through the one structure. *taken gets the tile indices in the order taken, their pixels are
 * in place in image. Collective (the window). */
static void render_queue(run *m, lt_structure *structure, const lt_scene *scene, const lt_render_config *config,
                         int width, int height, float *image, int **taken, size_t *count, lt_stats *stats) {
  size_t tiles = queue_tile(m, height, 0, &(size_t){0}, &(size_t){0});
  long *counter = NULL;
  MPI_Win win;
  MPI_Win_allocate(m->rank == 0 ? (MPI_Aint)sizeof(long) : 0, sizeof(long), MPI_INFO_NULL, MPI_COMM_WORLD, &counter,
                   &win);
  if (m->rank == 0) *counter = 0;
  MPI_Barrier(MPI_COMM_WORLD); /* the counter is zero before anyone takes a tile */
  *taken = malloc((tiles ? tiles : 1) * sizeof **taken), *count = 0;
  if (!*taken) fail(m, "rendering", LT_ERROR_OUT_OF_MEMORY);
  double sums[2 * EFFECTS] = {0};
  MPI_Win_lock_all(MPI_MODE_NOCHECK, win);
  for (;;) {
    long one = 1, tile = 0;
    MPI_Fetch_and_op(&one, &tile, MPI_LONG, 0, 0, MPI_SUM, win);
    MPI_Win_flush(0, win);
    /* A rank that failed keeps taking tiles without rendering them, so that none waits on it. */
    if (tile < 0 || (size_t)tile >= tiles) break;
    if (m->error[0]) continue;
    size_t row0 = 0, row1 = 0;
    queue_tile(m, height, (size_t)tile, &row0, &row1);
    lt_status status = lt_render_part(structure, scene, config, row0 * width, (row1 - row0) * width, 1, image, stats);
    if (status) fail(m, "rendering", status);
    effect_stats(stats, sums, 1);
    (*taken)[(*count)++] = (int)tile;
  }
  MPI_Win_unlock_all(win);
  MPI_Win_free(&win);
  for (size_t e = 0; e < EFFECTS; e++) {
    char key[64];
    snprintf(key, sizeof key, "rays_by_effect.%s", effect_names[e]);
    lt_stats_set(stats, key, sums[2 * e]);
    snprintf(key, sizeof key, "ms_by_effect.%s", effect_names[e]);
    lt_stats_set(stats, key, sums[2 * e + 1]);
  }
  m->tiles = (double)*count;
}

/* ---- render: pixels split between the ranks, the image gathered on rank 0 ---- */

static int run_render(run *m, lt_cli *cli, lt_context *ctx, lt_scene *scene, lt_stats *stats) {
  lt_structure *structure = NULL;
  float *image = NULL, *mine = NULL, *gathered = NULL;
  unsigned char *rgb = NULL;
  int *taken = NULL, *all_taken = NULL;
  size_t taken_count = 0;
  int rc = 1;
  lt_render_config config = {cli->size_given ? cli->width : 0, cli->size_given ? cli->height : 0, cli->spp, NULL,
                             cli->seed, 0, 0};
  int width = 0, height = 0, spp = 0;
  if (scene) lt_render_size(scene, &config, &width, &height, &spp);
  size_t pixels = (size_t)width * height;

  /* Contiguous shares are bands of rows: each rank's rays stay coherent and its tree small. */
  share s = {0, 0, 1};
  if (!m->error[0]) {
    if (cli->queue) {
      s.count = 0; /* known once the tiles are taken */
    } else if (cli->interleaved) {
      s = share_of(m, cli, pixels);
    } else {
      run rows = *m;
      s = share_of(&rows, cli, (size_t)height);
      s.first *= (size_t)width, s.count *= (size_t)width;
    }
    image = malloc(3 * (pixels ? pixels : 1) * sizeof *image);
    mine = malloc(3 * (cli->queue ? pixels : s.count ? s.count : 1) * sizeof *mine);
    if (!image || !mine) fail(m, "rendering", LT_ERROR_OUT_OF_MEMORY);
  }
  lt_status status = m->error[0] ? LT_OK : lt_structure_create(ctx, scene, &cli->structure, stats, &structure);
  if (status) fail(m, "building the structure", status);
  size_t tiles = queue_tile(m, height, 0, &(size_t){0}, &(size_t){0});
  if (cli->queue) {
    /* Every rank takes part (the window is collective), a failed one without rendering. */
    render_queue(m, structure, scene, &config, width, height, image, &taken, &taken_count, stats);
    if (m->rank == 0 && !m->error[0] && !(all_taken = malloc((tiles ? tiles : 1) * sizeof *all_taken)))
      fail(m, "gathering the image", LT_ERROR_OUT_OF_MEMORY);
  } else if (!m->error[0]) {
    status = lt_render_part(structure, scene, &config, s.first, s.count, s.stride, image, stats);
    if (status) fail(m, "rendering", status);
  }
  if (m->rank == 0 && !m->error[0]) {
    gathered = malloc(3 * (pixels ? pixels : 1) * sizeof *gathered);
    rgb = malloc(3 * (pixels ? pixels : 1));
    if (!gathered || !rgb) fail(m, "gathering the image", LT_ERROR_OUT_OF_MEMORY);
  }
  if (any_failed(m)) goto done;

  /* Rank 0 gathers every rank's pixels, puts them in place and writes the PNG. With the queue
   * each rank sends the tiles it took, in the order taken, then their pixels in the same order. */
  if (cli->queue) {
    for (size_t t = 0; t < taken_count; t++) {
      size_t row0 = 0, row1 = 0;
      queue_tile(m, height, (size_t)taken[t], &row0, &row1);
      size_t first = row0 * width, end = row1 * width;
      memcpy(mine + 3 * s.count, image + 3 * first, 3 * (end - first) * sizeof *mine);
      s.count += end - first;
    }
    gather(m, taken, taken_count, sizeof *taken, all_taken);
  } else {
    for (size_t j = 0; j < s.count; j++) memcpy(mine + 3 * j, image + 3 * (s.first + j * s.stride), 3 * sizeof *mine);
  }
  gather(m, mine, s.count, 3 * sizeof *mine, gathered);
  if (m->rank == 0) {
    if (cli->interleaved) {
      unshare(m, cli, (const char *)gathered, pixels, 3 * sizeof *image, (char *)image);
    } else if (cli->queue) {
      for (size_t t = 0, at = 0; t < tiles; t++) {
        size_t row0 = 0, row1 = 0;
        queue_tile(m, height, (size_t)all_taken[t], &row0, &row1);
        size_t first = row0 * width, end = row1 * width;
        memcpy(image + 3 * first, gathered + 3 * at, 3 * (end - first) * sizeof *image);
        at += end - first;
      }
    } else {
      memcpy(image, gathered, 3 * pixels * sizeof *image);
    }
    lt_image_to_srgb8(image, pixels, rgb);
    const char *output = cli->output ? cli->output : "render.png";
    if (lt_write_png(output, width, height, rgb) != 0)
      snprintf(m->error, sizeof m->error, "writing %s: could not write the PNG", output);
  }
  if (any_failed(m)) goto done;
  double *records;
  merge_stats(m, stats, &records);
  if (m->rank == 0) {
    say_totals(m, stats);
    fprintf(stderr, "lazytrace: wrote %s (%dx%d, %d sample%s per pixel)\n", cli->output ? cli->output : "render.png",
            width, height, spp, spp == 1 ? "" : "s");
  }
  rc = write_stats(m, cli, stats, records);
  free(records);

done:
  free(image), free(mine), free(gathered), free(rgb), free(taken), free(all_taken);
  lt_structure_destroy(structure);
  return rc;
}

/* ---- collide: agents split between the ranks; every frame each rank rebuilds, on demand,
 * only what its own agents' rays reach ---- */

static int run_collide(run *m, lt_cli *cli, lt_context *ctx, lt_scene *scene, lt_stats *stats) {
  size_t per_frame = (size_t)cli->agents * cli->rays_per_agent, frames = (size_t)cli->frames;
  share s = share_of(m, cli, (size_t)cli->agents);
  size_t count = s.count * cli->rays_per_agent;
  float *paths = malloc(6 * sizeof(float) * cli->agents);
  lt_ray *all_rays = malloc(per_frame * sizeof *all_rays), *rays = malloc((count ? count : 1) * sizeof *rays);
  lt_hit *hits = malloc((count * frames > 0 ? count * frames : 1) * sizeof *hits), *gathered = NULL, *ordered = NULL;
  double *per = calloc(3 * frames, sizeof *per), *worst = calloc(3 * frames, sizeof *worst);
  lt_stats *frame_stats = NULL;
  int rc = 1;
  if (!paths || !all_rays || !rays || !hits || !per || !worst || lt_stats_create(&frame_stats))
    fail(m, "collide", LT_ERROR_OUT_OF_MEMORY);
  if (m->rank == 0 && cli->hits && !m->error[0]) {
    gathered = malloc((per_frame * frames > 0 ? per_frame * frames : 1) * sizeof *gathered);
    ordered = malloc((per_frame * frames > 0 ? per_frame * frames : 1) * sizeof *ordered);
    if (!gathered || !ordered) fail(m, "gathering hits", LT_ERROR_OUT_OF_MEMORY);
  }
  if (!m->error[0]) lt_collision_paths(scene, cli->agents, cli->seed, paths);

  /* Every frame: all agents' rays (cheap, and the same on every rank), this rank's agents' share
   * of them, a structure from scratch, the trace. */
  double build_sum = 0, trace_sum = 0;
  for (size_t f = 0; f < frames && !m->error[0]; f++) {
    lt_collision_rays(paths, cli->agents, cli->rays_per_agent, (int)f, cli->frames, cli->seed + 1, all_rays);
    for (size_t j = 0; j < s.count; j++)
      memcpy(rays + j * cli->rays_per_agent, all_rays + (s.first + j * s.stride) * cli->rays_per_agent,
             cli->rays_per_agent * sizeof *rays);
    if (count == 0) continue;
    lt_structure *structure = NULL;
    lt_stats_reset(frame_stats);
    lt_scene_set_time(scene, lt_frame_time((int)f, cli->frames)); /* an animated scene moves, as in collide */
    lt_status status = lt_structure_create(ctx, scene, &cli->structure, frame_stats, &structure);
    if (!status) status = lt_structure_trace(structure, rays, count, LT_QUERY_CLOSEST, hits + f * count, frame_stats);
    lt_structure_destroy(structure);
    if (status) {
      fail(m, "collision frame", status);
      break;
    }
    double b = lt_stats_get(frame_stats, "build_ms"), t = lt_stats_get(frame_stats, "trace_ms");
    per[3 * f] = b, per[3 * f + 1] = t;
    for (size_t i = 0; i < count; i++) per[3 * f + 2] += hits[f * count + i].prim >= 0;
    build_sum += b, trace_sum += t;
  }
  if (any_failed(m)) goto done;

  /* Per frame: the slowest rank's build and trace, the hits of all. */
  double *sum_hits = worst + 2 * frames;
  for (size_t f = 0; f < frames; f++) {
    MPI_Reduce(per + 3 * f, worst + 2 * f, 2, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);
    MPI_Reduce(per + 3 * f + 2, sum_hits + f, 1, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
  }
  if (m->rank == 0) {
    double hits_all = 0;
    fprintf(stderr, "frame  build_ms  trace_ms  total_ms  hits   (the slowest rank's times)\n");
    for (size_t f = 0; f < frames; f++) {
      fprintf(stderr, "%5zu  %8.2f  %8.2f  %8.2f  %.0f\n", f, worst[2 * f], worst[2 * f + 1],
              worst[2 * f] + worst[2 * f + 1], sum_hits[f]);
      hits_all += sum_hits[f];
    }
    fprintf(stderr, "lazytrace: %d frames of %zu rays: %.0f hits\n", cli->frames, per_frame, hits_all);
  }

  /* With --hits, rank 0 gathers them: per rank frame after frame, put back in frame, agent
   * and ray order. */
  if (cli->hits) {
    gather(m, hits, count * frames, sizeof *hits, gathered);
    if (m->rank == 0) {
      size_t at = 0;
      for (int r = 0; r < m->ranks; r++) {
        run other = *m;
        other.rank = r;
        share o = share_of(&other, cli, (size_t)cli->agents);
        for (size_t f = 0; f < frames; f++)
          for (size_t j = 0; j < o.count; j++, at += cli->rays_per_agent)
            memcpy(ordered + f * per_frame + (o.first + j * o.stride) * cli->rays_per_agent, gathered + at,
                   cli->rays_per_agent * sizeof *ordered);
      }
      lt_status status = lt_hits_write(cli->hits, ordered, per_frame * frames);
      if (status) fail(m, "writing hits", status);
    }
    if (any_failed(m)) goto done;
  }

  /* As the one-process tool: totals over frames, names and node figures of the last frame. */
  lt_cli_collide_totals(stats, frame_stats, build_sum, trace_sum, (double)count * frames);
  double *records;
  merge_stats(m, stats, &records);
  say_totals(m, stats);
  rc = write_stats(m, cli, stats, records);
  free(records);

done:
  free(paths), free(all_rays), free(rays), free(hits), free(gathered), free(ordered), free(per), free(worst);
  lt_stats_destroy(frame_stats);
  return rc;
}

int lt_mpi_run(lt_cli *cli) {
  int provided;
  if (MPI_Init_thread(NULL, NULL, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
    return fprintf(stderr, "lazytrace: MPI could not start\n"), 1;
  run m = {0};
  m.tiles = -1;
  m.start_ms = lt_now_ms();
  MPI_Comm_rank(MPI_COMM_WORLD, &m.rank);
  MPI_Comm_size(MPI_COMM_WORLD, &m.ranks);
  MPI_Comm local;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, m.rank, MPI_INFO_NULL, &local);
  MPI_Comm_size(local, &m.local_ranks);
  MPI_Comm_free(&local);

  /* What the one-process tool checks before opening anything. */
  if (!cli->scene)
    snprintf(m.error, sizeof m.error, "no SCENE given (run 'lazytrace help %s')", cli->command);
  else if (strcmp(cli->command, "trace") == 0 && (!cli->rays || !cli->hits))
    snprintf(m.error, sizeof m.error, "--rays RAYS and --hits HITS are required (run 'lazytrace help trace')");

  lt_stats *stats = NULL;
  lt_context *ctx = NULL;
  lt_scene *scene = NULL;
  if (lt_stats_create(&stats)) fail(&m, "statistics", LT_ERROR_OUT_OF_MEMORY);
  if (!m.error[0]) open_rank(&m, cli, &ctx, &scene, stats);
  int rc = 1;
  if (!any_failed(&m)) {
    if (strcmp(cli->command, "trace") == 0) rc = run_trace(&m, cli, ctx, scene, stats);
    else if (strcmp(cli->command, "render") == 0) rc = run_render(&m, cli, ctx, scene, stats);
    else rc = run_collide(&m, cli, ctx, scene, stats);
  }
  lt_scene_destroy(scene);
  lt_context_destroy(ctx);
  lt_stats_destroy(stats);

  /* One exit status for all: a rank that failed late (writing statistics) fails the run. */
  int worst = 0;
  MPI_Allreduce(&rc, &worst, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  MPI_Finalize();
  return worst;
}
