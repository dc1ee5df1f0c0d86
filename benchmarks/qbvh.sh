#!/usr/bin/env bash
# The QBVH against the binary SAH BVH it collapses (issue 16; Bogolepov and Ulyanov's
# comparison): primary and diffuse rays on both backends, node memory, depth, Embree 3 beside,
# medians of interleaved runs, written to docs/results/qbvh.md.
#   benchmarks/qbvh.sh [--size N] [--runs R]      (defaults 1024, 5)
# SCENES (space-separated) overrides the scenes.
set -euo pipefail
cd "$(dirname "$0")/.."
. benchmarks/common.sh
lt_bench_prepare
out=$R/qbvh.md
scenes=${SCENES:-"house-grid:3x3 teapot-stadium hairball:3000 sphere:6"}
tables=""
for scene in $scenes; do
  tables+=$(build/benchmarks/bench_qbvh "$scene" "$@")$'\n\n'
done
{
  echo "# QBVH against the binary SAH BVH it collapses"
  echo
  echo "- command: \`SCENES=\"$scenes\" benchmarks/qbvh.sh $*\`"
  echo "- commit: $(lt_commit)"
  echo "- machine: $(lt_machine)"
  echo "- OpenCL: $(clinfo -l 2>/dev/null | sed -n 's/.*Device #0: //p' | head -1); Embree $(dpkg-query -W -f='${Version}' libembree-dev 2>/dev/null || echo 'not installed')"
  echo "- date: $(date -u +%Y-%m-%d)"
  echo "- trace_ms of the statistics (build and kernel compile excluded), medians over the runs; in each run every"
  echo "  backend, method and ray set is traced once, one after the other; one warm-up run first, not counted"
  echo "- BVH2 is the host SAH BVH (\`builders/host/bvh_sah.c\`, 16 triangles a leaf at most, 32 bins) traced by the"
  echo "  binary kernel; QBVH is that same tree collapsed 4 wide (the paper's layout); \"QBVH, 8 wide\" is what"
  echo "  \`--structure qbvh\` traces natively where the CPU has AVX2 (OpenCL has the 4-wide layout only);"
  echo "  \`bvh --build full\` is the pool's tree, for reference. Diffuse: one cosine-weighted bounce from every"
  echo "  primary hit, unbounded, closest hit"
  echo
  echo "$tables"
} >"$out"
cat "$out"
