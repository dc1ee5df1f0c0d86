#!/usr/bin/env bash
# Trace throughput of the full irregular grid against the full SAH BVH on primary rays (issue
# 15's target: within 1.2x of the BVH), for two builds of lazytrace side by side: an older one
# (irgrid only) and a newer one (irgrid and BVH). Per scene and device, the runs go old irgrid,
# new irgrid, BVH, run by run; medians of the runs, and of the paired ratios to the BVH.
#   benchmarks/irgrid_walk.sh OLD_LAZYTRACE NEW_LAZYTRACE [RUNS] [SIZE]
# SCENES and DEVICES (space-separated) override the Table 1 scenes and "native opencl".
set -euo pipefail
old=$1 new=$2 runs=${3:-3} size=${4:-512}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
. "$(dirname "$0")/common.sh"
scenes=${SCENES:-"house-grid:3x3 house-row:8 hairball:3000 teapot-stadium sphere:6 cornell"}
devices=${DEVICES:-"native opencl"}
lt_results_header "SCENES=\"$scenes\" DEVICES=\"$devices\" benchmarks/irgrid_walk.sh OLD NEW $runs $size"
echo "- ${size}x$size primary rays from each scene's outer camera, every structure built in full;"
echo "  trace_ms of each run's statistics (the trace alone); Mrays/s = rays / trace_ms; medians of $runs runs"
echo
echo "| scene | device | BVH Mrays/s | irgrid old Mrays/s | irgrid new Mrays/s | old / BVH time | new / BVH time |"
echo "|---|---|---:|---:|---:|---:|---:|"
median() { sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2}'; }
trace_ms() { # BINARY STRUCTURE SCENE DEVICE
  "$1" render "$3" --structure "$2" --build full --device "$4" --size "${size}x$size" -o "$tmp/x.png" \
    --stats "$tmp/s.json" >/dev/null 2>&1
  python3 -c "import json; s = json.load(open('$tmp/s.json')); print(s['trace_ms'], s['rays'])"
}
for scene in $scenes; do
  for device in $devices; do
    : >"$tmp/old" ; : >"$tmp/new" ; : >"$tmp/bvh" ; : >"$tmp/r_old" ; : >"$tmp/r_new"
    for r in $(seq "$runs"); do
      read -r t_old rays < <(trace_ms "$old" irgrid "$scene" "$device")
      read -r t_new _ < <(trace_ms "$new" irgrid "$scene" "$device")
      read -r t_bvh _ < <(trace_ms "$new" bvh "$scene" "$device")
      echo "$t_old" >>"$tmp/old" ; echo "$t_new" >>"$tmp/new" ; echo "$t_bvh" >>"$tmp/bvh"
      awk -v a="$t_old" -v b="$t_bvh" 'BEGIN {print a / b}' >>"$tmp/r_old"
      awk -v a="$t_new" -v b="$t_bvh" 'BEGIN {print a / b}' >>"$tmp/r_new"
    done
    mrays() { awk -v t="$(median <"$tmp/$1")" -v n="$rays" 'BEGIN {printf "%.2f", n / t / 1000}'; }
    printf "| %s | %s | %s | %s | %s | %.2f | %.2f |\n" "$scene" "$device" "$(mrays bvh)" "$(mrays old)" "$(mrays new)" \
      "$(median <"$tmp/r_old")" "$(median <"$tmp/r_new")"
  done
done
