#!/usr/bin/env bash
# The MPI build under mpirun: with 1, 2 and 3 ranks, on both backends, trace, render and collide
# write byte-identical hits and images to one process's; a rank given a bad input fails the whole
# run, naming the rank and the cause, and leaves no output where the complete one was expected.
set -u
LT=${1:?usage: mpi.sh path/to/lazytrace path/to/mpirun}
MPIRUN=${2:?usage: mpi.sh path/to/lazytrace path/to/mpirun}
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
failures=0; passes=0
pass() { passes=$((passes + 1)); echo "ok    $*"; }
fail() { failures=$((failures + 1)); echo "FAIL  $*"; }

# Three ranks on a machine of fewer cores need --oversubscribe; root needs --allow-run-as-root.
mpi=("$MPIRUN" --oversubscribe)
[ "$(id -u)" -eq 0 ] && mpi+=(--allow-run-as-root)

# Rays from around a sphere towards it, some missing; a scene file with shadows and AO, so that
# secondary batches are split too.
python3 - "$T/in.rays" <<'EOF'
import random, struct, sys
random.seed(19)
with open(sys.argv[1], "wb") as f:
    for _ in range(2001):
        o = [random.uniform(-3, 3) for _ in range(3)]
        d = [-x + random.uniform(-0.6, 0.6) for x in o]
        f.write(struct.pack("<8f", *o, 0.0, *d, 1e30))
EOF
cat >"$T/ao.json" <<'EOF'
{"meshes": [{"generator": "house"}], "lights": [{"point": [3, 6, -8], "intensity": [40, 40, 40]}],
 "image": {"width": 40, "height": 30, "spp": 1},
 "effects": {"primary": true, "shadows": true, "ao": {"samples": 2, "distance": 1.5}}}
EOF

# The same command with one process and under mpirun -np N must write the same bytes.
# same NAME OUTPUT NP ARGS...: ARGS name OUTPUT as their output file.
same() {
  local name=$1 output=$2 np=$3; shift 3
  local args=("$@") one=("$@")
  for i in "${!one[@]}"; do [ "${one[$i]}" = "$output" ] && one[$i]="$output.one"; done
  if [ ! -s "$output.one" ]; then
    timeout 120 "$LT" "${one[@]}" >/dev/null 2>"$T/err" || { fail "$name: one process: $(tail -c 300 "$T/err")"; return; }
  fi
  rm -f "$output"
  timeout 120 "${mpi[@]}" -np "$np" "$LT" "${args[@]}" >/dev/null 2>"$T/err"
  local rc=$?
  if [ $rc -ne 0 ]; then fail "$name: exit $rc: $(tail -c 400 "$T/err")"; return; fi
  if cmp -s "$output" "$output.one"; then pass "$name"; else fail "$name: differs from one process"; fi
}

