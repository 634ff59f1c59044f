#!/usr/bin/env bash
# Shows that tools/spy decodes hullgrind types: in a private network namespace, starts Xvfb, publishes
# sample messages of every type in a loop with hg-lcm-send, starts tools/spy, opens the detail view of one
# channel and saves a screenshot (default docs/spy.png).
#   tools/spy-screenshot.sh [OUT.png]   (HG_BUILD_DIR: build directory, default build/)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/version.sh"
hg_answer spy-screenshot "$0" "$@"
repo="$(dirname "$here")"
if [[ "${HG_IN_NETNS:-}" != "1" ]]; then
  exec "$repo/tests/netns.sh" --own-pids "$0" "$@"
fi
out="$(realpath -m "${1:-$repo/docs/spy.png}")"
build="${HG_BUILD_DIR:-$repo/build}"
bin="$build/bin"
for tool in Xvfb java; do command -v $tool >/dev/null || { echo "spy-screenshot: $tool missing" >&2; exit 1; }; done
[[ -x "$bin/hg-lcm-send" ]] || { echo "spy-screenshot: $bin/hg-lcm-send missing (build target hg-lcm-send)" >&2; exit 1; }

tmp="$(mktemp -d)"
pids=()
cleanup() {
  for ((i = ${#pids[@]} - 1; i >= 0; i--)); do kill "${pids[i]}" 2>/dev/null || true; done
  wait 2>/dev/null || true
  rm -rf "$tmp"
}
trap cleanup EXIT

# A display number nobody uses; the namespace keeps the X socket private only for TCP, so check the lock.
disp=99
while [[ -e /tmp/.X$disp-lock ]]; do disp=$((disp + 1)); done
Xvfb ":$disp" -screen 0 1280x800x24 -nolisten tcp >"$tmp/xvfb.log" 2>&1 &
pids+=($!)
for _ in $(seq 1 100); do [[ -S /tmp/.X11-unix/X$disp ]] && break; sleep 0.1; done
[[ -S /tmp/.X11-unix/X$disp ]] || { echo "spy-screenshot: Xvfb did not start" >&2; cat "$tmp/xvfb.log" >&2; exit 1; }
export DISPLAY=":$disp"

"$bin/hg-lcm-send" sample --type all --count 0 --rate 5 2>"$tmp/send.log" &
pids+=($!)
HG_BUILD_DIR="$build" "$here/spy" >"$tmp/spy.log" 2>&1 &
pids+=($!)

# Let spy open and collect a few seconds of rates, grab its table, then open the detail view of one
# channel (rows are sorted by name; HG_HEARTBEAT is the third, at y=59) and put it beside the table.
# Xvfb has no window manager, so both windows sit at 0,0: they are grabbed one after the other.
java "$here/lcm_tools/ScreenShot.java" wait 8000 grab 0 0 800 600 0 0 \
  dblclick 200 59 wait 3000 grab 0 0 650 400 808 0 save "$out"
echo "$out"
