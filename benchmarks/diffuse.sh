#!/usr/bin/env bash
# The on-demand paper's Figure 6 in shape (issue 6): time to image against diffuse samples per
# pixel on house-grid:3x3, the SAH BVH built in full against built on demand (and the LBVH),
# every image rendered by lt_render from the effects primary + diffuse {samples, bounces 1}.
# Written to docs/results/: diffuse_samples.md, diffuse_samples.csv, diffuse_samples.png.
#   benchmarks/diffuse.sh [--runs R] [--size N] [--samples 1,2,4,...]   (defaults: 3 runs, 256x256,
#                                                                        1,2,4,8,16,32,64)
# The committed results: --runs 5 --samples 1,2,4,8,16,32,64,128,256, about 5 minutes on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."
. benchmarks/common.sh
lt_bench_prepare
B=build/benchmarks/bench_diffuse
{
  echo "# Diffuse samples per pixel: full against on-demand builds (the paper's Figure 6)"
  echo
  echo "- command: \`benchmarks/diffuse.sh $*\` (native backend, $(nproc) work-groups)"
  echo "- commit: $(lt_commit)"
  echo "- machine: $(lt_machine); date $(date -u +%Y-%m-%d)"
  echo "- scene: house-grid:3x3 from its outer camera; effects primary + diffuse {samples S, bounces 1}, light"
  echo "  from the sky; the batches are exactly those \`lazytrace render\` traces for such a scene file"
  echo "- time to image: build plus trace over all batches (statistics total_ms), without scene loading and"
  echo "  ray generation and shading on the host (the same for every method); medians of the runs, methods"
  echo "  interleaved run by run; every on-demand image equals the full build's byte for byte"
  echo "- Mrays/s: all rays of the image (primary and diffuse) over the time to image, as in the paper"
  echo
  echo "![time to image and Mrays/s against diffuse samples](diffuse_samples.png)"
  echo
  $B "$@" --csv $R/diffuse_samples.csv house-grid:3x3
} >$R/diffuse_samples.md

gnuplot <<GP
set terminal pngcairo size 1100,450 font ",10"
set output "$R/diffuse_samples.png"
set datafile separator ","
set multiplot layout 1,2
set title "Time to image (house-grid:3x3, build + trace)"
set xlabel "diffuse samples per pixel"; set ylabel "ms"; set logscale x 2; set logscale y; set key top left
plot "$R/diffuse_samples.csv" every ::1 using 1:3 with linespoints title "full", \
     "" every ::1 using 1:4 with linespoints title "requested", "" every ::1 using 1:5 with linespoints title "speculative", \
     "" every ::1 using 1:6 with linespoints title "LBVH"
unset logscale y
set title "Performance from time to image (Mrays/s)"
set ylabel "Mrays/s"; set key bottom right
plot "$R/diffuse_samples.csv" every ::1 using 1:10 with linespoints title "full", \
     "" every ::1 using 1:11 with linespoints title "requested", "" every ::1 using 1:12 with linespoints title "speculative", \
     "" every ::1 using 1:13 with linespoints title "LBVH"
unset multiplot
GP
cat $R/diffuse_samples.md
