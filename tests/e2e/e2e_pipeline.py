"""The whole hullgrind pipeline, as `make run` starts it, driven from a test: the shipped
config/pipeline.toml rewritten to private paths (run/log directories, robot state file, DDS Security set
in a temporary directory; binaries of the build under test), started under tools/supervisor, the bus
recorded, jobs sent with hg-lcm-send and their statuses followed with hg-lcm-dump.

Every wait here has a deadline: a test that cannot get what it waits for fails with what it saw, it never
hangs. Runs inside a network namespace of its own (tests/netns.sh; CTest does that)."""

import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import tomllib

SRC = os.environ.get("HG_SOURCE_DIR", os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..")))
BIN = os.environ.get("HG_BIN_DIR", os.path.join(SRC, "build", "bin"))
BUILD = os.path.dirname(BIN)
CONFIG = os.path.join(SRC, "config")
PIPELINE = os.path.join(CONFIG, "pipeline.toml")
SUPERVISOR = os.path.join(SRC, "tools", "supervisor")
RECORD = os.path.join(SRC, "tools", "record")
STATES = ["ACCEPTED", "PLANNING", "PLANNED", "RUNNING", "DONE", "FAILED", "ABORTED", "REFUSED",
          "AWAITING_APPROVAL", "APPROVED", "INCOMPLETE", "REJECTED", "NEEDS_RESCAN"]
FINAL = ("DONE", "FAILED", "ABORTED", "REFUSED", "INCOMPLETE", "REJECTED", "NEEDS_RESCAN")
ROBOT = "hg-robot-bridge"


def bin_path(name):
    return os.path.join(BIN, name)


def run(cmd, timeout, **kw):
    """subprocess.run with a deadline; output captured as text."""
    return subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=timeout, **kw)


def toml_value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float, str)):
        return json.dumps(v)
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join("%s = %s" % (k, toml_value(x)) for k, x in v.items()) + " }"
    raise TypeError(v)


def write_toml(path, sup, procs):
    lines = ["[supervisor]"] + ["%s = %s" % (k, toml_value(v)) for k, v in sup.items()]
    for p in procs:
        lines.append("\n[[process]]")
        lines += ["%s = %s" % (k, toml_value(v)) for k, v in p.items()]
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def shipped_pipeline(path=PIPELINE):
    with open(path, "rb") as f:
        return tomllib.load(f)


def scene_truth(scene, profile, path):
    """The ground truth of a rendered scene (part polygons, camera pose, profile) through the camera bridge's
    own --synthetic.write-truth. The bridge keeps running afterwards: it is stopped once the file is there."""
    with open(path + ".log", "w") as log:
        p = subprocess.Popen([bin_path("hg-camera-bridge"), "--source", "synthetic", "--synthetic.scene", scene, "--synthetic.profile",
                              profile, "--trigger", "job", "--synthetic.write-truth", path], stdout=log, stderr=subprocess.STDOUT)
    try:
        end = time.monotonic() + 60
        while time.monotonic() < end and not (os.path.exists(path) and os.path.getsize(path) > 0):
            if p.poll() is not None:
                raise RuntimeError("hg-camera-bridge --synthetic.write-truth exited: " + Pipeline.read(path + ".log"))
            time.sleep(0.05)
    finally:
        p.terminate()
        try:
            p.wait(10)
        except subprocess.TimeoutExpired:
            p.kill()
            p.wait()
    with open(path) as f:
        return json.load(f)


def with_defaults(arg):
    """A pipeline file's argument with every ${NAME:-DEFAULT} placeholder at its default (${CELL:-cell-sim.yaml})."""
    return re.sub(r"\$\{[A-Za-z_][A-Za-z0-9_]*:-([^}]*)\}", r"\1", arg)


def process_command(name):
    """The command of one process in the shipped pipeline file, as written there (placeholders at their defaults)."""
    for p in shipped_pipeline()["process"]:
        if p["name"] == name:
            return [with_defaults(a) for a in p["command"]]
    raise KeyError(name)


