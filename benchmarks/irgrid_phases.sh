#!/usr/bin/env bash
# Full-build time of the irregular grid, two builds of lazytrace side by side (A B A B ...), for
# changes to how its build is cut into pool tasks: the statistics of the grid (cells, merges,
# expansions, references, memory) must come out the same, and the table says whether they do.
# Native backend, the grid's defaults (--merge on: merge passes across the grid) and --merge top
# (merges within top cells, the build that on-demand cells match), 64x64 primary rays (only to
# finish the run); build ms is the median of RUNS runs of each side, alternated run by run.
#   benchmarks/irgrid_phases.sh OLD_LAZYTRACE NEW_LAZYTRACE [RUNS] > docs/results/NAME.md
# SCENES (space-separated) overrides the scenes; OLD_COMMIT and NEW_COMMIT name the commits the
# two builds come from, for the record.
set -euo pipefail
old=$1 new=$2 runs=${3:-3}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
. "$(dirname "$0")/common.sh"
scenes=${SCENES:-"house-grid:3x3 hairball:3000"}
echo "- command: \`SCENES=\"$scenes\" benchmarks/irgrid_phases.sh OLD NEW $runs\` (native backend, $(nproc) work-groups, --structure irgrid --build full)"
echo "- old: ${OLD_COMMIT:-OLD}, new: ${NEW_COMMIT:-NEW}; machine: $(lt_machine); date $(date -u +%Y-%m-%d)"
echo "- build ms: median of $runs runs, old and new alternated run by run (min - max in brackets);"
echo "  same statistics: cells (top, built, initial, final, merges, expansions), references, memory_bytes equal"
echo
echo "| scene | --merge | old build ms | new build ms | new / old | same statistics | final cells | merges | expansions |"
echo "|---|---|---:|---:|---:|---|---:|---:|---:|"
for scene in $scenes; do
  for merge in on top; do
    : >"$tmp/old.ms" ; : >"$tmp/new.ms"
    for r in $(seq "$runs"); do
      for side in old new; do
        "${!side}" render "$scene" --structure irgrid --build full --merge $merge --device native --size 64x64 \
          -o "$tmp/x.png" --stats "$tmp/$side.json" >/dev/null 2>&1
        python3 -c "import json; print(json.load(open('$tmp/$side.json'))['build_ms'])" >>"$tmp/$side.ms"
      done
    done
    python3 - "$scene" "$merge" "$tmp" <<'PY'
import json, statistics as st, sys
scene, merge, tmp = sys.argv[1:]
ms = {k: [float(x) for x in open(f"{tmp}/{k}.ms")] for k in ("old", "new")}
o, n = (json.load(open(f"{tmp}/{k}.json")) for k in ("old", "new"))
same = o["cells"] == n["cells"] and all(o[k] == n[k] for k in ("reference_bytes", "node_bytes", "map_bytes", "memory_bytes"))
cell = lambda k: f"{ms[k] and st.median(ms[k]):.0f} ({min(ms[k]):.0f} - {max(ms[k]):.0f})"
c = n["cells"]
print(f"| {scene} | {merge} | {cell('old')} | {cell('new')} | {st.median(ms['new']) / st.median(ms['old']):.2f} | "
      f"{'yes' if same else 'NO'} | {c['final']} | {c['merges']} | {c['expansions']} |")
PY
  done
done
