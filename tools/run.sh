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
# Every run has its own HG_RUN_ID: the simulated robot of a run that was stopped mid-job reports that job
# ABORTED (interrupted) and starts clean; a real robot (--driver ur) keeps its FAULT until RESET.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/version.sh"
hg_answer_version run "$@"
cd "$(dirname "$0")/.."
ROOT=$PWD
BIN=${BIN:-$ROOT/build/bin}
OUT=${OUT:-$ROOT/out}
PIPELINE=$ROOT/config/pipeline.toml
JOB_ID=demo-$(date +%Y%m%d-%H%M%S)
TIMEOUT=120
EXTRA=()

usage() {
  cat <<USAGE
usage: tools/run.sh [options]
Runs the whole hullgrind pipeline once, in its own network namespace, and writes $OUT/.

  --pipeline FILE    pipeline file for tools/supervisor [config/pipeline.toml]
  --camera KIND      openni2: the virtual OpenNI2 device (config/pipeline.toml); genicam: a fake GigE
                     Vision 3-D camera on loopback read through Aravis (config/pipeline-genicam.toml)
  --job-id ID        job id of the request [demo-DATE]
  --timeout S        give up waiting for the job after S seconds [120]
  --station          the simulated cell with the operator station until Ctrl-C, reachable at
                     http://127.0.0.1:8080 (tools/station.sh; docs/station.md)
  --offline          no processes: hg-outline on the bundled sample cloud (data/samples/), checked
                     against its ground truth (out/outline.json, outline.png)
  -h, --help         this text
Other inputs: edit the camera process in the pipeline file: --source openni2 with --uri of a real
device or an .oni file, --source files --files DIR, and the robot with --driver ur (docs/RUNNING.md).
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

while [[ $# -gt 0 ]]; do
  case "$1" in
    --pipeline) PIPELINE=$(realpath "$2"); shift 2 ;;
    --camera)
      case "$2" in
        openni2) PIPELINE=$ROOT/config/pipeline.toml ;;
        genicam) PIPELINE=$ROOT/config/pipeline-genicam.toml ;;
        *) echo "run.sh: --camera must be openni2 or genicam, not '$2'" >&2; exit 2 ;;
      esac
      shift 2 ;;
    --job-id) JOB_ID=$2; shift 2 ;;
    --timeout) TIMEOUT=$2; shift 2 ;;
    --offline) offline; exit $? ;;
    --station) shift; exec "$ROOT/tools/station.sh" "$@" ;;
    -h|--help) usage; exit 0 ;;
    *) echo "run.sh: unknown option $1" >&2; usage >&2; exit 2 ;;
  esac
done

# This run, for the simulated robot's state file (robot_bridge: a state file of another run is stale).
export HG_RUN_ID=${HG_RUN_ID:-run-$(date -u +%Y%m%dT%H%M%S)-$$}

# Everything below runs in a private network namespace: LCM and DDS stay on this machine by construction.
if [[ "${HG_IN_NETNS:-}" != "1" ]]; then
  exec "$ROOT/tests/netns.sh" "$0" --pipeline "$PIPELINE" --job-id "$JOB_ID" --timeout "$TIMEOUT"
fi

rm -rf "$OUT/logs" "$OUT/supervisor" "$OUT/run.lcmlog" "$OUT/outline.json" "$OUT/path.json" "$OUT/overview.png" "$OUT/summary.json"
mkdir -p "$OUT"
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill -TERM "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
}
trap cleanup EXIT
t0=$(date +%s.%N)
stamp() { printf '[%6.1f s] %s\n' "$(awk -v a="$(date +%s.%N)" -v b="$t0" 'BEGIN { print a - b }')" "$*"; }

stamp "recording the bus to $OUT/run.lcmlog"
"$ROOT/tools/record" "$OUT/run.lcmlog" >"$OUT/record.name" &
pids+=("$!")
for _ in $(seq 1 200); do [[ -s "$OUT/record.name" ]] && break; sleep 0.1; done
[[ -s "$OUT/record.name" ]] || { echo "run.sh: tools/record did not start" >&2; exit 1; }
rm -f "$OUT/record.name"

if [[ ! -f "$OUT/dds-security/governance.p7s" ]]; then
  stamp "making a test DDS Security set in $OUT/dds-security (tools/make-dds-security.sh)"
  "$ROOT/tools/make-dds-security.sh" "$OUT/dds-security" >/dev/null
