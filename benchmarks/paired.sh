#!/usr/bin/env bash
# Two builds of lazytrace side by side on the on-demand and task-pool benchmarks, to show that a
# change costs no speed: rounds alternate old and new (A B A B ...), each round one run of
# every figure, and the table gives each side's median and the median of the paired ratios
# new/old (a ratio per round, so that the machine's drift hits both alike).
#   benchmarks/paired.sh OLD_BUILD_DIR NEW_BUILD_DIR [ROUNDS] > docs/results/NAME.md
# (build directories as scripts/build makes them: build/benchmarks/bench_ondemand, ...).
# ROUNDS defaults to 5; one round takes about 3 minutes on 2 cores.
set -euo pipefail
old=$1 new=$2 rounds=${3:-5}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
. "$(dirname "$0")/common.sh"

scenes_table="house-grid:3x3 house-grid:6x5 hairball:10000 teapot-stadium"
scenes_collide="house-grid:3x3 hairball:10000 teapot-stadium"
for r in $(seq "$rounds"); do
  for side in old new; do
    dir=${!side}
    echo "round $r/$rounds: $side" >&2
    "$dir/benchmarks/bench_ondemand" table --runs 1 --csv "$tmp/table.$side.$r.csv" $scenes_table >/dev/null 2>&1
    "$dir/benchmarks/bench_ondemand" collide --runs 1 --csv "$tmp/collide.$side.$r.csv" $scenes_collide >/dev/null 2>&1
    "$dir/benchmarks/bench_pool" --runs 1 --keys 2000000 >"$tmp/pool.$side.$r.md" 2>/dev/null
    for build in full speculative; do
      "$dir/lazytrace" render house-grid:6x5 --device opencl --build "$build" --size 1024x1024 -o "$tmp/x.png" \
        --stats "$tmp/render.$build.$side.$r.json" >/dev/null 2>&1
    done
  done
done

{
  echo "- command: \`benchmarks/paired.sh OLD NEW $rounds\`, rounds alternating old and new"
  echo "- machine: $(lt_machine)"
  echo "- date: $(date -u +%Y-%m-%d)"
  echo "- on-demand rows: bench_ondemand (native backend, time to image in ms at 1024x1024, 20 collision frames);"
  echo "  pool rows: bench_pool (2M keys); render rows: \`lazytrace render house-grid:6x5 --device opencl\` total_ms"
  echo
  python3 - "$tmp" "$rounds" <<'PY'
import csv, glob, json, os, re, statistics as st, sys
tmp, rounds = sys.argv[1], int(sys.argv[2])
rows = {}  # figure -> side -> [per round]
def add(name, side, r, value):
    rows.setdefault(name, {"old": {}, "new": {}})[side][r] = value
for side in ("old", "new"):
    for r in range(1, rounds + 1):
        for row in csv.reader(open(f"{tmp}/table.{side}.{r}.csv")):
            if row[3] == "embree": continue
            add(f"table {row[0]}@{row[1]} {row[2]}, {row[3]}", side, r, float(row[4]))
        for row in csv.reader(open(f"{tmp}/collide.{side}.{r}.csv")):
            for name, value in zip(("full", "requested", "speculative", "lbvh"), row[1:5]):
                add(f"collide {row[0]}, {name}", side, r, float(value))
        backend = None
        for line in open(f"{tmp}/pool.{side}.{r}.md"):
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            if len(cells) > 3 and re.match(r"^[0-9.]+$", cells[2]) and "qsort" not in cells[1]:
                add(f"pool {cells[0]}: {cells[1]}", side, r, float(cells[2]))
        for build in ("full", "speculative"):
            d = json.load(open(f"{tmp}/render.{build}.{side}.{r}.json"))
            add(f"render opencl house-grid:6x5 {build}", side, r, d["total_ms"])
print("| figure | old ms (median) | new ms (median) | new / old, median of paired ratios | min - max |")
print("|---|---:|---:|---:|---|")
all_ratios = []
for name, sides in rows.items():
    pairs = [(sides["old"][r], sides["new"][r]) for r in range(1, rounds + 1) if r in sides["old"] and r in sides["new"]]
    if not pairs: continue
    ratios = [n / o for o, n in pairs if o > 0]
    all_ratios.append(st.median(ratios))
    print(f"| {name} | {st.median(o for o, _ in pairs):.1f} | {st.median(n for _, n in pairs):.1f} | "
          f"{st.median(ratios):.3f} | {min(ratios):.2f} - {max(ratios):.2f} |")
print()
print(f"Median over the {len(all_ratios)} figures of their paired ratios: {st.median(all_ratios):.3f} "
      f"(geometric mean {st.geometric_mean(all_ratios):.3f}).")
PY
}
