#!/usr/bin/env bash
# Regenerates the committed LCM logs with the project's own tools, in a private network namespace.
# Run after a change to lcmtypes/ (HG_BUILD_DIR: build directory, default build/):
#   tests/data/tools/samples-all-types.lcmlog   3 rounds of hg-lcm-send samples of every type
#                                                (ToolsBus.CommittedLogReplaysAndDecodes)
#   tests/data/dds_gateway/replay.lcmlog        4 samples of the six types the DDS gateway bridges
#                                                (dds_gateway_bridge_test)
#   tests/data/camera_bridge_three_parts.lcmlog  2 clouds of the synthetic three-parts scene
#                                                (camera_bridge_log_test, replay tests)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/../../.." && pwd)"
source "$repo/tools/version.sh"
hg_answer make-logs.sh "$0" "$@"
if [[ "${HG_IN_NETNS:-}" != "1" ]]; then exec "$repo/tests/netns.sh" --own-pids "$0" "$@"; fi
bin="${HG_BUILD_DIR:-$repo/build}/bin"
data="$repo/tests/data"

# record OUT REGEX CMD...: records the channels matching REGEX while CMD runs.
record() {
  local out="$1" channels="$2"
  shift 2
  rm -f "$out"
  "$repo/tools/record" --channels "$channels" "$out" >"$out.name" &
  local rec=$!
  while [[ ! -s "$out.name" ]]; do kill -0 $rec || exit 1; sleep 0.05; done
  "$@"
  sleep 1  # lcm-logger writes what it received (flush interval 100 ms)
  kill -TERM $rec
  wait $rec
  rm -f "$out.name"
  ls -l "$out"
}

# two_clouds: the camera bridge until it has published two plate clouds.
two_clouds() {
  "$bin/hg-lcm-dump" --channels HG_PLATE_CLOUD --count 2 --timeout 60 >/dev/null &
  local dump=$!
  sleep 0.5
  # One frame a second: the bridge is stopped well before a third cloud.
  "$bin/hg-camera-bridge" --source synthetic --synthetic.scene three-parts --synthetic.profile pm806 --parts all --rate 1 &
  local bridge=$!
  wait $dump
  kill -TERM $bridge
  wait $bridge || true
}

record "$data/tools/samples-all-types.lcmlog" 'HG_.*' "$bin/hg-lcm-send" sample --type all --count 3 --rate 20
record "$data/dds_gateway/replay.lcmlog" 'HG_.*' "$bin/hg-lcm-send" sample \
  --type outline_t,part_pose_t,grind_path_t,job_status_t,robot_status_t,heartbeat_t --count 4 --rate 20
record "$data/camera_bridge_three_parts.lcmlog" 'HG_PLATE_CLOUD' two_clouds
