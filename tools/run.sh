#!/usr/bin/env bash
# `make run`: the whole pipeline on a generated part, with no input needed.
#
# In a network namespace of its own (loopback only), starts the pipeline of config/pipeline.toml under
# tools/supervisor (job recorder, camera bridge on the virtual OpenNI2 device — or with --camera genicam on a
# fake GigE Vision 3-D camera, config/pipeline-genicam.toml —, outline service, path planner,
# simulated robot, DDS gateway with DDS Security), records the bus, sends one job request, waits until the job
# ends, and writes out/: outline.json, path.json, overview.png, summary.json, run.lcmlog, the processes' logs,
# and the job's record in out/jobs/ (kept across runs; tools/hg-jobs). Prints the timings of each stage and the
# job's final state; exits non-zero if the job did not end DONE.
#
# The output folder (--out DIR, else $OUT, else out/) is everything a run writes: the pipeline file names it
# ${OUT} and tools/supervisor expands it, so two runs with two output folders share nothing. A bad pipeline
# or cell file is refused (exit 2, one line) before anything in the output folder is touched; a second run on
# an output folder whose supervisor still runs is refused (exit 3) with that supervisor's pid. Every process
# this script starts dies with it, even when it is killed with SIGKILL (setpriv --pdeathsig; the supervisor's
# processes die with the supervisor).
#
# Every run has its own HG_RUN_ID: the simulated robot of a run that was stopped mid-job reports that job
# ABORTED (interrupted) and starts clean; a real robot (--driver ur) keeps its FAULT until RESET.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/version.sh"
hg_answer_version run "$@"
CALLER=$PWD  # relative --out, --pipeline and --cell are relative to where run.sh was started
cd "$(dirname "$0")/.."
ROOT=$PWD
BIN=${BIN:-$ROOT/build/bin}
OUT=${OUT:-$ROOT/out}
PIPELINE=$ROOT/config/pipeline.toml
CELL=''
JOB_ID=demo-$(date +%Y%m%d-%H%M%S)
TIMEOUT=120
EXTRA=()

