#!/usr/bin/env bash
# hg-mcap's speed on one core (docs/BENCHMARKS.md, "hg-mcap"): an LCM log of plate clouds of the size the
# speed target names (1.59 M points, 19 MB each) plus the rest of a job's bus (heartbeats, robot statuses
# at 125 Hz), converted with each compression pinned to CPU 0; prints MB/s of LCM log per second of wall time
# and the CPU seconds (user + sys: on a loaded machine the wall time says more about the others).
#   tools/bench/mcap_bench.sh [CLOUDS] [POINTS]   (default 10 clouds of 1590000 points; env HG_BIN_DIR)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
source "$root/tools/version.sh"
hg_answer mcap_bench.sh "$0" "$@"
bin="${HG_BIN_DIR:-$root/build/bin}"
clouds=${1:-10}
points=${2:-1590000}
tmp=$(mktemp -d)
trap '[[ -n "${HG_KEEP:-}" ]] || rm -rf "$tmp"' EXIT
# One sample of each type from hg-lcm-send (the current fingerprints), recorded in a network namespace.
"$root/tests/netns.sh" bash -c "'$root/tools/record' --channels 'HG_.*' '$tmp/samples.lcmlog' >'$tmp/name' & r=\$!;
  while [[ ! -s '$tmp/name' ]]; do sleep 0.05; done; '$bin/hg-lcm-send' sample --type all --count 1 >/dev/null; sleep 0.5; kill \$r; wait \$r" \
  >/dev/null 2>&1
/usr/bin/python3 - "$tmp/samples.lcmlog" "$tmp/bench.lcmlog" "$clouds" "$points" <<'PY'
import math, random, struct, sys
src, out, clouds, points = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
data, pos, events = open(src, "rb").read(), 0, {}
while pos + 28 <= len(data):
    _, _, _, cl, dl = struct.unpack(">IqqII", data[pos:pos + 28])
    events[data[pos + 28:pos + 28 + cl].decode()] = data[pos + 28 + cl:pos + 28 + cl + dl]
    pos += 28 + cl + dl
fp = events["HG_PLATE_CLOUD"][:8]
def s(t): return struct.pack(">i", len(t) + 1) + t.encode() + b"\0"
def cloud(seq, utime):
    side = int(math.sqrt(points))
    u = [((i % side) - side / 2) * 0.0008 for i in range(points)]
    v = [((i // side) - side / 2) * 0.0008 + random.uniform(-1e-4, 1e-4) for i in range(points)]
    b = fp + struct.pack(">qq", seq, utime) + s("camera") + struct.pack(">qb", seq, 0) + s("")
    b += struct.pack(">12d", 0.5, 0, 1.5, 0, 0, -1, 1, 0, 0, 0, -1, 0) + struct.pack(">d", 0.01)
    b += struct.pack(">i", points) + struct.pack(">%df" % points, *u) + struct.pack(">%df" % points, *v)
    b += struct.pack(">%dh" % points, *([0] * points)) + struct.pack(">h?7d", 1, False, 0, 0, 0, 1, 0, 0, 0)
    b += struct.pack(">id?dd", 0, 0, False, 0, 0)  # dropout_filled(_area), edge_assessed, edge dropout, gap
    return b
n, t = 0, 1_700_000_000_000_000
with open(out, "wb") as f:
    def ev(ch, payload):
        global n
        c = ch.encode()
        f.write(struct.pack(">Iqqii", 0xEDA1DA01, n, t, len(c), len(payload)) + c + payload)
        n += 1
    for k in range(clouds):
        ev("HG_PLATE_CLOUD", cloud(k, t))
        for i in range(25):  # 0.2 s of a 5 fps camera: 125 Hz robot status, the heartbeats
            t += 8000
            ev("HG_ROBOT_STATUS", events["HG_ROBOT_STATUS"])
            if i % 5 == 0:
                ev("HG_HEARTBEAT", events["HG_HEARTBEAT"])
PY
size=$(stat -c %s "$tmp/bench.lcmlog")
[[ -z "${HG_KEEP:-}" ]] || echo "kept: $tmp/bench.lcmlog"
echo "log: $clouds plate clouds of $points points + statuses and heartbeats, $(( size / 1000000 )) MB"
printf '%-12s %-14s %10s %10s %10s %14s\n' compression max-points "MB in" "MB out" "MB/s" "user+sys s"
for mp in 200000 0; do
  for c in zstd lz4 none; do
    t0=$(date +%s.%N)
    /usr/bin/time -f "%U %S" -o "$tmp/cpu" taskset -c 0 "$bin/hg-mcap" "$tmp/bench.lcmlog" -o "$tmp/out.mcap" \
      --compression $c --max-points $mp 2>"$tmp/err"
    t1=$(date +%s.%N)
    # A cloud this script wrote in an older layout of plate_cloud_t would be skipped, not converted.
    if grep -q "did not decode" "$tmp/err"; then cat "$tmp/err" >&2; exit 1; fi
    read -r user sys <"$tmp/cpu"
    awk -v a="$t0" -v b="$t1" -v s="$size" -v o="$(stat -c %s "$tmp/out.mcap")" -v c=$c -v m=$mp -v u="$user" -v y="$sys" \
      'BEGIN { printf "%-12s %-14s %10.0f %10.0f %10.1f %9.2f+%.2f\n", c, m, s / 1e6, o / 1e6, s / 1e6 / (b - a), u, y }'
  done
done
