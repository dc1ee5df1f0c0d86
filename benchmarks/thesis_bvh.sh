#!/usr/bin/env bash
# The thesis' comparison (Thrane and Simonsen 2005; issue 16): the uniform grid, the kd-tree with
# its three traversals (stack, restart, backtrack), the escape-index BVH from the SAH,
# Kay-Kajiya and Goldsmith-Salmon builders, the SAH BVH and the QBVH: build time, primary-ray
# speed (512x512, outer camera) and memory, on both backends, medians of interleaved runs,
# written to docs/results/thesis_bvh.md.
#   benchmarks/thesis_bvh.sh [RUNS]        (default 3)
# SCENES and METHODS (one method a line: a label, a colon, the structure options) override the
# defaults.
set -euo pipefail
cd "$(dirname "$0")/.."
. benchmarks/common.sh
lt_bench_prepare
runs=${1:-3}
scenes=${SCENES:-"house-grid:3x3 sphere:6"}
methods=${METHODS:-"uniform grid:--structure grid
kd-tree, stack traversal:--structure kdtree --build full
kd-tree, restart (stackless):--structure kdtree --build full --traversal restart
kd-tree, backtrack (stackless):--structure kdtree --build full --traversal backtrack
SAH BVH (full build):--structure bvh --build full
QBVH:--structure qbvh
escape-index BVH, SAH builder:--structure escape-bvh
escape-index BVH, Kay-Kajiya:--structure escape-bvh --builder kay-kajiya
escape-index BVH, Goldsmith-Salmon:--structure escape-bvh --builder goldsmith-salmon"}
# KEEP=DIR keeps the runs' statistics there (and makes the table again from them with RUNS=0).
T=${KEEP:-$(mktemp -d)}
[ -n "${KEEP:-}" ] && mkdir -p "$T" || trap 'rm -rf "$T"' EXIT
table_runs=$runs
[ "${RUNS:-}" = 0 ] && runs=0
# Every run goes once through every scene, backend and method, one after the other.
for run in $(seq "$runs"); do
  for scene in $scenes; do
    for device in native opencl; do
      m=0
      while IFS= read -r line; do
        m=$((m + 1))
        # shellcheck disable=SC2086
        build/lazytrace render "$scene@outer" ${line#*:} --device $device --size 512x512 -o "$T/x.png" \
          --stats "$T/$scene.$device.$m.$run.json" 2>/dev/null
      done <<<"$methods"
    done
  done
done
table=$(python3 - "$T" "$table_runs" "$scenes" "$methods" <<'PY'
import json, statistics, sys
tmp, runs, scenes, methods = sys.argv[1], int(sys.argv[2]), sys.argv[3].split(), sys.argv[4].splitlines()
for scene in scenes:
    print(f"### {scene}\n")
    print("| method | backend | build ms | primary Mrays/s | memory MiB | nodes | node bytes | depth |")
    print("| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |")
    for device in ("native", "opencl"):
        for m, line in enumerate(methods, 1):
            st = [json.load(open(f"{tmp}/{scene}.{device}.{m}.{r}.json")) for r in range(1, runs + 1)]
            med = lambda k: statistics.median(s[k] for s in st)
            mrays = statistics.median(s["rays"] / s["trace_ms"] / 1000.0 for s in st)
            s = st[0]
            num = lambda k, scale=1, digits=0: "n/a" if s.get(k) is None else f"{s[k] / scale:.{digits}f}"
            print(f"| {line.split(':')[0]} | {device} | {med('build_ms'):.0f} | {mrays:.2f} | "
                  f"{num('memory_bytes', 2**20, 1)} | {num('nodes_built')} | {num('node_bytes')} | {num('max_depth')} |")
    print()
PY
)
{
  echo "# The thesis' comparison: uniform grid, kd-tree traversals, the BVH family, SAH BVH and QBVH"
  echo
  lt_results_header "benchmarks/thesis_bvh.sh $table_runs"
  echo "- the machine was shared with other engineers' builds and tests while this ran: single timings move by"
  echo "  10-30% from run to run, so compare the ratios within a run rather than figures across tables"
  echo "- primary rays of the outer camera, 512x512, one sample; Mrays/s from trace_ms of the statistics (build and"
  echo "  kernel compile excluded); build ms is the structure's build_ms; medians of $table_runs runs, interleaved (each run"
  echo "  goes once through every scene, backend and method); memory is memory_bytes (nodes or cells and triangle references;"
  echo "  the kd-tree's also its parent links, node cells, task pool and triangle boxes); depth: the deepest"
  echo "  the tree can be (the stack a traversal may need; the uniform grid has none)"
  echo
  echo "$table"
} >"$R/thesis_bvh.md"
cat "$R/thesis_bvh.md"
