#!/usr/bin/env bash
# Trace time of full builds, two builds side by side (A B A B ...): the full SAH BVH and the
# full kd-tree on 1024x1024 primary rays, native backend, medians of the runs and the median of
# the paired ratios new/old. For changes to how finished trees are traced.
#   benchmarks/full_trace.sh OLD_LAZYTRACE NEW_LAZYTRACE [RUNS] > docs/results/NAME.md
# STRUCTURES and SCENES (space-separated) override the structures and scene@camera pairs.
set -euo pipefail
old=$1 new=$2 runs=${3:-3}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
. "$(dirname "$0")/common.sh"
scenes=${SCENES:-"house-grid:3x3@outer house-grid:3x3@close house-grid:6x5@close hairball:10000@outer teapot-stadium@close"}
structures=${STRUCTURES:-"bvh kdtree"}
echo "- command: \`STRUCTURES=\"$structures\" SCENES=\"$scenes\" benchmarks/full_trace.sh OLD NEW $runs\` (native backend, $(nproc) work-groups, 1024x1024 primary rays)"
echo "- machine: $(lt_machine); date $(date -u +%Y-%m-%d)"
echo "- trace_ms of each build's statistics; medians of $runs runs, old and new alternated run by run"
echo
echo "| scene@camera | structure | old trace ms | new trace ms | new / old (median of paired ratios) |"
echo "|---|---|---:|---:|---:|"
median() { sort -n | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2}'; }
for scene in $scenes; do
  for structure in $structures; do
    : >"$tmp/old" ; : >"$tmp/new" ; : >"$tmp/ratio"
    for r in $(seq "$runs"); do
      for side in old new; do
        "${!side}" render "$scene" --structure $structure --build full --device native --size 1024x1024 \
          -o "$tmp/x.png" --stats "$tmp/s.json" >/dev/null 2>&1
        python3 -c "import json; print(json.load(open('$tmp/s.json'))['trace_ms'])" >>"$tmp/$side"
      done
      paste "$tmp/old" "$tmp/new" | tail -1 | awk '{print $2 / $1}' >>"$tmp/ratio"
    done
    printf "| %s | %s | %.0f | %.0f | %.2f |\n" "$scene" "$structure" "$(median <"$tmp/old")" "$(median <"$tmp/new")" \
      "$(median <"$tmp/ratio")"
  done
done