usage() {
  cat <<USAGE
usage: tools/run.sh [options]
Runs the whole hullgrind pipeline once, in its own network namespace, and writes $OUT/.

  --out DIR          the output folder, \${OUT} of the pipeline file [\$OUT, else out/]
  --pipeline FILE    pipeline file for tools/supervisor [config/pipeline.toml]
  --cell FILE        the cell file of the planner and the robot bridge, \${CELL} of the pipeline file
                     [config/cell-sim.yaml]
  --camera KIND      openni2: the virtual OpenNI2 device (config/pipeline.toml); genicam: a fake GigE
                     Vision 3-D camera on loopback read through Aravis (config/pipeline-genicam.toml)
  --job-id ID        job id of the request [demo-DATE]
  --timeout S        give up waiting for the job after S seconds [120]
  --station          the simulated cell with the operator station until Ctrl-C, reachable at
                     http://127.0.0.1:8080 (tools/station.sh; docs/station.md)
  --offline          no processes: hg-outline on the bundled sample cloud (data/samples/), checked
                     against its ground truth (out/outline.json, outline.png)
  -h, --help         this text
Exit status: 0 the job ended DONE; 1 it did not, or the pipeline failed; 2 a bad command line, pipeline or
cell file (nothing in the output folder touched); 3 another supervisor runs on the output folder.
Other inputs: edit the camera process in the pipeline file: --source openni2 with --openni2.uri of a real
device or an .oni file, --source files --files.path DIR (docs/cameras.md; every option of the camera bridge:
docs/PARAMETERS.md#hg-camera-bridge), and the robot with --driver ur (docs/robot_bridge.md).
USAGE
}

offline() {
  local sample=data/samples/plate-hole-slot-low.xyz
  mkdir -p "$OUT"
  echo "== hullgrind offline: outline of $sample"
  "$BIN/hg-outline" "$sample" -o "$OUT/outline.json" --png "$OUT/outline.png" --svg "$OUT/outline.svg"
  python3 - "$OUT/outline.json" "$sample.truth.json" <<'PY'
import json, sys
out = json.load(open(sys.argv[1]))
truth = json.load(open(sys.argv[2]))
outer = [l for l in out["loops"] if not l["hole"]]
holes = [l for l in out["loops"] if l["hole"]]
want_holes = sum(len(p["holes"]) for p in truth["parts"])
print("points %d, R %.4g, triangles %d, search cost %d, total %.1f ms" %
      (out["points_used"], out["alpha_radius"], out["triangles"], out["search_cost"], out["time_ms"]["total"]))
print("loops: %d outer, %d holes (ground truth: %d parts, %d holes)" % (len(outer), len(holes), len(truth["parts"]), want_holes))
sys.exit(0 if len(outer) == len(truth["parts"]) and len(holes) == want_holes else 1)
PY
}

absolute() { [[ $1 == /* ]] && echo "$1" || echo "$CALLER/$1"; }
need_value() { [[ $# -ge 2 && -n $2 ]] || { echo "run.sh: $1 needs a value (see --help)" >&2; exit 2; }; }
while [[ $# -gt 0 ]]; do
  case "$1" in
    --out) need_value "$@"; OUT=$(absolute "$2"); shift 2 ;;
    --pipeline) need_value "$@"; PIPELINE=$(absolute "$2"); shift 2 ;;
    --cell) need_value "$@"; CELL=$(absolute "$2"); shift 2 ;;
    --camera)
      case "$2" in
        openni2) PIPELINE=$ROOT/config/pipeline.toml ;;
        genicam) PIPELINE=$ROOT/config/pipeline-genicam.toml ;;
        *) echo "run.sh: --camera must be openni2 or genicam, not '$2'" >&2; exit 2 ;;
      esac
      shift 2 ;;
    --job-id) need_value "$@"; JOB_ID=$2; shift 2 ;;
    --timeout) need_value "$@"; TIMEOUT=$2; shift 2 ;;
    --offline) offline; exit $? ;;
    --station) shift; exec "$ROOT/tools/station.sh" --out "$(absolute "$OUT")" --pipeline "$PIPELINE" ${CELL:+--cell "$CELL"} "$@" ;;
    -h|--help) usage; exit 0 ;;
    *) echo "run.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
done

[[ $OUT == /* ]] || OUT=$CALLER/$OUT
[[ $TIMEOUT =~ ^[0-9]+$ ]] || { echo "run.sh: --timeout must be a whole number of seconds, not '$TIMEOUT'" >&2; exit 2; }
# This run, for the simulated robot's state file (robot_bridge: a state file of another run is stale).
export HG_RUN_ID=${HG_RUN_ID:-run-$(date -u +%Y%m%dT%H%M%S)-$$}

# Everything below runs in a private network namespace: LCM and DDS stay on this machine by construction.
if [[ "${HG_IN_NETNS:-}" != "1" ]]; then
  exec "$ROOT/tests/netns.sh" "$0" --out "$OUT" --pipeline "$PIPELINE" ${CELL:+--cell "$CELL"} --job-id "$JOB_ID" \
    --timeout "$TIMEOUT"
fi

# First every check, then the output folder: a bad pipeline or cell file leaves the last run's results alone.
sets=()
[[ -z $CELL ]] || sets=(--set "CELL=$CELL")
checked=$("$ROOT/tools/supervisor" check --out "$OUT" "${sets[@]}" "$PIPELINE" 2>&1) || { echo "run.sh: $checked" >&2; exit 2; }
# The planner's command line (cell and configuration resolved), for the cell check and for hg-overview.
mapfile -t planner_args < <(python3 -c '
import json, os, sys
for p in json.load(sys.stdin)["process"]:
    if os.path.basename(p["command"][0]) == "hg-path-planner":
        cmd = p["command"]
        for i, a in enumerate(cmd[1:]):
            print(os.path.join(p["cwd"], a) if i > 0 and cmd[i] in ("--config", "--cell") else a)
        break' <<<"$checked")
planner_file() {  # the value of the planner's option $1 (--cell, --config), empty without it
  local i
  for ((i = 0; i + 1 < ${#planner_args[@]}; i++)); do [[ ${planner_args[i]} != "$1" ]] || { echo "${planner_args[i + 1]}"; return; }; done
}
if [[ -n $(planner_file --cell) ]]; then
  config=$(planner_file --config)
  cell_check=$("$BIN/hg-plan" --check-config ${config:+--config "$config"} --cell "$(planner_file --cell)" 2>&1) ||
    { echo "run.sh: $cell_check" >&2; exit 2; }
fi
if [[ -e "$OUT/supervisor.lock" ]] && ! flock -n "$OUT/supervisor.lock" true; then
  echo "run.sh: another supervisor (pid $(head -c 20 "$OUT/supervisor.lock" | tr -d '\n')) runs on output folder $OUT" >&2
  exit 3
fi

# The supervisor's socket (in $OUT/supervisor) is its own: it removes a stale one and refuses a live one.
rm -rf "$OUT/logs" "$OUT/run.lcmlog" "$OUT/run.mcap" "$OUT/outline.json" "$OUT/path.json" "$OUT/overview.png" "$OUT/summary.json"
mkdir -p "$OUT"
printf '%s\n' "$checked" >"$OUT/pipeline.json"  # what this run started: every command line, placeholders expanded
# Each child gets a parent-death signal: a run.sh killed even by SIGKILL takes everything it started with it.
# (setpriv execs the command: it keeps the pid that $! names.)
with_pdeathsig=(setpriv --pdeathsig)
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill -TERM "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
}
trap cleanup EXIT
t0=$(date +%s.%N)
stamp() { printf '[%6.1f s] %s\n' "$(awk -v a="$(date +%s.%N)" -v b="$t0" 'BEGIN { print a - b }')" "$*"; }

stamp "recording the bus to $OUT/run.lcmlog"
"${with_pdeathsig[@]}" TERM -- "$ROOT/tools/record" "$OUT/run.lcmlog" >"$OUT/record.name" &
pids+=("$!")
for _ in $(seq 1 200); do [[ -s "$OUT/record.name" ]] && break; sleep 0.1; done
[[ -s "$OUT/record.name" ]] || { echo "run.sh: tools/record did not start" >&2; exit 1; }
rm -f "$OUT/record.name"

if [[ ! -f "$OUT/dds-security/governance.p7s" ]]; then
  stamp "making a test DDS Security set in $OUT/dds-security (tools/make-dds-security.sh)"
  "$ROOT/tools/make-dds-security.sh" "$OUT/dds-security" >/dev/null
fi
stamp "starting the pipeline ($PIPELINE) under tools/supervisor"
"${with_pdeathsig[@]}" TERM -- "$ROOT/tools/supervisor" run --out "$OUT" "${sets[@]}" "$PIPELINE" >"$OUT/supervisor.out" 2>"$OUT/supervisor.log" &
sup=$!
pids=("$sup" "${pids[@]}")  # stop the supervisor first, the recorder last
ready=0
for _ in $(seq 1 120); do
  sleep 0.5
  kill -0 "$sup" 2>/dev/null || { cat "$OUT/supervisor.log" >&2; echo "run.sh: the supervisor stopped" >&2; exit 1; }
  if "$ROOT/tools/supervisor" status-json --out "$OUT" 2>/dev/null |
     python3 -c 'import json,sys; st=json.load(sys.stdin)["processes"]; sys.exit(0 if st and all(p["state"]=="running" for p in st) else 1)' 2>/dev/null; then
    ready=1; break
  fi
done
[[ $ready == 1 ]] || { "$ROOT/tools/supervisor" status --out "$OUT" >&2 || true; echo "run.sh: the pipeline did not come up" >&2; exit 1; }
"$ROOT/tools/supervisor" status --out "$OUT"

# Watch the job's statuses, then ask for the job.
"${with_pdeathsig[@]}" KILL -- "$BIN/hg-lcm-dump" --channels '^HG_JOB_STATUS$' --type job_status_t >"$OUT/job_status.jsonl" 2>"$OUT/job_status.err" &
pids+=("$!")
for _ in $(seq 1 100); do grep -q listening "$OUT/job_status.err" 2>/dev/null && break; sleep 0.1; done
stamp "job request $JOB_ID"
"$BIN/hg-lcm-send" job --job-id "$JOB_ID" --part-id demo-plate >/dev/null
# Follows the statuses until the job ends: DONE from the robot, or any other terminal state (FAILED, ABORTED,
# REFUSED, INCOMPLETE, REJECTED, NEEDS_RESCAN) from anyone; a plan awaiting approval is waited for (the
# operator approves or rejects it: hg-lcm-send approve|reject --job-id ID --by NAME).
"${with_pdeathsig[@]}" KILL -- python3 - "$OUT/job_status.jsonl" "$JOB_ID" "$TIMEOUT" "$t0" <<'PY' || true
import json, sys, time
path, job, timeout, t0 = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
names = ["ACCEPTED", "PLANNING", "PLANNED", "RUNNING", "DONE", "FAILED", "ABORTED", "REFUSED",
         "AWAITING_APPROVAL", "APPROVED", "INCOMPLETE", "REJECTED", "NEEDS_RESCAN"]
terminal = ("FAILED", "ABORTED", "REFUSED", "INCOMPLETE", "REJECTED", "NEEDS_RESCAN")
end = time.time() + timeout
pos, running, last_step = 0, False, -1
while time.time() < end:
    with open(path) as f:
        f.seek(pos)
        lines = f.readlines()
        pos = f.tell()
    for line in lines:
        if not line.endswith("\n"):
            pos -= len(line.encode())
            break
        m = json.loads(line).get("msg", {})
        if m.get("job_id") != job:
            continue
        state = names[m["state"]] if 0 <= m["state"] < len(names) else str(m["state"])
        text = "%s %s%s %3.0f%% %s" % (m["source"], state, " (answer)" if m.get("answer") else "",
                                       100 * m["progress"], m["message"])
        if state == "RUNNING":
            if sys.stdout.isatty():  # one line that updates itself
                sys.stdout.write("\r[%6.1f s] %s" % (time.time() - t0, text[:110].ljust(110)))
                running = True
                continue
            step = int(100 * m["progress"]) // 25
            if step == last_step:  # a log file gets a line per quarter
                continue
            last_step = step
        if running:
            sys.stdout.write("\n")
            running = False
        print("[%6.1f s] %s" % (time.time() - t0, text))
        if state == "AWAITING_APPROVAL" and not m.get("answer"):
            print("           approve: hg-lcm-send approve --job-id %s --by NAME [--exclude-loops N,...]; "
                  "or reject: hg-lcm-send reject --job-id %s --by NAME" % (job, job))
        if (state == "DONE" and m["source"] == "hg-robot-bridge") or state in terminal:
            sys.exit(0)
    sys.stdout.flush()
    time.sleep(0.1)
print("\nno final state within %.0f s" % timeout)
sys.exit(1)
PY

stamp "stopping the pipeline"
kill -TERM "$sup"; wait "$sup" || true
"$ROOT/tools/supervisor" status --out "$OUT" 2>/dev/null || true
cleanup
trap - EXIT
cp "$OUT/supervisor.out" "$OUT/logs/status.txt" 2>/dev/null || true

echo "== results"
rc=0
# The picture needs the calibration the planner ran with: its command line from the pipeline file (above).
"$BIN/hg-overview" "$OUT/run.lcmlog" --out "$OUT" --job-id "$JOB_ID" --planner-config "$ROOT/config/path_planner.yaml" \
  --planner-args "${planner_args[@]}" || rc=$?
# The bus as MCAP for Foxglove / Lichtblick beside run.lcmlog, and the job's slice in its record
# (docs/foxglove.md); the log is closed by now.
mcap() { "$BIN/hg-mcap" "$OUT/run.lcmlog" --cell "$(planner_file --cell)" "$@" 2>&1 | sed 's/^/  /'; return "${PIPESTATUS[0]}"; }
mcap -o "$OUT/run.mcap" || { echo "run.sh: hg-mcap failed: no $OUT/run.mcap" >&2; rc=1; }
if times=$(python3 -c 'import json,sys; j=json.load(open(sys.argv[1])); print(j["created_utime"] - 1000000, j.get("ended_utime", j["updated_utime"]) + 1000000)' \
    "$OUT/jobs/$JOB_ID/job.json" 2>/dev/null); then
  read -r t0_us t1_us <<<"$times"
  mcap -o "$OUT/jobs/$JOB_ID/job.mcap" --start-utime "$t0_us" --end-utime "$t1_us" || rc=1
fi
echo "bus recorded in $OUT/run.lcmlog (MCAP: $OUT/run.mcap); process logs in $OUT/logs/; the job's record: tools/hg-jobs --dir $OUT/jobs show $JOB_ID"
exit $rc
