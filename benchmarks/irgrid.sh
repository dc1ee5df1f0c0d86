#!/usr/bin/env bash
# The irregular grid paper's experiments in shape (Perard-Gayot et al. 2017), lazytrace's
# --structure irgrid beside the full SAH BVH and Embree 3, written to docs/results/:
#   irgrid_table1.md     Table 1: two-level grid, + merge, + merge + expansion, merge within top
#                        cells only, SAH BVH, Embree: steps and tests per ray, build, trace, memory
#   irgrid_table2.md     Table 2: lambda1 x lambda2 in {0.012, 0.04, 0.12} x {0.24, 0.8, 2.4}, the
#                        irregular and the two-level grid, and the ranges over the nine pairs
#   irgrid_table5.md     Table 5: merge and expansion on uniform grids (lambda1 0.12 and 1)
#   irgrid_trace_target.md  Table 1's full grid and SAH BVH (and Embree) alone, 5 runs: issue 15's
#                        trace target (grid within 1.2x of the BVH) measured with more runs
#   irgrid_ondemand.md   the full irregular grid against top cells built on request and
#                        speculatively, then house-row:1..16 (also irgrid_sweep.csv)
#   benchmarks/irgrid.sh [--runs R] [--size N]      (defaults: 3 runs, 512x512 primary rays)
# TABLES="1 trace 2 5 ondemand" (the default) picks which of them to measure again.
# Takes about 25 minutes on 2 cores; most of it is hairball:3000's irregular grid builds in
# Table 1 (each several tens of seconds).
set -euo pipefail
cd "$(dirname "$0")/.."
. benchmarks/common.sh
lt_bench_prepare
B=build/benchmarks/bench_irgrid
header() {
  echo "- command: \`benchmarks/irgrid.sh $*\` (native backend, $(nproc) work-groups; Embree with as many threads)"
  echo "- commit: $(lt_commit)"
  echo "- machine: $(lt_machine)"
  echo "- Embree $(dpkg-query -W -f='${Version}' libembree-dev 2>/dev/null || echo 'not installed') (robust flag); date $(date -u +%Y-%m-%d)"
  echo "- rays: primary rays from each scene's outer camera (512x512 unless --size says otherwise);"
  echo "  times are milliseconds without scene loading and kernel compilation, medians of the runs,"
  echo "  a finished structure's trace time the median of 3 traces after the first (Embree's too),"
  echo "  the variants interleaved run by run; every lazytrace variant's closest hits equal the full"
  echo "  SAH BVH's bit for bit (the benchmark stops otherwise)"
  echo "- irregular grid defaults: lambda1 (top cells per triangle) 0.12, lambda2 (sub-voxels per"
  echo "  reference of a top cell) 2.4, merge on (across the whole grid in a full build), alpha 0.995,"
  echo "  3 expansion passes; the two-level grid is the same build with merge off and no expansion"
}
tables=" ${TABLES:-1 trace 2 5 ondemand} "
want() { [[ $tables == *" $1 "* ]]; }
# What the columns shared by several tables mean.
columns() {
  echo "- steps/ray: cells whose triangles a ray tested (irregular grid; the walk's voxel lookups between"
  echo "  them are not counted) or nodes visited (BVH); tests/ray: ray-triangle tests"
  echo "- memory MB: the structure's device memory as lazytrace counts it after the build (memory_bytes:"
  echo "  cells or nodes, references, voxel map, task pool, and what the build left allocated: the BVH keeps"
  echo "  its triangle boxes and build scratch; a full irregular grid is compacted, its top lists, boxes and scratch given back);"
  echo "  structure MB: cells (nodes), references and voxel map alone; memory / BVH and structure / BVH:"
  echo "  relative to the full SAH BVH of the same run"
}

