#!/usr/bin/env bash
# The on-demand BVH's Morton top against its SAH top on collision frames that rebuild (issue 17,
# point 2), written to docs/results/morton_top.md:
#   1. where a requested frame goes with each top (bench_frame_parts), the tops interleaved run
#      by run, each cell the median over the runs of the run's median frame;
#   2. the per-frame peers side by side (bench_ondemand collide --peers): requested and
#      speculative with either top, the parallel LBVH and Embree low, interleaved run by run.
#   benchmarks/morton_top.sh [--runs R] [--tops "sah morton:4096 ..."] [SCENE...]
# Defaults: 3 runs, tops sah and morton (its default bound), the collision table's scenes.
set -euo pipefail
cd "$(dirname "$0")/.."
. benchmarks/common.sh
runs=3
tops="sah morton"
while [ $# -gt 0 ]; do
  case "$1" in
    --runs) runs=$2; shift 2 ;;
    --tops) tops=$2; shift 2 ;;
    *) break ;;
  esac
done
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(house-grid:3x3 house-grid:6x5 teapot-stadium hairball:10000)
lt_bench_prepare >/dev/null
parts=$(mktemp)
trap 'rm -f "$parts"' EXIT

{
  echo "# The Morton top: collision frames with the triangles sorted once and the top split by code"
  echo
  lt_results_header "benchmarks/morton_top.sh --runs $runs --tops \"$tops\" ${scenes[*]}"
  echo "- native backend, $(nproc) work-groups; 100 agents x 8 rays x 20 frames, every frame rebuilt"
  echo "  (the collision table's seeds); Embree $(dpkg-query -W -f='${Version}' libembree-dev 2>/dev/null ||
    echo 'not installed') with as many threads; \`morton:K\` is \`--top morton --morton-above K\`"
  echo "- the machine was shared with other engineers' builds and tests while this ran (load average"
  echo "  $(cut -d' ' -f1-3 /proc/loadavg) at the end): compare within a table, run by run, not across files"
  echo
  echo "## Where a requested frame goes"
  echo
  echo "bench_frame_parts per top; each cell the median over $runs runs of the run's median frame."
  echo
  for ((r = 0; r < runs; r++)); do
    for top in $tops; do build/benchmarks/bench_frame_parts --runs 1 --top "$top" "${scenes[@]}" | tail -n +3; done
  done >"$parts"
  python3 - "$parts" <<'PY'
import re, statistics, sys
rows = {}
for line in open(sys.argv[1]):
    cells = [c.strip() for c in line.strip().strip('|').split('|')]
    rows.setdefault((cells[0], cells[1]), []).append(cells)
print("| scene | top | triangles | nodes per frame | frame ms | set-up ms | top path ms | other requested nodes ms | trace ms |")
print("|---|---|---:|---:|---:|---:|---:|---:|---:|")
for (scene, top), runs in rows.items():
    def med(i):
        return statistics.median(float(re.match(r"-?[0-9.]+", r[i]).group()) for r in runs)
    frame = med(4)
    out = [scene, top, runs[0][2], "%.0f" % med(3), "%.1f" % frame]
    out += ["%.1f (%.0f%%)" % (med(i), 100 * med(i) / frame) for i in range(5, 9)]
    print("| " + " | ".join(out) + " |")
PY
  echo
  echo "## Per frame against the peers"
  echo
  build/benchmarks/bench_ondemand collide --peers --runs "$runs" "${scenes[@]}"
} >"$R/morton_top.md"
