#!/usr/bin/env bash
# The task pool on its own workload (issue 3): a full lazy sort through the persistent kernel
# against one launch per tree level, and requested mode, on both backends; medians written to
# docs/results/pool_scheduler.md.
#   benchmarks/pool.sh [--keys N] [--runs R]
set -euo pipefail
cd "$(dirname "$0")/.."
. benchmarks/common.sh
lt_bench_prepare
out=$R/pool_scheduler.md
table=$(build/benchmarks/bench_pool "$@")
{
  echo "# The task pool measured on its own workload (lazy sort)"
  echo
  lt_results_header "benchmarks/pool.sh $*"
  echo
  echo "$table"
} >"$out"
cat "$out"
