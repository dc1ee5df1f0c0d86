#!/usr/bin/env bash
# Instructions per ray of the native 8-wide trace kernel and of Embree 3 (rtcIntersect1 for
# primary rays, rtcOccluded1 for AO rays), counted by callgrind on bench_wide_simd's rays
# (deterministic: the noise of a shared machine does not reach it). Only the two trace entry
# points are counted (--toggle-collect), one dump after every trace call; the measured run's
# dumps are read (the warm-up run's counts are the same). Under valgrind Embree picks its
# code path from the CPU valgrind emulates (AVX2, not AVX-512).
#   benchmarks/wide_simd_profile.sh [SCENE] [SIZE] [BUILD_DIR]   (defaults: sphere:5 128 build)
# For per-line figures, build with CMAKE_C_FLAGS_RELEASE="-O3 -DNDEBUG -g" and run
# callgrind_annotate on the dump files the same run leaves with KEEP=DIR (cg.out.17 is the
# 8-wide path's AO trace, cg.out.13 its primary one).
set -euo pipefail
scene=${1:-sphere:5} size=${2:-128} dir=${3:-build}
out=${KEEP:-$(mktemp -d)}
mkdir -p "$out"
valgrind --tool=callgrind --callgrind-out-file="$out/cg.out" --dump-instr=yes \
  --toggle-collect=lt_bvh8_trace_any --toggle-collect=lt_bvh8_trace_closest --toggle-collect=lt_bvh8_trace_other --toggle-collect=rtcIntersect1 --toggle-collect=rtcOccluded1 \
  --dump-after=lt_structure_trace --dump-after=lt_embree_trace \
  "$dir/benchmarks/bench_wide_simd" "$scene" --size "$size" --runs 1 --ao 2 >"$out/bench.md" 2>"$out/valgrind.log"
ao=$(sed -n 's/.*primary rays, \([0-9]*\) AO rays.*/\1/p' "$out/bench.md")
primary=$((size * size))

# Dumps in call order: the two reference traces (BVH2), then per run and ray set BVH2, QBVH4,
# 8 wide, Embree; the measured run is the second.
parts=()
for i in $(seq 1 20); do
  [ -f "$out/cg.out.$i" ] || break
  parts+=("$(sed -n 's/^summary: //p' "$out/cg.out.$i")")
done
[ "${#parts[@]}" -ge 18 ] || { echo "expected 18 dumps (is Embree built in?), got ${#parts[@]}" >&2; exit 1; }
echo "| scene | rays | count | 8 wide instructions per ray | Embree instructions per ray | 8 wide / Embree |"
echo "|---|---|---:|---:|---:|---:|"
awk -v s="$scene" -v p="${parts[12]}" -v q="${parts[13]}" -v n="$primary" \
  'BEGIN {printf "| %s | primary | %d | %.0f | %.0f | %.2f |\n", s, n, p / n, q / n, p / q}'
awk -v s="$scene" -v p="${parts[16]}" -v q="${parts[17]}" -v n="$ao" \
  'BEGIN {printf "| %s | AO | %d | %.0f | %.0f | %.2f |\n", s, n, p / n, q / n, p / q}'
[ -n "${KEEP:-}" ] || rm -rf "$out"
