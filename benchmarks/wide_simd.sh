#!/usr/bin/env bash
# The QBVH's native 8-wide AVX2 path against the 4-wide QBVH, the binary SAH BVH and Embree 3
# (issue 16, "0.8x Embree"): trace throughput for primary and AO rays on the native backend,
# medians of interleaved runs, written to docs/results/wide_simd.md.
#   benchmarks/wide_simd.sh [--size N] [--runs R] [--ao S]      (defaults 1024, 5, 2)
# SCENES (space-separated) overrides the scenes.
set -euo pipefail
cd "$(dirname "$0")/.."
. benchmarks/common.sh
lt_bench_prepare
out=$R/wide_simd.md
scenes=${SCENES:-"house-grid:3x3 teapot-stadium hairball:3000 sphere:6"}
tables=""
for scene in $scenes; do
  tables+=$(build/benchmarks/bench_wide_simd "$scene" "$@")$'\n\n'
done
{
  echo "# The QBVH's native 8-wide path against the 4-wide QBVH, the binary BVH and Embree 3"
  echo
  lt_results_header "SCENES=\"$scenes\" benchmarks/wide_simd.sh $*"
  echo "- Embree $(dpkg-query -W -f='${Version}' libembree-dev 2>/dev/null || echo 'not installed'), robust flag, default (medium) build, as many threads as the native backend"
  echo "- trace_ms of the statistics (build excluded) and Embree's trace time, medians over the runs; in each run every"
  echo "  method, Embree included, traces each ray set once, one after the other; one warm-up run first, not counted"
  echo
  echo "$tables"
} >"$out"
cat "$out"