for device in native opencl; do
  rm -f "$T"/*.one
  for np in 1 2 3; do
    same "trace -np $np on $device" "$T/out.hits" $np trace sphere:2 --rays "$T/in.rays" --hits "$T/out.hits" --device $device
    same "trace --any -np $np on $device" "$T/any.hits" $np trace sphere:2 --rays "$T/in.rays" --hits "$T/any.hits" --any --device $device
    same "render -np $np on $device" "$T/out.png" $np render cornell --size 48x32 --spp 2 --seed 7 -o "$T/out.png" --device $device
    same "render AO and shadows -np $np on $device" "$T/ao.png" $np render "$T/ao.json" -o "$T/ao.png" --device $device
    same "collide -np $np on $device" "$T/c.hits" $np collide house --agents 10 --rays-per-agent 4 --frames 3 --hits "$T/c.hits" --device $device
  done
  same "trace interleaved -np 3 on $device" "$T/out.hits" 3 trace sphere:2 --rays "$T/in.rays" --hits "$T/out.hits" --device $device --split interleaved
  same "render interleaved -np 2 on $device" "$T/ao.png" 2 render "$T/ao.json" -o "$T/ao.png" --device $device --split interleaved
  same "collide interleaved -np 3 on $device" "$T/c.hits" 3 collide house --agents 10 --rays-per-agent 4 --frames 3 --hits "$T/c.hits" --device $device --split interleaved
  # --split queue: bands of rows taken from a counter on rank 0, in whatever order the ranks come.
  for np in 1 2 3; do
    same "render queue AO and shadows -np $np on $device" "$T/ao.png" $np render "$T/ao.json" -o "$T/ao.png" --device $device --split queue
  done
  same "render queue -np 3 on $device" "$T/out.png" 3 render cornell --size 48x32 --spp 2 --seed 7 -o "$T/out.png" --device $device --split queue
  same "kd-tree trace -np 2 on $device" "$T/kd.hits" 2 trace sphere:2 --rays "$T/in.rays" --hits "$T/kd.hits" --device $device --structure kdtree
done

# Statistics: totals over ranks and one record per rank.
timeout 120 "${mpi[@]}" -np 2 "$LT" trace sphere:2 --rays "$T/in.rays" --hits "$T/s.hits" --device native --stats "$T/s.json" 2>"$T/err"
if python3 - "$T/s.json" <<'EOF'
import json, sys
s = json.load(open(sys.argv[1]))
assert s["rays"] == 2001 and s["mpi"]["ranks"] == 2, s
ranks = s["per_rank"]
assert [r["rays"] for r in ranks] == [1000, 1001], ranks
assert s["nodes_built"] == sum(r["nodes_built"] for r in ranks)
assert s["total_ms"] == max(r["total_ms"] for r in ranks)
EOF
then pass "statistics summed, slowest rank's time, per-rank records"; else fail "statistics: $(head -c 300 "$T/err")"; fi

# With the queue every tile is taken once: the ranks' tiles add up to the image's.
timeout 120 "${mpi[@]}" -np 3 "$LT" render cornell --size 48x32 -o "$T/q.png" --device native --split queue --stats "$T/q.json" 2>"$T/err"
if python3 - "$T/q.json" <<'EOF'
import json, sys
s = json.load(open(sys.argv[1]))
assert s["mpi"]["split"] == "queue" and s["mpi"]["ranks"] == 3, s["mpi"]
ranks = s["per_rank"]
# The guided tiles of 32 rows at 3 ranks: half the rows left over the ranks, at least 1.
tiles, left = 0, 32
while left:
    left -= min(left, max(1, -(-left // 6)))
    tiles += 1
assert tiles == 13 and sum(r["tiles"] for r in ranks) == tiles, ranks
assert s["rays"] == 48 * 32 == sum(r["rays"] for r in ranks), s["rays"]
assert s["rays_by_effect"]["primary"] == 48 * 32, s["rays_by_effect"]
EOF
then pass "queue statistics: every tile taken once, rays summed"; else fail "queue statistics: $(head -c 300 "$T/err")"; fi

# expect_failure NAME OUTPUT PATTERN MPIRUN-ARGS...: non-zero exit, PATTERN on stderr, and OUTPUT
# as it was before (absent, or the old bytes).
expect_failure() {
  local name=$1 output=$2 pattern=$3; shift 3
  local before=absent
  [ -e "$output" ] && before=$(md5sum <"$output")
  timeout 120 "${mpi[@]}" "$@" >/dev/null 2>"$T/err"; local rc=$?
  local after=absent
  [ -e "$output" ] && after=$(md5sum <"$output")
  if [ $rc -eq 0 ]; then fail "$name: accepted"
  elif [ $rc -ge 124 ]; then fail "$name: exit $rc (hang or crash)"
  elif [ "$before" != "$after" ]; then fail "$name: $output was changed"
  elif ! grep -qE -- "$pattern" "$T/err"; then fail "$name: message lacks /$pattern/: $(head -c 400 "$T/err")"
  else pass "$name"; fi
}
rm -f "$T/bad.hits" "$T/bad.png"
expect_failure "a rank with a missing ray file" "$T/bad.hits" "rank 2 of 3 failed: reading rays: .*nosuch.rays: cannot open" \
  -np 2 "$LT" trace sphere:2 --rays "$T/in.rays" --hits "$T/bad.hits" --device native : \
  -np 1 "$LT" trace sphere:2 --rays "$T/nosuch.rays" --hits "$T/bad.hits" --device native
head -c 100 "$T/in.rays" >"$T/trunc.rays"
expect_failure "a rank with a truncated ray file" "$T/bad.hits" "rank 0 of 2 failed: reading rays: .*not a whole number" \
  -np 1 "$LT" trace sphere:2 --rays "$T/trunc.rays" --hits "$T/bad.hits" --device opencl : \
  -np 1 "$LT" trace sphere:2 --rays "$T/in.rays" --hits "$T/bad.hits" --device opencl
head -c 32 "$T/in.rays" >"$T/one.rays"
expect_failure "a rank with another ray file" "$T/bad.hits" "rank 1 of 2 failed: reading rays: .*holds 1 rays" \
  -np 1 "$LT" trace sphere:2 --rays "$T/in.rays" --hits "$T/bad.hits" --device native : \
  -np 1 "$LT" trace sphere:2 --rays "$T/one.rays" --hits "$T/bad.hits" --device native
expect_failure "a rank with a missing scene" "$T/bad.png" "rank 1 of 2 failed: loading the scene: .*no-such.obj" \
  -np 1 "$LT" render cornell --size 16x16 -o "$T/bad.png" --device native : \
  -np 1 "$LT" render "$T/no-such.obj" --size 16x16 -o "$T/bad.png" --device native
expect_failure "a rank with an unknown generator" "$T/bad.hits" "rank 1 of 2 failed: loading the scene: .*pyramid" \
  -np 1 "$LT" collide house --agents 4 --frames 2 --hits "$T/bad.hits" --device native : \
  -np 1 "$LT" collide pyramid:3 --agents 4 --frames 2 --hits "$T/bad.hits" --device native
cp "$T/out.png" "$T/keep.png"
expect_failure "a failed run leaves the old image as it was" "$T/keep.png" "rank 1 of 3 failed" \
  -np 1 "$LT" render cornell --size 48x32 -o "$T/keep.png" --device native : \
  -np 1 "$LT" render cornell --size 48x32 -o "$T/keep.png" --device native --work-groups 16777216 : \
  -np 1 "$LT" render cornell --size 48x32 -o "$T/keep.png" --device native
expect_failure "an unwritable output" "/nonexistent/x.hits" "rank 0 of 2 failed: writing hits" \
  -np 2 "$LT" trace sphere:2 --rays "$T/in.rays" --hits /nonexistent/x.hits --device native

echo "mpi: $passes passed, $failures failed"
[ $failures -eq 0 ]
