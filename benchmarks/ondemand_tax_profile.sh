#!/usr/bin/env bash
# Instructions per ray of the persistent kernel against the plain trace kernel on a finished
# tree, counted by callgrind (deterministic: the noise of a shared machine does not reach it).
# Runs bench_ondemand_tax once under callgrind with a dump after every trace call and prints
# the measured run's counts (the warm-up pair is left out). Native backend only, one work-group
# (WORK_GROUPS=N for more): valgrind runs one thread at a time, so a second work-group out of rays
# polls the pool for as long as the first one runs, and its polls land in the counts (3 to 26
# times the plain kernel's instructions per ray in four runs of sphere:6 with two).
#   benchmarks/ondemand_tax_profile.sh [SCENE] [SIZE] [bvh|kdtree] [BUILD_DIR]
#                                      (defaults: sphere:6 256 bvh build)
# For per-line figures, build with CMAKE_C_FLAGS_RELEASE="-O3 -DNDEBUG -g" and run
# callgrind_annotate --auto=yes on the dump files the same run leaves with KEEP=DIR.
set -euo pipefail
scene=${1:-sphere:6} size=${2:-256} structure=${3:-bvh} dir=${4:-build}
launch=lt__ondemand_launch
[ "$structure" = kdtree ] && launch=lt__kd_launch
out=${KEEP:-$(mktemp -d)}
mkdir -p "$out"
valgrind --tool=callgrind --callgrind-out-file="$out/cg.out" --dump-instr=yes --dump-after=$launch \
  --dump-after=lt__trace_finished "$dir/benchmarks/bench_ondemand_tax" "$scene" --size "$size" --runs 1 \
  --device native --structure "$structure" --groups "${WORK_GROUPS:-1}" >"$out/bench.md" 2>"$out/valgrind.log"
counts=$(grep '^| native' "$out/bench.md" | awk -F'|' '{print $4}' | tr -d ' ' | tr '\n' ' ')

# Dumps in call order: the build; the first plain trace (it finds the primary hits the AO
# rays start from); then per ray set a warm-up pair and the measured pair (persistent first).
parts=()
for i in $(seq 1 20); do
  [ -f "$out/cg.out.$i" ] || break
  parts+=("$(sed -n 's/^summary: //p' "$out/cg.out.$i")")
done
[ "${#parts[@]}" -ge 10 ] || { echo "expected 10 dumps, got ${#parts[@]}" >&2; exit 1; }
read -r primary ao <<<"$counts"
echo "| rays | count | persistent instructions per ray | plain instructions per ray | persistent / plain |"
echo "|---|---:|---:|---:|---:|"
awk -v p="${parts[4]}" -v q="${parts[5]}" -v n="$primary" \
  'BEGIN {printf "| primary | %d | %.0f | %.0f | %.3f |\n", n, p / n, q / n, p / q}'
awk -v p="${parts[8]}" -v q="${parts[9]}" -v n="$ao" \
  'BEGIN {printf "| AO | %d | %.0f | %.0f | %.3f |\n", n, p / n, q / n, p / q}'
[ -n "${KEEP:-}" ] || rm -rf "$out"