class Pipeline:
    """One run of the shipped pipeline in a temporary directory.

    lcm_url: passed to every process (the supervisor's lcm_url) and to the test's own tools.
    without: names of processes to leave out (the second-host test runs the camera elsewhere).
    extra_args: {process name: [args appended to its command]}.
    netns_exec: a prefix (e.g. nsenter ...) under which everything of this pipeline is started.
    pipeline_file: the shipped pipeline file to run (config/pipeline.toml; config/pipeline-genicam.toml).
    variables: {NAME: VALUE} for the file's ${NAME:-DEFAULT} placeholders, given to the supervisor as
        --set NAME=VALUE (as tools/run.sh --cell FILE does with CELL); the others take their defaults."""

    def __init__(self, name, lcm_url=None, without=(), extra_args=None, netns_exec=(), keep=None, pipeline_file=PIPELINE,
                 variables=None):
        self.pipeline_file = pipeline_file
        self.variables = dict(variables or {})
        self.dir = tempfile.mkdtemp(prefix="hg-e2e-%s-" % name)
        self.lcm_url = lcm_url
        self.prefix = list(netns_exec)
        self.files = []
        self.procs = []  # our helper processes (recorder, status dump), stopped in reverse order
        self.supervisor = None
        self.status_file = os.path.join(self.dir, "job_status.jsonl")
        self._statuses = {"file": None, "offset": 0, "all": []}  # what statuses() has read of it
        self.log = os.path.join(self.dir, "run.lcmlog")
        self.keep = keep if keep is not None else os.environ.get("HG_E2E_KEEP") == "1"
        self.toml = os.path.join(self.dir, "pipeline.toml")
        self._write_pipeline(without, extra_args or {})

    # ---- pipeline file ----
    def _rewrite_arg(self, arg):
        """Paths of the shipped file are relative to config/: ../build/ is the build under test, ${OUT} (the
        supervisor's output folder) this run's directory, other existing files are config/ files; a
        placeholder with a default (${CELL:-cell-sim.yaml}) takes its default unless it is one of `variables`
        (then it stays for the supervisor's --set)."""
        if any(re.search(r"\$\{%s(:-[^}]*)?\}" % re.escape(n), arg) for n in self.variables):
            return arg
        arg = with_defaults(arg)
        if arg.startswith("${OUT}/"):
            return os.path.join(self.dir, arg[len("${OUT}/"):])
        if arg.startswith("../build/"):
            return os.path.join(BUILD, arg[len("../build/"):])
        if arg.startswith("../out/"):
            return os.path.join(self.dir, arg[len("../out/"):])
        if not arg.startswith("-") and "/" not in arg and os.path.isfile(os.path.join(CONFIG, arg)):
            return os.path.join(CONFIG, arg)
        return arg

    def _write_pipeline(self, without, extra_args):
        shipped = shipped_pipeline(self.pipeline_file)
        sup = dict(shipped.get("supervisor", {}))
        sup["run_dir"] = os.path.join(self.dir, "supervisor")
        sup["log_dir"] = os.path.join(self.dir, "logs")
        sup["bin_dir"] = BIN
        if self.lcm_url:
            sup["lcm_url"] = self.lcm_url
        procs = []
        for p in shipped["process"]:
            if p["name"] in without:
                continue
            p = dict(p)
            p["command"] = [self._rewrite_arg(a) for a in p["command"]]
            if p["name"] == "robot":
                # A private state file: the shipped one is in /tmp, shared by every run on this machine.
                p["command"] += ["--state-file", os.path.join(self.dir, "robot.state")]
            p["command"] += extra_args.get(p["name"], [])
            p["cwd"] = self.dir
            procs.append(p)
            if p["name"] == "planner":
                self.planner_command = list(p["command"])  # for hg-overview: the calibration this run uses
        self.names = [p["name"] for p in procs]
        if any("dds-security" in a for p in procs for a in p["command"]):
            out = run([os.path.join(SRC, "tools", "make-dds-security.sh"), os.path.join(self.dir, "dds-security")],
                      timeout=120)
            if out.returncode != 0:
                raise RuntimeError("make-dds-security.sh failed: " + out.stderr)
        write_toml(self.toml, sup, procs)

    def lcm_args(self):
        return ["--lcm-url", self.lcm_url] if self.lcm_url else []

    # ---- life cycle ----
    def _file(self, name):
        """An output file of this run, closed by cleanup()."""
        f = open(os.path.join(self.dir, name), "w")
        self.files.append(f)
        return f

    @staticmethod
    def read(path):
        with open(path, errors="replace") as f:
            return f.read()

    def _spawn(self, cmd, **kw):
        p = subprocess.Popen(self.prefix + cmd, start_new_session=True, **kw)
        self.procs.append(p)
        return p

    def start(self, up_timeout=120):
        """Recorder, supervisor with every process running, job status dump. Raises on a deadline."""
        rec_out = self._file("record.out")
        self.recorder = self._spawn([RECORD] + self.lcm_args() + [self.log], stdout=rec_out,
                                    stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL)
        self.wait(lambda: os.path.getsize(rec_out.name) > 0 or self.recorder.poll() is not None, 30, "the recorder")
        if self.recorder.poll() is not None:
            raise RuntimeError("tools/record stopped: " + self.read(rec_out.name))
        self.sup_out = self._file("supervisor.log")
        self.supervisor = subprocess.Popen(self.prefix + [sys.executable, SUPERVISOR, "run"] +
                                           ["--set=%s=%s" % kv for kv in self.variables.items()] + [self.toml],
                                           stdout=self.sup_out, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                                           start_new_session=True)
        self.wait_all_running(up_timeout)
        err = self._file("job_status.err")
        self.dump = self._spawn([bin_path("hg-lcm-dump")] + self.lcm_args() +
                                ["--channels", "^HG_JOB_STATUS$", "--type", "job_status_t"],
                                stdout=self._file("job_status.jsonl"), stderr=err, stdin=subprocess.DEVNULL)
        self.wait(lambda: "listening" in self.read(err.name), 30, "hg-lcm-dump listening")

    def status(self):
        try:
            out = run(self.prefix + [sys.executable, SUPERVISOR, "status-json", "--run-dir",
                                     os.path.join(self.dir, "supervisor")], timeout=10)
        except subprocess.TimeoutExpired:
            return None
        if out.returncode != 0:
            return None
        try:
            return {r["name"]: r for r in json.loads(out.stdout)["processes"]}
        except ValueError:
            return None

    def wait_all_running(self, timeout):
        def up():
            if self.supervisor.poll() is not None:
                raise RuntimeError("the supervisor stopped:\n" + self.tail("supervisor.log"))
            st = self.status()
            return st is not None and len(st) == len(self.names) and all(r["state"] == "running" for r in st.values())
        self.wait(up, timeout, "every process running under the supervisor")

    def wait(self, pred, timeout, what, period=0.1):
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            if pred():
                return
            time.sleep(period)
        raise TimeoutError("timed out after %.0f s waiting for %s\n%s" % (timeout, what, self.diagnostics()))

    def stop(self):
        """Supervisor first (processes in reverse order), then our helpers; the recorder last."""
        if self.supervisor is not None and self.supervisor.poll() is None:
            self.supervisor.send_signal(signal.SIGTERM)
            try:
                self.supervisor.wait(30)
            except subprocess.TimeoutExpired:
                os.killpg(self.supervisor.pid, signal.SIGKILL)
                self.supervisor.wait()
        for p in reversed(self.procs):
            if p.poll() is None:
                p.send_signal(signal.SIGINT)
                try:
                    p.wait(10)
                except subprocess.TimeoutExpired:
                    os.killpg(p.pid, signal.SIGKILL)
                    p.wait()

    def cleanup(self, failed=False):
        self.stop()
        for f in self.files:
            f.close()
        if failed or self.keep:
            sys.stderr.write("e2e: run directory kept: %s\n" % self.dir)
        else:
            shutil.rmtree(self.dir, ignore_errors=True)

    # ---- jobs ----
    def send(self, job_id, action="start", extra=()):
        out = run([*self.prefix, bin_path("hg-lcm-send")] + self.lcm_args() +
                  ["job", "--job-id", job_id, "--part-id", "e2e-plate", "--action", action, *extra], timeout=20)
        if out.returncode != 0:
            raise RuntimeError("hg-lcm-send failed: " + out.stderr)

    def statuses(self, job_id=None):
        """Every status the dump has written so far (of job_id), in order. The file only grows while the dump
        runs: the lines read before are kept, so that polling a long run reads each line once."""
        cache = self._statuses
        if cache["file"] != self.status_file or os.path.getsize(self.status_file) < cache["offset"]:
            cache.update(file=self.status_file, offset=0, all=[])  # another file, or written anew by start()
        with open(self.status_file, "rb") as f:
            f.seek(cache["offset"])
            for line in f:
                if not line.endswith(b"\n"):
                    break
                cache["offset"] += len(line)
                m = json.loads(line).get("msg", {})
                cache["all"].append({"source": m["source"], "state": STATES[m["state"]] if 0 <= m["state"] < len(STATES) else str(m["state"]),
                                     "progress": m["progress"], "message": m["message"], "job_id": m.get("job_id"),
                                     "answer": bool(m.get("answer", False))})
        return [s for s in cache["all"] if job_id is None or s["job_id"] == job_id]

    def wait_status(self, job_id, pred, timeout, what):
        """The first status of job_id for which pred(status) holds."""
        found = []

        def seen():
            for s in self.statuses(job_id):
                if pred(s):
                    found.append(s)
                    return True
            return False
        self.wait(seen, timeout, what)
        return found[0]

    def wait_final(self, job_id, timeout):
        """How the job ended: DONE from the robot bridge, or any other terminal state from anyone."""
        return self.wait_status(job_id, lambda s: (s["state"] == "DONE" and s["source"] == ROBOT) or
                                (s["state"] in FINAL and s["state"] != "DONE"), timeout,
                                "job %s to end (%s)" % (job_id, ", ".join(FINAL)))

    def record(self, job_id):
        """The job history's summary of a job (hg-job-recorder's job.json; ids of these tests need no escaping)."""
        with open(os.path.join(self.dir, "jobs", job_id, "job.json")) as f:
            return json.load(f)

    def wait_record(self, job_id, pred, timeout, what):
        found = []

        def seen():
            try:
                r = self.record(job_id)
            except (OSError, ValueError):
                return False
            if pred(r):
                found.append(r)
                return True
            return False
        self.wait(seen, timeout, what)
        return found[0]

    def overview(self, job_id, out_dir):
        """hg-overview on the recorded log (flushed by lcm-logger every 100 ms)."""
        os.makedirs(out_dir, exist_ok=True)
        planner = getattr(self, "planner_command", [])[1:]
        return run([bin_path("hg-overview"), self.log, "--out", out_dir, "--job-id", job_id,
                    "--planner-config", os.path.join(CONFIG, "path_planner.yaml"), "--planner-args"] + planner,
                   timeout=120)

    # ---- diagnostics ----
    def tail(self, name, lines=25):
        path = os.path.join(self.dir, name)
        try:
            with open(path, errors="replace") as f:
                return "".join(f.readlines()[-lines:])
        except OSError:
            return "(no %s)\n" % name

    def diagnostics(self):
        parts = ["--- supervisor status: %s" % json.dumps(self.status()), "--- supervisor.log\n" + self.tail("supervisor.log")]
        for n in getattr(self, "names", []):
            parts.append("--- logs/%s.log\n%s" % (n, self.tail(os.path.join("logs", n + ".log"), 12)))
        try:
            parts.append("--- job statuses\n" + "\n".join(json.dumps(s) for s in self.statuses()[-15:]))
        except (OSError, ValueError):
            pass
        return "\n".join(parts)
