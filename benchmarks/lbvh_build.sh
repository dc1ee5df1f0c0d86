#!/usr/bin/env bash
# LBVH build time per frame, paired: several lazytrace binaries (for example this commit's and an
# older one's, built with scripts/build into another directory) and work-group counts, run by
# run interleaved, on the collision workload (lazytrace collide --structure lbvh, native backend),
# which rebuilds every frame. Prints the median over runs of each variant's build ms per frame.
#   benchmarks/lbvh_build.sh [--runs R] [--frames F] BINARY:WORK_GROUPS... -- SCENE...  (paths from the repository root)
#   e.g. benchmarks/lbvh_build.sh /tmp/old/lazytrace:2 build/lazytrace:1 build/lazytrace:2 -- hairball:10000
set -euo pipefail
runs=5 frames=10 variants=() scenes=()
while [ $# -gt 0 ]; do
  case $1 in
    --runs) runs=$2; shift 2 ;;
    --frames) frames=$2; shift 2 ;;
    --) shift; scenes=("$@"); break ;;
    *) variants+=("$1"); shift ;;
  esac
done
[ ${#variants[@]} -gt 0 ] && [ ${#scenes[@]} -gt 0 ] || { sed -n 2,8p "$0"; exit 2; }
cd "$(dirname "$0")/.."
. benchmarks/common.sh
median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
echo "# LBVH build per frame, paired"
echo
lt_results_header "benchmarks/lbvh_build.sh --runs $runs --frames $frames ${variants[*]} -- ${scenes[*]}"
echo "- build ms: the collision command's build_ms over its frames, divided by the frames; the"
echo "  variants run one after the other within each run; the machine is shared with other work"
echo
echo "| scene | variant (binary, work-groups) | build ms per frame, median of $runs runs | runs |"
echo "|---|---|---:|---|"
for scene in "${scenes[@]}"; do
  tmp=$(mktemp -d)
  for run in $(seq "$runs"); do
    for v in "${variants[@]}"; do
      bin=${v%:*} groups=${v##*:}
      "$bin" collide "$scene" --structure lbvh --device native --work-groups "$groups" --frames "$frames" --stats - 2>/dev/null |
        python3 -c "import json, sys; print(json.load(sys.stdin)['build_ms'] / $frames)" >>"$tmp/$(echo "$v" | tr '/:' '__')"
    done
  done
  for v in "${variants[@]}"; do
    f="$tmp/$(echo "$v" | tr '/:' '__')"
    echo "| $scene | \`$v\` | $(median <"$f" | xargs printf '%.1f') | $(xargs printf '%.1f ' <"$f")|"
  done
  rm -r "$tmp"
done
