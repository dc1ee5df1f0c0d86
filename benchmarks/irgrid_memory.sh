#!/usr/bin/env bash
# Memory and build time of the full irregular grid, two builds of lazytrace side by side (A B A B
# ...): for changes to what a finished grid holds. Byte counts are the statistics of the build
# (deterministic); build ms is the median of the runs. Native backend, the irregular grid's
# defaults, 64x64 primary rays (only to finish the run).
#   benchmarks/irgrid_memory.sh OLD_LAZYTRACE NEW_LAZYTRACE [RUNS] > docs/results/NAME.md
# SCENES (space-separated) overrides the scenes (default: those of the grid paper's Table 1 here);
# OLD_COMMIT and NEW_COMMIT name the commits the two builds come from, for the record.
set -euo pipefail
old=$1 new=$2 runs=${3:-3}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
. "$(dirname "$0")/common.sh"
scenes=${SCENES:-"house-grid:3x3 house-row:8 hairball:3000 teapot-stadium sphere:6 cornell"}
echo "- command: \`SCENES=\"$scenes\" benchmarks/irgrid_memory.sh OLD NEW $runs\` (native backend, $(nproc) work-groups, --structure irgrid --build full)"
echo "- old: ${OLD_COMMIT:-OLD}, new: ${NEW_COMMIT:-NEW}; machine: $(lt_machine); date $(date -u +%Y-%m-%d)"
echo "- MB: memory_bytes (everything the structure holds after the build), node_bytes (cells),"
echo "  reference_bytes, map_bytes (voxel map) of the statistics, in 2^20 bytes; build ms: median of $runs runs,"
echo "  old and new alternated run by run; the BVH column: the full SAH BVH's memory_bytes (new build)"
echo
echo "| scene | old MB | new MB | new / old | cells old -> new | references old -> new | voxel map old -> new | old build ms | new build ms | BVH MB | new / BVH |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
median() { sort -n | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2}'; }
stat() { python3 -c "import json; print(json.load(open('$1'))['$2'])"; }
for scene in $scenes; do
  : >"$tmp/old" ; : >"$tmp/new"
  for r in $(seq "$runs"); do
    for side in old new; do
      "${!side}" render "$scene" --structure irgrid --build full --device native --size 64x64 \
        -o "$tmp/x.png" --stats "$tmp/$side.json" >/dev/null 2>&1
      stat "$tmp/$side.json" build_ms >>"$tmp/$side"
    done
  done
  "$new" render "$scene" --structure bvh --build full --device native --size 64x64 -o "$tmp/x.png" \
    --stats "$tmp/bvh.json" >/dev/null 2>&1
  python3 - "$scene" "$tmp" "$(median <"$tmp/old")" "$(median <"$tmp/new")" <<'EOF'
import json, sys
scene, tmp, old_ms, new_ms = sys.argv[1:]
o, n, b = (json.load(open(f"{tmp}/{k}.json")) for k in ("old", "new", "bvh"))
mb = lambda s, k: s[k] / 2**20
pair = lambda k: f"{mb(o, k):.2f} -> {mb(n, k):.2f}"
print(f"| {scene} | {mb(o, 'memory_bytes'):.2f} | {mb(n, 'memory_bytes'):.2f} | "
      f"{n['memory_bytes'] / o['memory_bytes']:.2f} | {pair('node_bytes')} | {pair('reference_bytes')} | "
      f"{pair('map_bytes')} | {float(old_ms):.1f} | {float(new_ms):.1f} | {mb(b, 'memory_bytes'):.2f} | "
      f"{n['memory_bytes'] / b['memory_bytes']:.2f} |")
EOF
done
