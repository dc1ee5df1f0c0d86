#!/usr/bin/env bash
# Strong scaling of lazytrace under mpirun on one machine: house-grid:6x5 rendered with primary
# rays, and with primary plus AO rays, by 1 process and by mpirun -np 1, 2, 3 and 4 (3 and 4
# oversubscribed: more ranks than cores, to show the overhead), each rank taking a contiguous
# band of rows (tiles), every ranks-th pixel (interleaved) or bands of rows from a shared counter
# as it asks for them (queue). Reports the median over RUNS of the
# time to image (the slowest rank's build plus trace), of the wall time of the whole command
# (starting the ranks, loading, compiling kernels, gathering), the load imbalance (slowest rank's
# time to image over the mean) and the nodes built summed over ranks against one process's (how
# much of the tree the ranks build twice), both in the default speculative mode and, for the node
# counts alone, in requested mode (deterministic: only nodes rays reach).
#   benchmarks/mpi_scaling.sh [RUNS] [SIZE]      (default 3 runs, 512x512; writes docs/results/mpi_scaling.md)
# DEVICES (default "native opencl") picks the backends.
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-3} size=${2:-512x512}
devices=${DEVICES:-"native opencl"}
. benchmarks/common.sh
lt_bench_prepare
LT=build/lazytrace
mpirun=$(command -v mpirun) || { echo "mpi_scaling: no mpirun (scripts/setup installs Open MPI)" >&2; exit 1; }
grep -q "lazytrace: MPI layer ON" build/configure.log || { echo "mpi_scaling: the build has no MPI layer" >&2; exit 1; }
mpi=("$mpirun" --oversubscribe)
[ "$(id -u)" -eq 0 ] && mpi+=(--allow-run-as-root)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
w=${size%x*} h=${size#*x}
printf '{"meshes": [{"generator": "house-grid:6x5"}], "image": {"width": %d, "height": %d},\n "effects": {"primary": true}}\n' "$w" "$h" >"$tmp/primary.json"
printf '{"meshes": [{"generator": "house-grid:6x5"}], "image": {"width": %d, "height": %d},\n "effects": {"primary": true, "ao": {"samples": 4, "distance": 2}}}\n' "$w" "$h" >"$tmp/ao.json"

# One run: prints "time_to_image_ms wall_ms nodes_built imbalance gather_ms".
one() {
  local np=$1; shift
  local start end
  start=$(date +%s.%N)
  if [ "$np" = 0 ]; then "$LT" "$@" --stats "$tmp/s.json" >/dev/null 2>"$tmp/err"
  else "${mpi[@]}" -np "$np" "$LT" "$@" --stats "$tmp/s.json" >/dev/null 2>"$tmp/err"; fi || { cat "$tmp/err" >&2; exit 1; }
  end=$(date +%s.%N)
  python3 - "$tmp/s.json" "$start" "$end" <<'EOF'
import json, sys
s = json.load(open(sys.argv[1]))
ranks = s.get("per_rank") or [{"total_ms": s["total_ms"]}]
mean = sum(r["total_ms"] for r in ranks) / len(ranks)
gather = s["mpi"]["gather_ms"] if "mpi" in s else 0.0
print(f"{s['total_ms']:.1f} {1000 * (float(sys.argv[3]) - float(sys.argv[2])):.0f} {s['nodes_built']:.0f} "
      f"{s['total_ms'] / mean if mean > 0 else 1:.2f} {gather:.1f}")
EOF
}
median() { sort -n | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2}'; }
col() { awk -v c="$1" '{print $c}'; }

{
  echo "# lazytrace under mpirun on one machine: strong scaling on house-grid:6x5"
  echo
  echo "- command: \`benchmarks/mpi_scaling.sh $runs $size\` (DEVICES=\"$devices\"); commit $(lt_commit); date $(date -u +%Y-%m-%d)"
  echo "- machine: $(lt_machine); $(mpirun --version | head -1); shared with other work while measured, so"
  echo "  times are noisy: medians of $runs runs"
  echo "- scene: house-grid:6x5 ($size, its outer camera), BVH, default speculative build; AO: 4 samples, distance 2"
  echo "- ranks: 1 process = the tool without mpirun; np N = \`mpirun -np N\`; each rank launches"
  echo "  max(1, cores / ranks on the machine) work-groups, so np 3 and 4 are oversubscribed (more processes than cores)"
  echo "- time to image: the slowest rank's build plus trace (statistics total_ms); wall: the whole command,"
  echo "  ranks started, scene loaded and kernels compiled on every rank, image gathered and written;"
  echo "  imbalance: the slowest rank's time to image over the mean rank's; nodes: summed over ranks,"
  echo "  and their ratio to one process's (1 process: its own); queue: bands of rows taken one at a time"
  echo "  from a counter on rank 0, guided: each half the rows left over the ranks, at least height / (16 ranks)"
  echo
  for device in $devices; do
    echo "## $device backend"
    echo
    echo "| effects | ranks | split | time to image ms | speed-up | wall ms | imbalance | nodes built (sum) | nodes / 1 process | requested-mode nodes (sum) | requested / 1 process | gather ms |"
    echo "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    for fx in primary ao; do
      base_t="" base_n="" base_r=""
      for np in 0 1 2 3 4; do
        for split in tiles interleaved queue; do
          [ "$np" -le 1 ] && [ "$split" != tiles ] && continue
          : >"$tmp/runs"
          for r in $(seq "$runs"); do
            one "$np" render "$tmp/$fx.json" -o "$tmp/x.png" --device "$device" --split "$split" >>"$tmp/runs"
          done
          req=$(one "$np" render "$tmp/$fx.json" -o "$tmp/x.png" --device "$device" --split "$split" --build requested | col 3)
          t=$(col 1 <"$tmp/runs" | median) wall=$(col 2 <"$tmp/runs" | median) n=$(col 3 <"$tmp/runs" | median)
          imb=$(col 4 <"$tmp/runs" | median) g=$(col 5 <"$tmp/runs" | median)
          if [ "$np" = 0 ]; then base_t=$t base_n=$n base_r=$req; fi
          label=$([ "$np" = 0 ] && echo "1 process" || echo "np $np")
          [ "$np" = 0 ] && s="-" || s=$split
          awk -v fx="$fx" -v l="$label" -v s="$s" -v t="$t" -v bt="$base_t" -v wl="$wall" -v imb="$imb" -v n="$n" \
              -v bn="$base_n" -v rq="$req" -v br="$base_r" -v g="$g" \
            'BEGIN {printf "| %s | %s | %s | %.0f | %.2f | %.0f | %.2f | %.0f | %.2f | %.0f | %.2f | %.1f |\n", fx, l, s, t, bt / t, wl, imb, n, n / bn, rq, rq / br, g}'
        done
      done
    done
    echo
  done
} >"$R/mpi_scaling.md.tmp"
mv "$R/mpi_scaling.md.tmp" "$R/mpi_scaling.md"
cat "$R/mpi_scaling.md"
