#!/usr/bin/env bash
# The Python module's overhead per call against the C API (issue 18): batches of 10, 10k and 1M
# rays on a full BVH, traced from C and from Python, on both backends; medians written to
# docs/results/python_overhead.md.
#   benchmarks/python_overhead.sh [SCENE] [ROUNDS]      (default sphere:5, 5 rounds; about 3 minutes)
set -euo pipefail
cd "$(dirname "$0")/.."
. benchmarks/common.sh
lt_bench_prepare
scene=${1:-sphere:5}
rounds=${2:-5}
python=$(sed -n 's/^LT_PYTHON:FILEPATH=//p' build/CMakeCache.txt)
out=$R/python_overhead.md
table=$(PYTHONDONTWRITEBYTECODE=1 PYTHONPATH=python LAZYTRACE_LIBRARY=build/liblazytrace.so \
  "${python:-python3}" benchmarks/python_overhead.py build "$scene" "$rounds" native opencl)
{
  echo "# Python overhead per call against the C API"
  echo
  lt_results_header "benchmarks/python_overhead.sh $*"
  echo
  echo "$table"
} >"$out"
cat "$out"
