#!/usr/bin/env bash
# The on-demand paper's kd-tree experiments in shape (issue 14), beside the SAH BVH and Embree 3,
# written to docs/results/:
#   kd_table2.md            Table 2: Kd-tree, Kd-tree_R, Kd-tree_A time to image, build, trace,
#                           sort operations (primary and primary + 8 AO), the BVH and Embree beside
#   kd_table3.md            Table 3: traversal steps and triangle tests per primary ray, LBVH,
#                           BVH and kd-tree, fully built
#   kd_sweep.md, .png       Figure 5 for the kd-tree: house-row:1..16 from the outer camera
#   kd_collision.md         Table 4 with kd rows: 100 agents x 8 rays x 20 frames, rebuilt per frame
#   benchmarks/kdtree.sh [--runs R] [--size N]      (defaults: 3 runs, 1024x1024)
# Takes about 25 minutes on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."
. benchmarks/common.sh
lt_bench_prepare
B=build/benchmarks/bench_ondemand
header() {
  echo "- command: \`benchmarks/kdtree.sh $*\` (native backend, $(nproc) work-groups; Embree with as many threads)"
  echo "- commit: $(lt_commit)"
  echo "- machine: $(lt_machine)"
  echo "- Embree $(dpkg-query -W -f='${Version}' libembree-dev 2>/dev/null || echo 'not installed') (robust flag); date $(date -u +%Y-%m-%d)"
  echo "- times are milliseconds: build plus trace, without scene loading and kernel compilation;"
  echo "  medians of the runs, methods interleaved run by run; every lazytrace method's closest hits"
  echo "  are checked against the full BVH's"
}

{
  echo "# kd-tree time to image: full, requested and speculative (the paper's Table 2)"
  echo
  header "$@"
  echo "- Kd_R and Kd_A columns: time to image / trace time / sort operations, each relative to the full"
  echo "  kd-tree's (negative: less); BVH and BVH_A are the full and speculative SAH BVH of the same run"
  echo
  $B table --kd "$@" --csv $R/kd_table2.csv house-grid:3x3 house-grid:6x5 house-row:8 hairball:10000 teapot-stadium cornell
} >$R/kd_table2.md

{
  echo "# Traversal steps and triangle tests per primary ray, fully built trees (the paper's Table 3)"
  echo
  header "$@"
  echo
  $B steps "$@" house-grid:3x3 house-grid:6x5 house-row:8 hairball:10000 teapot-stadium cornell
} >$R/kd_table3.md

{
  echo "# Hidden geometry for the kd-tree: house-row:1 to house-row:16 from the outer camera (the paper's Figure 5)"
  echo
  header "$@"
  echo
  echo "![kd-tree nodes built and time to image](kd_sweep.png)"
  echo
  $B sweep --kd "$@" --csv $R/kd_sweep.csv
} >$R/kd_sweep.md

{
  echo "# Collision rays with kd rows: 100 agents x 8 rays x 20 frames, every frame rebuilt (the paper's Table 4)"
  echo
  header "$@"
  echo
  $B collide "$@" --csv $R/kd_collision.csv house-grid:3x3 teapot-stadium hairball:10000
} >$R/kd_collision.md

gnuplot <<GP
set terminal pngcairo size 1100,450 font ",10"
set output "$R/kd_sweep.png"
set datafile separator ","
set multiplot layout 1,2
set title "kd-tree nodes built (house-row:N, outer camera)"
set xlabel "houses in the row"; set ylabel "nodes built"; set logscale y; set key top left
plot "$R/kd_sweep.csv" using 1:3 with linespoints title "Kd-tree (full)", \
     "" using 1:4 with linespoints title "Kd-tree_R", "" using 1:5 with linespoints title "Kd-tree_A"
unset logscale y
set title "Time to image (ms)"
set ylabel "ms"
plot "$R/kd_sweep.csv" using 1:6 with linespoints title "Kd-tree (full)", "" using 1:7 with linespoints title "Kd-tree_R", \
     "" using 1:8 with linespoints title "Kd-tree_A", "" using 1:9 with linespoints title "BVH (full)", \
     "" using 1:10 with linespoints title "Embree"
unset multiplot
GP
cat $R/kd_table2.md $R/kd_table3.md $R/kd_sweep.md $R/kd_collision.md