fi
stamp "starting the pipeline ($PIPELINE) under tools/supervisor"
"$ROOT/tools/supervisor" run "$PIPELINE" >"$OUT/supervisor.out" 2>"$OUT/supervisor.log" &
sup=$!
pids=("$sup" "${pids[@]}")  # stop the supervisor first, the recorder last
ready=0
for _ in $(seq 1 120); do
  sleep 0.5
  kill -0 "$sup" 2>/dev/null || { cat "$OUT/supervisor.log" >&2; echo "run.sh: the supervisor stopped" >&2; exit 1; }
  if "$ROOT/tools/supervisor" status-json --run-dir "$OUT/supervisor" 2>/dev/null |
     python3 -c 'import json,sys; st=json.load(sys.stdin)["processes"]; sys.exit(0 if st and all(p["state"]=="running" for p in st) else 1)' 2>/dev/null; then
    ready=1; break
  fi
done
[[ $ready == 1 ]] || { "$ROOT/tools/supervisor" status --run-dir "$OUT/supervisor" >&2 || true; echo "run.sh: the pipeline did not come up" >&2; exit 1; }
"$ROOT/tools/supervisor" status --run-dir "$OUT/supervisor"

# Watch the job's statuses, then ask for the job.
"$BIN/hg-lcm-dump" --channels '^HG_JOB_STATUS$' --type job_status_t >"$OUT/job_status.jsonl" 2>"$OUT/job_status.err" &
pids+=("$!")
for _ in $(seq 1 100); do grep -q listening "$OUT/job_status.err" 2>/dev/null && break; sleep 0.1; done
stamp "job request $JOB_ID"
"$BIN/hg-lcm-send" job --job-id "$JOB_ID" --part-id demo-plate >/dev/null
# Follows the statuses until the job ends: DONE from the robot, or FAILED/ABORTED/REFUSED from anyone.
python3 - "$OUT/job_status.jsonl" "$JOB_ID" "$TIMEOUT" "$t0" <<'PY' || true
import json, sys, time
path, job, timeout, t0 = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
names = ["ACCEPTED", "PLANNING", "PLANNED", "RUNNING", "DONE", "FAILED", "ABORTED", "REFUSED"]
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
        state = names[m["state"]] if 0 <= m["state"] < 8 else str(m["state"])
        text = "%s %s %3.0f%% %s" % (m["source"], state, 100 * m["progress"], m["message"])
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
        if (state == "DONE" and m["source"] == "hg-robot-bridge") or state in ("FAILED", "ABORTED", "REFUSED"):
            sys.exit(0)
    sys.stdout.flush()
    time.sleep(0.1)
print("\nno final state within %.0f s" % timeout)
sys.exit(1)
PY

stamp "stopping the pipeline"
kill -TERM "$sup"; wait "$sup" || true
"$ROOT/tools/supervisor" status --run-dir "$OUT/supervisor" 2>/dev/null || true
cleanup
trap - EXIT
cp "$OUT/supervisor.out" "$OUT/logs/status.txt" 2>/dev/null || true

echo "== results"
rc=0
# The picture needs the calibration the planner ran with: its command line from the pipeline file.
mapfile -t planner_args < <(python3 - "$PIPELINE" <<'PY'
import os, sys, tomllib
path = sys.argv[1]
with open(path, "rb") as f:
    pipeline = tomllib.load(f)
for p in pipeline.get("process", []):
    cmd = p["command"]
    if os.path.basename(cmd[0]) == "hg-path-planner":
        cwd = p.get("cwd", os.path.dirname(path))  # the supervisor runs a process there
        for i, a in enumerate(cmd[1:]):
            print(os.path.join(cwd, a) if i > 0 and cmd[i] in ("--config", "--cell") else a)
        break
PY
)
"$BIN/hg-overview" "$OUT/run.lcmlog" --out "$OUT" --job-id "$JOB_ID" --planner-config "$ROOT/config/path_planner.yaml" \
  --planner-args "${planner_args[@]}" || rc=$?
echo "bus recorded in $OUT/run.lcmlog; process logs in $OUT/logs/; the job's record: tools/hg-jobs --dir $OUT/jobs show $JOB_ID"
exit $rc
