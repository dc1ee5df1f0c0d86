#!/usr/bin/env bash
# The persistent kernel's tax on a finished tree (issue 16): a tree built in full through the
# pool, its rays traced once through the persistent (on-demand) kernel and once through the
# plain trace kernel, alternated run by run (bench_ondemand_tax), for the BVH and the kd-tree,
# native and OpenCL, on primary and AO rays. With OLD_BENCH, that build's bench_ondemand_tax
# runs before the current one on every scene and structure (before and after, side by side).
#   benchmarks/ondemand_tax.sh [--runs R] [--size N] [--device native|opencl|both] > docs/results/NAME.md
# SCENES and STRUCTURES (space-separated) override the scenes and structures; OLD_BENCH names
# another build's bench_ondemand_tax to compare with.
set -euo pipefail
cd "$(dirname "$0")/.."
. benchmarks/common.sh
scenes=${SCENES:-"house-grid:3x3 sphere:6"}
structures=${STRUCTURES:-"bvh kdtree"}
echo "# The persistent kernel's tax on finished trees"
echo
lt_results_header "SCENES=\"$scenes\" STRUCTURES=\"$structures\"${OLD_BENCH:+ OLD_BENCH=OLD} benchmarks/ondemand_tax.sh $*"
echo "- look at the ratios, measured side by side in one process, more than at the absolute times (the machine's"
echo "  load moves those)"
echo
for scene in $scenes; do
  for structure in $structures; do
    for bench in ${OLD_BENCH:-} build/benchmarks/bench_ondemand_tax; do
      [ "$bench" = build/benchmarks/bench_ondemand_tax ] && which=current || which=old
      echo "### $scene, $structure ($which build)"
      echo
      "$bench" "$scene" --structure "$structure" "$@"
      echo
    done
  done
done
