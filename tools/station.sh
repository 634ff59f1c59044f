#!/usr/bin/env bash
# `make station` / `tools/run.sh --station`: the simulated cell with the operator station, up until Ctrl-C.
#
# Starts the pipeline of config/pipeline.toml (or --pipeline FILE) under tools/supervisor in a network
# namespace of its own, as tools/run.sh does, with hg-station in it, and makes the station reachable from
# this machine's browser at http://127.0.0.1:PORT (default 8080) through a Unix socket (tools/station-forward):
# LCM stays inside the namespace. On the first start it makes the user `operator` (role operator) with a
# generated password, written to OUT/station/first-password (mode 0600) and printed once.
#   tools/station.sh [--out DIR] [--pipeline FILE] [--cell FILE] [--port PORT]
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/version.sh"
hg_answer station.sh "$0" "$@"
CALLER=$PWD  # relative --out, --pipeline and --cell are relative to where it was started
cd "$(dirname "$0")/.."
ROOT=$PWD
BIN=${BIN:-$ROOT/build/bin}
OUT=${OUT:-$ROOT/out}  # ${OUT} of the pipeline file: the station's users, the recorder's jobs, the logs
PIPELINE=$ROOT/config/pipeline.toml
CELL=''
PORT=8080
absolute() { [[ $1 == /* ]] && echo "$1" || echo "$CALLER/$1"; }
while [[ $# -gt 0 ]]; do
  case "$1" in --out | --pipeline | --cell | --port) [[ $# -ge 2 ]] || { echo "station.sh: $1 needs a value" >&2; exit 2; } ;; esac
  case "$1" in
    --out) OUT=$(absolute "$2"); shift 2 ;;
    --pipeline) PIPELINE=$(realpath "$(absolute "$2")"); shift 2 ;;
    --cell) CELL=$(absolute "$2"); shift 2 ;;
    --port) PORT=$2; shift 2 ;;
    *) echo "station.sh: unknown option $1 (--out DIR, --pipeline FILE, --cell FILE, --port PORT)" >&2; exit 2 ;;
  esac
done
[[ $PORT =~ ^[0-9]+$ ]] || { echo "station.sh: --port must be a port number, not '$PORT'" >&2; exit 2; }
[[ -z $CELL || -f $CELL ]] || { echo "station.sh: --cell $CELL: no such file" >&2; exit 2; }
SOCK=$OUT/station/http.sock
mkdir -p "$OUT/station"
chmod 700 "$OUT/station"

if [[ "${HG_IN_NETNS:-}" != "1" ]]; then
  # Outside: the host's end of the forwarder, then the cell in its namespace.
  "$ROOT/tools/station-forward" --listen-tcp "127.0.0.1:$PORT" --to-unix "$SOCK" >"$OUT/station/forward-host.log" 2>&1 &
  fwd=$!
  trap 'kill $fwd 2>/dev/null || true' EXIT
  sleep 0.3
  kill -0 $fwd 2>/dev/null || { cat "$OUT/station/forward-host.log" >&2; echo "station.sh: cannot listen on 127.0.0.1:$PORT" >&2; exit 1; }
  export HG_RUN_ID=${HG_RUN_ID:-run-$(date -u +%Y%m%dT%H%M%S)-$$}
  "$ROOT/tests/netns.sh" "$0" --out "$OUT" --pipeline "$PIPELINE" ${CELL:+--cell "$CELL"} --port "$PORT" || true
  exit 0
fi

if [[ ! -s "$OUT/station/users" ]]; then
  pw=$("$BIN/hg-station-user" add operator --role operator --file "$OUT/station/users" | sed -n 's/^password: //p')
  [[ -n "$pw" ]] || { echo "station.sh: hg-station-user add operator failed" >&2; exit 1; }
  (umask 077; printf '%s\n' "$pw" >"$OUT/station/first-password")
  FIRST="user operator, password $pw (also in $OUT/station/first-password; shown only this once)"
else
  FIRST="users in $OUT/station/users (tools/hg-station-user); the first password is in $OUT/station/first-password"
fi

pids=()
cleanup() { for p in "${pids[@]}"; do kill -TERM "$p" 2>/dev/null || true; done; wait 2>/dev/null || true; }
trap cleanup EXIT
rm -rf "$OUT/logs" "$OUT/supervisor"
if grep -q dds-security "$PIPELINE" && [[ ! -f "$OUT/dds-security/governance.p7s" ]]; then
  "$ROOT/tools/make-dds-security.sh" "$OUT/dds-security" >/dev/null
fi
"$ROOT/tools/supervisor" run --out "$OUT" ${CELL:+--set "CELL=$CELL"} "$PIPELINE" >"$OUT/supervisor.out" 2>"$OUT/supervisor.log" &
pids=("$!")
"$ROOT/tools/station-forward" --listen-unix "$SOCK" --to-tcp "127.0.0.1:8080" >"$OUT/station/forward-netns.log" 2>&1 &
pids+=("$!")
for _ in $(seq 1 120); do
  sleep 0.5
  kill -0 "${pids[0]}" 2>/dev/null || { cat "$OUT/supervisor.log" >&2; echo "station.sh: the supervisor stopped" >&2; exit 1; }
  if "$ROOT/tools/supervisor" status-json --run-dir "$OUT/supervisor" 2>/dev/null |
     python3 -c 'import json,sys; st=json.load(sys.stdin)["processes"]; sys.exit(0 if st and all(p["state"]=="running" for p in st) else 1)' 2>/dev/null; then
    break
  fi
done
"$ROOT/tools/supervisor" status --run-dir "$OUT/supervisor" || true
echo
echo "hullgrind station: http://127.0.0.1:$PORT/  ($FIRST)"
echo "The simulated cell runs until Ctrl-C. Logs: $OUT/logs/; history: $OUT/jobs/"
while kill -0 "${pids[0]}" 2>/dev/null; do sleep 1; done
