/* What a compacted irregular grid's cells and reference lists look like, and what smaller
 * layouts of them would take (issue 15: the grid's memory on long thin geometry):
 *
 *   bench_irgrid_lists SCENE...
 *
 * Builds each scene's full irregular grid (the defaults, native backend), reads its arrays back
 * and prints, per scene, one markdown row of the cells (how many, the fine grid's largest side,
 * whether 16-bit coordinates hold it, lists not laid end to end because they share an earlier
 * cell's) and one of the references (stored, consecutive pairs, runs, the deltas' sizes), then
 * the bytes each candidate layout would take. Nothing is timed: the counts are deterministic. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "benchmarks/methods.h"
#include "lazytrace.h"
#include "runtime/irgrid_host.h"

static void die(const char *what) {
  fprintf(stderr, "bench_irgrid_lists: %s: %s\n", what, lt_last_error());
  exit(1);
}

#define MB(x) ((double)(x) / 1048576.0)

int main(int argc, char **argv) {
  if (argc < 2) return fprintf(stderr, "usage: bench_irgrid_lists SCENE...\n"), 2;
  lt_context *ctx = lt_bench_native_context();
  if (!ctx) die("native context");
  printf("| scene | triangles | cells | fine grid | fits 16 bits | shared lists (cells) | refs in shared lists |"
         " refs stored | per triangle | consecutive pairs | runs | runs of 1 | deltas < 128 | < 32768 | larger |\n");
  printf("|---|---:|---:|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  char (*estimates)[512] = calloc((size_t)argc, sizeof *estimates);
  for (int s = 1; s < argc; s++) {
    lt_scene *scene;
    if (lt_scene_load(argv[s], &scene) != LT_OK) die(argv[s]);
    lt_structure_config config = lt_structure_config_default(LT_STRUCTURE_IRGRID);
    config.build = LT_BUILD_FULL;
    lt_structure *st;
    if (lt_structure_create(ctx, scene, &config, NULL, &st) != LT_OK) die("build");
    lt__irgrid *g = lt__irgrid_of(st);
    lt__irgrid_arrays a;
    if (!g || lt__irgrid_read(g, &a) != LT_OK) die("read");
    int dims[3] = {g->fine.dims.x, g->fine.dims.y, g->fine.dims.z};
    int largest = dims[0] > dims[1] ? dims[0] : dims[1];
    largest = largest > dims[2] ? largest : dims[2];
    /* Lists in cell order: one laid after the previous ends where the next begins; one that
     * begins before the farthest end so far shares (part of) an earlier cell's. */
    long shared = 0, shared_refs = 0, consecutive = 0, runs = 0, singles = 0, small = 0, medium = 0, large = 0;
    long laid = 0;
    for (int c = 0; c < a.cell_count; c++) {
      const lt_irg_cell *cell = &a.cells[c];
      int length = cell->end - cell->begin;
      if (cell->begin < laid && length > 0)
        shared++, shared_refs += length;
      else if (cell->end > laid)
        laid = cell->end;
      /* Runs of consecutive triangle numbers, and the steps from one reference to the next
       * (the first from 0: a list written as deltas starts there). */
      int run = 0; /* the length of the run being read */
      for (int i = cell->begin; i < cell->end; i++) {
        lt_i32 delta = a.refs[i] - (i > cell->begin ? a.refs[i - 1] : -1);
        if (i > cell->begin && delta == 1)
          consecutive++, run++;
        else {
          if (run == 1) singles++;
          runs++, run = 1;
        }
        if (delta < 128)
          small++;
        else if (delta < 32768)
          medium++;
        else
          large++;
      }
      if (run == 1) singles++;
    }
    double tris = (double)lt_scene_triangle_count(scene);
    printf("| %s | %.0f | %d | %dx%dx%d | %s | %ld | %ld | %d | %.1f | %ld | %ld | %ld | %ld | %ld | %ld |\n", argv[s],
           tris, a.cell_count, dims[0], dims[1], dims[2], largest < 65536 ? "yes" : "NO", shared, shared_refs,
           a.ref_count, a.ref_count / tris, consecutive, runs, singles, small, medium, large);
    /* Candidate layouts, in MB:
     *  - cells of 16 bytes (six u16 coordinates, begin; end the next cell's begin), shared
     *    lists copied out again so that every list lies end to end;
     *  - runs: a run of one as one i32, a longer run as two (first, count);
     *  - 16-bit deltas: a list's first triangle in two u16, each next one's delta in one u16
     *    (three where it does not fit);
     *  - byte deltas (varint: 7 bits a byte). */
    long long unshared_refs = a.ref_count + shared_refs;
    long long run_words = runs + (runs - singles);
    long long delta16 = 0, varint = 0;
    for (int c = 0; c < a.cell_count; c++) {
      const lt_irg_cell *cell = &a.cells[c];
      for (int i = cell->begin; i < cell->end; i++) {
        lt_u32 delta = (lt_u32)(a.refs[i] - (i > cell->begin ? a.refs[i - 1] : 0));
        delta16 += i == cell->begin ? 4 : delta < 32768 ? 2 : 6;
        varint += delta < 128 ? 1 : delta < 16384 ? 2 : delta < 2097152 ? 3 : 4;
      }
    }
    snprintf(estimates[s], sizeof estimates[s],
             "| %s | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f |\n", argv[s], MB(a.cell_count * 32.0),
             MB(a.cell_count * 16.0), MB(a.ref_count * 4.0), MB(unshared_refs * 4.0), MB(run_words * 4.0),
             MB((double)delta16), MB((double)varint));
    lt__irgrid_arrays_free(&a);
    lt_structure_destroy(st);
    lt_scene_destroy(scene);
  }
  printf("\nThe reference columns above count every cell's list (a shared list once per cell that reads it).\n"
         "Candidate layouts (MB, 2^20 bytes): 'refs i32' as stored now (shared lists once); the others with every\n"
         "list laid end to end (a shared list copied per cell), as cells without an end of their own need:\n\n");
  printf("| scene | cells 32 B | cells 16 B | refs i32 | refs i32 unshared | runs | 16-bit deltas | byte deltas |\n");
  printf("|---|---:|---:|---:|---:|---:|---:|---:|\n");
  for (int s = 1; s < argc; s++) fputs(estimates[s], stdout);
  free(estimates);
  return 0;
}
