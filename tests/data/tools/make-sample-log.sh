#!/usr/bin/env bash
# Regenerates samples-all-types.lcmlog (used by ToolsBus.CommittedLogReplaysAndDecodes) with the project's
# own tools: tools/record records 3 rounds of hg-lcm-send samples of every message type, in a private
# network namespace. Run after a change to lcmtypes/ (HG_BUILD_DIR: build directory, default build/).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/../../.." && pwd)"
source "$repo/tools/version.sh"
hg_answer make-sample-log.sh "$0" "$@"
if [[ "${HG_IN_NETNS:-}" != "1" ]]; then exec "$repo/tests/netns.sh" "$0" "$@"; fi
bin="${HG_BUILD_DIR:-$repo/build}/bin"
out="$here/samples-all-types.lcmlog"
rm -f "$out"
"$repo/tools/record" --channels 'HG_.*' "$out" >"$out.name" &
rec=$!
while [[ ! -s "$out.name" ]]; do kill -0 $rec || exit 1; sleep 0.05; done
"$bin/hg-lcm-send" sample --type all --count 3 --rate 20
sleep 1  # lcm-logger writes what it received (flush interval 100 ms)
kill -TERM $rec
wait $rec
rm -f "$out.name"
ls -l "$out"
