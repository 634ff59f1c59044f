#!/usr/bin/env bash
# What hg-foxglove's conversion for two viewers costs the outline core, without the pipeline (docs/BENCHMARKS.md,
# "Conversion and viewers at idle priority"). In a network namespace of its own: hg-foxglove and
# hg-bench-station-feed publishing hg-gen's high-4 cloud (1.59 M points, 19 MB) 5 times a second; 0 or 2
# viewers (tools/bench/foxglove_client.js under `chrt --idle 0`, subscribed to everything); meanwhile
# hg-outline (the outline core, 2 threads, normal priority) runs 4 times on the same cloud and its own compute
# time is printed. Rows: conversion idle without viewers, idle with 2, normal with 2; ROUNDS rounds.
# Every process here shares the script's session, so thread priorities act across them; under the
# supervisor each process has a session of its own (docs/RUNNING.md, Priority).
#   tools/bench/foxglove_outline_check.sh [ROUNDS]   (default 2; env HG_BIN_DIR, HG_NPM_DIR)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
source "$root/tools/version.sh"
hg_answer foxglove_outline_check.sh "$0" "$@"
if [[ "${HG_IN_NETNS:-}" != "1" ]]; then exec "$root/tests/netns.sh" --own-pids "$0" "$@"; fi
bin="${HG_BIN_DIR:-$root/build/bin}"
export NODE_PATH="${HG_NPM_DIR:-$root/build/npm}/node_modules"
rounds=${1:-2}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$bin/hg-gen" --preset high-4 --noise 0.0000122 --jagged --seed 7 -o "$tmp/high-4.pcd" >/dev/null
for round in $(seq "$rounds"); do
  for mode in none idle normal; do
    prio=$([[ $mode == normal ]] && echo normal || echo idle)
    "$bin/hg-foxglove" --port 8765 --conversion-priority "$prio" 2>/dev/null & fox=$!
    "$bin/hg-bench-station-feed" --cloud "$tmp/high-4.pcd" --rate 5 >/dev/null 2>&1 & feed=$!
    viewers=()
    if [[ $mode != none ]]; then
      for i in 1 2; do chrt --idle 0 node "$root/tools/bench/foxglove_client.js" >"$tmp/v$i.json" & viewers+=($!); done
    fi
    sleep 3  # viewers connected, a few clouds on the bus
    ms=()
    for k in 1 2 3 4; do
      ms+=("$("$bin/hg-outline" "$tmp/high-4.pcd" -o "$tmp/o.json" 2>&1 | sed -n 's/.*threads, \([0-9.]*\) ms.*/\1/p')")
    done
    for p in "${viewers[@]}"; do kill "$p"; wait "$p" || true; done
    got=0
    [[ ! -s "$tmp/v1.json" ]] || got=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1])).get("HG_PLATE_CLOUD", {}).get("messages", 0))' "$tmp/v1.json")
    kill $feed $fox
    wait $feed $fox || true
    rm -f "$tmp"/v*.json
    echo "round $round, conversion $prio, $([[ $mode == none ]] && echo 0 || echo 2) viewers: hg-outline ms ${ms[*]}; viewer 1 got $got clouds; load $(cut -d' ' -f1 /proc/loadavg)"
  done
done
