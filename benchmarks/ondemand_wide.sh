#!/usr/bin/env bash
# On-demand traversal on the wide layout against binary on-demand traversal (issue 16, point 2),
# Embree 3 beside them, on Table 1's workloads; writes docs/results/ondemand_wide.md.
#   benchmarks/ondemand_wide.sh [--runs R] [--size N] [SCENE...]
#   (defaults: 3 runs, 1024x1024, house-grid:3x3 house-row:8 hairball:10000)
set -euo pipefail
cd "$(dirname "$0")/.."
. benchmarks/common.sh
args=() scenes=()
while [ $# -gt 0 ]; do
  case "$1" in --runs | --size | --ao) args+=("$1" "$2"); shift 2 ;; *) scenes+=("$1"); shift ;; esac
done
[ ${#scenes[@]} -gt 0 ] || scenes=(house-grid:3x3 house-row:8 hairball:10000)
lt_bench_prepare
{
  echo "# On-demand BVH: wide (8-wide AVX2) against binary on-demand traversal, native backend"
  echo
  lt_results_header "benchmarks/ondemand_wide.sh ${args[*]:-} ${scenes[*]}"
  echo "- Embree $(dpkg-query -W -f='${Version}' libembree-dev 2>/dev/null || echo 'not installed') (robust flag), as many threads as work-groups ($(nproc))"
  echo "- times are milliseconds to image (build plus trace over the batches, the collapses included),"
  echo "  medians of the runs, methods interleaved run by run; the machine was shared with other work"
  echo
  build/benchmarks/bench_ondemand_wide "${args[@]}" "${scenes[@]}"
} >$R/ondemand_wide.md
