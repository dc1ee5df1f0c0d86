#!/usr/bin/env bash
# The on-demand paper's experiments in shape (issue 4), lazytrace against Embree 3, written to
# docs/results/: ondemand_table1.md (time to image, primary and primary + 8 AO rays),
# ondemand_sweep.md and ondemand_sweep.png (house-row:1..16: nodes built and time to image),
# ondemand_collision.md (100 agents x 8 rays x 20 frames, rebuilt every frame, beside Embree's
# default and low-quality builds).
#   benchmarks/ondemand.sh [table1|sweep|collision] [--runs R] [--size N]   (defaults: all three,
#                                                                            3 runs, 1024x1024)
# Takes about 15 minutes on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."
. benchmarks/common.sh
only=all
case "${1:-}" in table1 | sweep | collision) only=$1; shift ;; esac
lt_bench_prepare
B=build/benchmarks/bench_ondemand
header() {
  local part=""
  [ "$only" = all ] || part="$only "
  echo "- command: \`benchmarks/ondemand.sh $part$*\` (native backend, $(nproc) work-groups; Embree with as many"
  echo "  threads, one Embree device kept across builds; the LBVH is built on the host on one thread per"
  echo "  work-group, then traced by the native trace kernel)"
  echo "- commit: $(lt_commit)"
  echo "- machine: $(lt_machine)"
  echo "- Embree $(dpkg-query -W -f='${Version}' libembree-dev 2>/dev/null || echo 'not installed') (robust flag); date $(date -u +%Y-%m-%d)"
  echo "- times are milliseconds to image: build plus trace, without scene loading and kernel compilation;"
  echo "  medians of the runs, methods interleaved run by run"
}

[ "$only" = all ] || [ "$only" = table1 ] && {
  echo "# Time to image: full, requested and speculative SAH BVH, LBVH, Embree and the QBVH (the paper's Table 1)"
  echo
  header "$@"
  echo
  $B table "$@" --csv $R/ondemand_table1.csv house-grid:3x3 house-grid:6x5 house-row:8 hairball:10000 teapot-stadium cornell
} >$R/ondemand_table1.md

[ "$only" = all ] || [ "$only" = sweep ] && {
  echo "# Hidden geometry: house-row:1 to house-row:16 from the outer camera (the paper's Figure 5)"
  echo
  header "$@"
  echo
  echo "![nodes built and time to image](ondemand_sweep.png)"
  echo
  $B sweep "$@" --csv $R/ondemand_sweep.csv
} >$R/ondemand_sweep.md

[ "$only" = all ] || [ "$only" = collision ] && {
  echo "# Collision rays: 100 agents x 8 rays x 20 frames, every frame rebuilt (the paper's Table 4)"
  echo
  header "$@"
  echo "- the machine is shared with other work, so single runs are noisy; compare within one run"
  echo "- best on-demand: the fastest per frame of requested and speculative (SAH or Morton top), Kd_R and Kd_A; the targets"
  echo "  (issue 17): best / Embree low at most 0.6, best / LBVH below 1"
  echo
  $B collide "$@" --csv $R/ondemand_collision.csv house-grid:3x3 house-grid:6x5 teapot-stadium hairball:10000
} >$R/ondemand_collision.md

[ "$only" = all ] || [ "$only" = sweep ] && gnuplot <<GP
set terminal pngcairo size 1100,450 font ",10"
set output "$R/ondemand_sweep.png"
set datafile separator ","
set multiplot layout 1,2
set title "Nodes built (house-row:N, outer camera, 1024x1024)"
set xlabel "houses in the row"; set ylabel "nodes built"; set logscale y; set key top left
plot "$R/ondemand_sweep.csv" using 1:3 with linespoints title "full", \
     "" using 1:4 with linespoints title "requested", "" using 1:5 with linespoints title "speculative"
unset logscale y
set title "Time to image (ms)"
set ylabel "ms"
plot "$R/ondemand_sweep.csv" using 1:6 with linespoints title "full", "" using 1:7 with linespoints title "requested", \
     "" using 1:8 with linespoints title "speculative", "" using 1:9 with linespoints title "LBVH", \
     "" using 1:10 with linespoints title "Embree"
unset multiplot
GP
case $only in
  all) cat $R/ondemand_table1.md $R/ondemand_sweep.md $R/ondemand_collision.md ;;
  table1) cat $R/ondemand_table1.md ;;
  sweep) cat $R/ondemand_sweep.md ;;
  collision) cat $R/ondemand_collision.md ;;
esac