want 1 && {
  echo "# Irregular grid after each construction phase, against the SAH BVH and Embree (the paper's Table 1)"
  echo
  header "$@"
  columns
  echo "- every structure built in full; build ms: the build alone, first trace ms: the primary rays"
  echo "  traced right after the build, trace ms: traced again (the median of 3), Mrays/s: of that"
  echo "  trace; trace / BVH and memory / BVH: relative to the"
  echo "  full SAH BVH of the same run (x); Embree has no step or test counts and no memory figure"
  echo "- merge within top cells: LT_IRGRID_MERGE_TOP (cells never merge across top cells), 3 expansion passes"
  echo
  $B table1 "$@" house-grid:3x3 house-row:8 hairball:3000 teapot-stadium sphere:6 cornell
} >"$R"/irgrid_table1.md

want trace && {
  echo "# The full irregular grid's primary-ray trace against the SAH BVH (issue 15's trace target)"
  echo
  header "$@"
  echo "- the \"+ merge + expansion\" and \"SAH BVH (full)\" rows of irgrid_table1.md (and Embree) alone,"
  echo "  5 runs (interleaved run by run), so that the ratio is measured more often than Table 1's slow"
  echo "  builds allow; grid / BVH: each run's grid trace time over its BVH trace time, and the median of"
  echo "  those; grid memory / BVH: memory_bytes"
  echo
  $B trace --runs 5 "$@" house-grid:3x3 house-row:8 hairball:3000 teapot-stadium sphere:6 cornell
} >"$R"/irgrid_trace_target.md

want 2 && {
  echo "# Irregular and two-level grid over their densities (the paper's Table 2)"
  echo
  header "$@"
  columns
  echo "- first table: per (lambda1, lambda2) pair, the irregular grid (defaults otherwise) and the two-level"
  echo "  grid, both built in full; cells: cells of the finished grid (cells.final)"
  echo "- second table, as the paper's: the irregular grid's [min, max] over the nine pairs, the two-level"
  echo "  grid at the pair of its fastest trace (named in the last column), the full SAH BVH"
  echo
  $B densities "$@" house-grid:3x3 teapot-stadium
} >"$R"/irgrid_table2.md

want 5 && {
  echo "# Merge and expansion on uniform grids (the paper's Table 5)"
  echo
  header "$@"
  columns
  echo "- uniform grid: the irregular grid with a cell density (lambda2) of 1e-6, so that no top cell is"
  echo "  cut (cells = top cells), at top density lambda1 = 0.12 (the irregular grid's default) and 1;"
  echo "  the top grid's resolution in brackets; + expansion: 3 passes; + merge: across the whole grid"
  echo "- trace / uniform: trace time relative to the plain uniform grid at the same lambda1; cells:"
  echo "  cells of the finished grid. Built in full; the paper's macro regions are not implemented"
  echo
  $B uniform "$@" house-grid:3x3 hairball:3000 teapot-stadium
} >"$R"/irgrid_table5.md

want ondemand && {
  echo "# Irregular grid with top cells built on demand"
  echo
  header "$@"
  echo "- full: built in full (merging across top cells), then traced; requested and speculative: top"
  echo "  cells materialised while the primary rays are traced, in one launch (merging within top cells"
  echo "  only, so the cells differ from the full build's)"
  echo "- time to image: build plus trace (on demand, the launch that builds and traces); trace ms: the"
  echo "  same rays traced again on the grid as built; build ms: time to image less that trace"
  echo "- top cells built: of the top grid's cells; cells: cells of the grid as built (nodes_built);"
  echo "  image / full: time to image relative to the full build's"
  echo
  $B ondemand "$@" house-grid:6x5 house-grid:3x3 house-row:8
  echo
  echo "## Hidden geometry: house-row:1 to house-row:16 from the outer camera"
  echo
  echo "Time to image (image ms) and cells built (also in irgrid_sweep.csv); requested / full and"
  echo "speculative / full: time to image relative to the full build's."
  echo
  $B sweep "$@" --csv "$R"/irgrid_sweep.csv
} >"$R"/irgrid_ondemand.md

for t in table1 table2 table5 ondemand; do want "${t#table}" && cat "$R/irgrid_$t.md"; done; true
