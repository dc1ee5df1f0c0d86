#!/usr/bin/env bash
# The on-demand paper's experiments in shape (issue 4), lazytrace against Embree 3, written to
# docs/results/: ondemand_table1.md (time to image, primary and primary + 8 AO rays),
# ondemand_sweep.md and ondemand_sweep.png (house-row:1..16: nodes built and time to image),
# ondemand_collision.md (100 agents x 8 rays x 20 frames, rebuilt every frame).
#   benchmarks/ondemand.sh [--runs R] [--size N]      (defaults: 3 runs, 1024x1024)
# Takes about 15 minutes on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."
. benchmarks/common.sh
lt_bench_prepare
B=build/benchmarks/bench_ondemand
header() {
  echo "- command: \`benchmarks/ondemand.sh $*\` (native backend, $(nproc) work-groups; Embree with as many threads;"
  echo "  the LBVH is built on the host on one thread, then traced by the native trace kernel)"
  echo "- commit: $(lt_commit)"
  echo "- machine: $(lt_machine)"
  echo "- Embree $(dpkg-query -W -f='${Version}' libembree-dev 2>/dev/null || echo 'not installed') (robust flag); date $(date -u +%Y-%m-%d)"
  echo "- times are milliseconds to image: build plus trace, without scene loading and kernel compilation;"
  echo "  medians of the runs, methods interleaved run by run"
}

{
  echo "# Time to image: full, requested and speculative SAH BVH, LBVH and Embree (the paper's Table 1)"
  echo
  header "$@"
  echo
  $B table "$@" --csv $R/ondemand_table1.csv house-grid:3x3 house-grid:6x5 house-row:8 hairball:10000 teapot-stadium cornell
} >$R/ondemand_table1.md

{
  echo "# Hidden geometry: house-row:1 to house-row:16 from the outer camera (the paper's Figure 5)"
  echo
  header "$@"
  echo
  echo "![nodes built and time to image](ondemand_sweep.png)"
  echo
  $B sweep "$@" --csv $R/ondemand_sweep.csv
} >$R/ondemand_sweep.md

{
  echo "# Collision rays: 100 agents x 8 rays x 20 frames, every frame rebuilt (the paper's Table 4)"
  echo
  header "$@"
  echo
  $B collide "$@" --csv $R/ondemand_collision.csv house-grid:3x3 house-grid:6x5 teapot-stadium hairball:10000
} >$R/ondemand_collision.md

gnuplot <<GP
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
cat $R/ondemand_table1.md $R/ondemand_sweep.md $R/ondemand_collision.md
