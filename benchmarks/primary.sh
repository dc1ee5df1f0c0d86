#!/usr/bin/env bash
# Full-BVH primary-ray benchmark (issue 2): house-grid:3x3, 1024x1024 rays, lazytrace on both
# backends and Embree 3, medians of 5 runs, written to docs/results/primary_full_bvh.md.
#   benchmarks/primary.sh [SCENE] [--size N] [--runs R]
set -euo pipefail
cd "$(dirname "$0")/.."
. benchmarks/common.sh
lt_bench_prepare
out=$R/primary_full_bvh.md
table=$(build/benchmarks/bench_primary "$@")
{
  echo "# Primary rays, full SAH BVH: lazytrace (OpenCL and native) against Embree 3"
  echo
  echo "- command: \`benchmarks/primary.sh $*\`"
  echo "- commit: $(lt_commit)"
  echo "- machine: $(lt_machine)"
  echo "- OpenCL: $(lt_opencl_device); Embree $(dpkg-query -W -f='${Version}' libembree-dev 2>/dev/null || echo 'not installed')"
  echo "- date: $(date -u +%Y-%m-%d)"
  echo
  echo "$table"
} >"$out"
cat "$out"
