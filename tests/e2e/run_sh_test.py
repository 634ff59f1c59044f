"""tools/run.sh and its output folder (issue 22, section 3), against the real pipeline of this build:

- a bad pipeline or cell file is refused with exit 2 and one line naming the file and key, and the output
  folder's last results are left exactly as they were;
- OUT (and --out) is where everything goes: two runs with two output folders, side by side (each run.sh
  makes its network namespace of its own, so they share no bus either), both end DONE, each with its own
  job record, robot state, DDS security set, logs and results;
- SIGKILL of run.sh at a random moment of a job, several seeds: no process of the run is left 5 s later
  (the run's processes are found independently of run.sh: every process in its network namespace).

Needs the pipeline's executables built (tests/e2e/CMakeLists.txt)."""

import json
import os
import random
import shutil
import signal
import subprocess
import tempfile
import time
import unittest

SRC = os.environ.get("HG_SOURCE_DIR", os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..")))
BIN = os.environ.get("HG_BIN_DIR", os.path.join(SRC, "build", "bin"))
RUN = os.path.join(SRC, "tools", "run.sh")
RESULTS = ("outline.json", "path.json", "summary.json", "overview.png", "run.lcmlog")


def run_env(out=None):
    """run.sh's environment: its own network namespace (not the test's), this build's binaries."""
    env = {k: v for k, v in os.environ.items() if k not in ("HG_IN_NETNS", "OUT", "HG_RUN_ID")}
    env["BIN"] = BIN
    if out:
        env["OUT"] = out
    return env


def snapshot(folder):
    snap = {}
    for d, _, names in os.walk(folder):
        for n in names:
            p = os.path.join(d, n)
            with open(p, "rb") as f:
                snap[os.path.relpath(p, folder)] = f.read()
    return snap


def netns_of(pid):
    try:
        return os.readlink("/proc/%d/ns/net" % pid)
    except OSError:
        return None


def processes_in(netns):
    """Every live process in network namespace `netns` (zombies are gone already, only not reaped)."""
    found = []
    for name in os.listdir("/proc"):
        if not name.isdigit() or netns_of(int(name)) != netns:
            continue
        try:
            with open("/proc/%s/stat" % name) as f:
                if f.read().split(")")[-1].split()[0] == "Z":
                    continue
            with open("/proc/%s/cmdline" % name, "rb") as f:
                found.append((int(name), f.read().replace(b"\0", b" ").decode(errors="replace").strip()))
        except OSError:
            pass
    return found


class Case(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="hg-runsh-")

    def tearDown(self):
        shutil.rmtree(self.dir, ignore_errors=True)


class RunShRefusesBadFiles(Case):
    def last_results(self, out):
        os.makedirs(out)
        for name in RESULTS:
            with open(os.path.join(out, name), "wb") as f:
                f.write(b"the last run's " + name.encode())
        return snapshot(out)

    def refused(self, args, expected):
        out = os.path.join(self.dir, "out-%d" % len(os.listdir(self.dir)))
        before = self.last_results(out)
        r = subprocess.run([RUN, "--out", out, "--timeout", "5"] + args, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                           text=True, timeout=120, env=run_env(), stdin=subprocess.DEVNULL)
        self.assertEqual(r.returncode, 2, r.stdout + r.stderr)
        self.assertEqual(len(r.stderr.splitlines()), 1, r.stderr)
        for text in expected:
            self.assertIn(text, r.stderr)
        self.assertEqual(snapshot(out), before, "the output folder was touched")

    def test_bad_pipeline_files(self):
        typo = os.path.join(self.dir, "typo.toml")
        with open(os.path.join(SRC, "config", "pipeline.toml")) as f:
            text = f.read()
        with open(typo, "w") as f:
            f.write(text.replace("heartbeat_timeout = 5\n", "heartbeat_timout = 5\n", 1))
        self.refused(["--pipeline", typo], [typo, "unknown key 'heartbeat_timout'", "nearest known: 'heartbeat_timeout'"])
        self.refused(["--pipeline", os.path.join(self.dir, "missing.toml")], ["missing.toml"])
        unset = os.path.join(self.dir, "unset.toml")
        with open(unset, "w") as f:
            f.write(text.replace("${OUT}/jobs", "${JOBS}/jobs"))
        self.refused(["--pipeline", unset], [unset, "${JOBS} is not set"])

    def test_bad_cell_files(self):
        with open(os.path.join(SRC, "config", "cell-sim.yaml")) as f:
            text = f.read()
        bad = os.path.join(self.dir, "bad-cell.yaml")
        with open(bad, "w") as f:
            f.write(text.replace("  radius:", "  radius: -1\n  old-radius:", 1))
        self.refused(["--cell", bad], ["bad-cell.yaml"])
        self.refused(["--cell", os.path.join(self.dir, "no-cell.yaml")], ["no-cell.yaml", "cannot open"])

    def test_bad_command_line(self):
        self.refused(["--no-such-option"], ["unknown option --no-such-option"])
        self.refused(["--camera", "usb"], ["--camera must be openni2 or genicam"])
        self.refused(["--timeout", "soon"], ["--timeout must be a whole number"])


class RunShOutputFolders(Case):
    def test_two_output_folders_side_by_side(self):
        outs = [os.path.join(self.dir, "cell-%d" % i) for i in (1, 2)]
        runs = []
        for i, out in enumerate(outs):
            log = open(os.path.join(self.dir, "run-%d.log" % i), "w")
            # One through $OUT, one through --out.
            args = [RUN, "--job-id", "side-%d" % i, "--timeout", "240"] + (["--out", out] if i else [])
            runs.append((subprocess.Popen(args, stdout=log, stderr=subprocess.STDOUT, env=run_env(None if i else out),
                                          stdin=subprocess.DEVNULL), log))
        for (p, log), out in zip(runs, outs):
            p.wait(timeout=600)
            log.close()
            with open(log.name) as f:
                text = f.read()
            self.assertEqual(p.returncode, 0, text[-3000:])
        for i, out in enumerate(outs):
            with self.subTest(out=out):
                with open(os.path.join(out, "summary.json")) as f:
                    self.assertEqual(json.load(f)["final_state"], "DONE")
                self.assertEqual(os.listdir(os.path.join(out, "jobs")), ["side-%d" % i])  # only its own job
                for name in ("dds-security/governance.p7s", "logs/planner.log", "logs/robot.log", "run.lcmlog",
                             "overview.png", "supervisor.lock", "pipeline.json"):
                    self.assertTrue(os.path.exists(os.path.join(out, name)), name)
                # Every file a process of the run was given lies in the tree (programs, configs) or in its own
                # output folder: none in the tree's out/, none in the other run's folder.
                with open(os.path.join(out, "pipeline.json")) as f:
                    pipeline = json.load(f)
                paths = [a for p in pipeline["process"] for a in p["command"] if a.startswith("/")]
                paths += [pipeline["supervisor"]["run_dir"], pipeline["supervisor"]["log_dir"]]
                self.assertIn(os.path.join(out, "robot.state"), paths)
                self.assertIn(os.path.join(out, "jobs"), paths)
                for path in paths:
                    inside = path.startswith(out + "/") or (path.startswith(SRC + "/") and
                                                            not path.startswith(os.path.join(SRC, "out") + "/"))
                    self.assertTrue(inside, path)

    def test_sigkill_of_run_sh_leaves_no_process(self):
        for seed in range(3):
            with self.subTest(seed=seed):
                rng = random.Random(seed)
                out = os.path.join(self.dir, "kill-%d" % seed)
                log = open(os.path.join(self.dir, "kill-%d.log" % seed), "w")
                p = subprocess.Popen([RUN, "--out", out, "--job-id", "kill-%d" % seed, "--timeout", "240"], stdout=log,
                                     stderr=subprocess.STDOUT, env=run_env(), stdin=subprocess.DEVNULL)
                mine = netns_of(os.getpid())
                deadline = time.monotonic() + 60
                while netns_of(p.pid) in (None, mine) and time.monotonic() < deadline:
                    time.sleep(0.01)  # until run.sh is in its own namespace
                netns = netns_of(p.pid)
                self.assertNotEqual(netns, mine)
                # A random moment between "the pipeline is starting" and "the job runs".
                deadline = time.monotonic() + 120
                started = []
                while time.monotonic() < deadline:  # until the supervisor runs its children
                    started = processes_in(netns)
                    if len(started) > 3 and any("supervisor" in cmd for _, cmd in started):
                        break
                    time.sleep(0.05)
                self.assertGreater(len(started), 3, started)
                time.sleep(rng.uniform(0.0, 8.0))  # the job takes ~10 s: run.sh is still running (checked below)
                self.assertIsNone(p.poll(), "run.sh ended before it was killed; see kill-%d.log" % seed)
                p.send_signal(signal.SIGKILL)
                p.wait()
                log.close()
                deadline = time.monotonic() + 5
                while processes_in(netns) and time.monotonic() < deadline:
                    time.sleep(0.05)
                self.assertEqual(processes_in(netns), [], "left 5 s after SIGKILL of run.sh (started: %s)" % started)


if __name__ == "__main__":
    unittest.main()
