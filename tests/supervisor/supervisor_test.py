"""tools/supervisor against real processes: order, restart with back-off, crash loop, reverse stop with
SIGKILL fallback, log rotation, status, heartbeat watch and the single-instance rule.
Runs inside tests/netns.sh (CTest does that)."""

import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import unittest

SRC = os.environ.get("HG_SOURCE_DIR", os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..")))
BIN = os.environ.get("HG_BIN_DIR", os.path.join(SRC, "build", "bin"))
SUPERVISOR = os.path.join(SRC, "tools", "supervisor")


def toml_list(items):
    return "[" + ", ".join(json.dumps(i) for i in items) + "]"


class SupervisorCase(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="hg-sup-")
        self.run_dir = os.path.join(self.dir, "run")
        self.procs = []

    def tearDown(self):
        for p in self.procs:
            if p.poll() is None:
                p.kill()
                p.wait()
        shutil.rmtree(self.dir, ignore_errors=True)

    def pipeline(self, processes, **sup):
        sup.setdefault("run_dir", self.run_dir)
        sup.setdefault("log_dir", os.path.join(self.dir, "logs"))
        sup.setdefault("heartbeat_watch", False)
        sup.setdefault("single_instance_wait", 0)
        sup.setdefault("bin_dir", BIN)
        lines = ["[supervisor]"]
        for k, v in sup.items():
            lines.append("%s = %s" % (k, json.dumps(v)))
        for p in processes:
            lines.append("\n[[process]]")
            for k, v in p.items():
                if k == "env":
                    lines.append("env = { %s }" % ", ".join("%s = %s" % (a, json.dumps(b)) for a, b in v.items()))
                else:
                    lines.append("%s = %s" % (k, toml_list(v) if isinstance(v, list) else json.dumps(v)))
        path = os.path.join(self.dir, "pipeline-%d.toml" % len(self.procs))
        with open(path, "w") as f:
            f.write("\n".join(lines) + "\n")
        return path

    def start(self, path):
        p = subprocess.Popen([sys.executable, SUPERVISOR, "run", path], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)
        self.procs.append(p)
        return p

    def status(self, run_dir=None):
        out = subprocess.run([sys.executable, SUPERVISOR, "status-json", "--run-dir", run_dir or self.run_dir],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        if out.returncode != 0:
            return None
        return {r["name"]: r for r in json.loads(out.stdout)["processes"]}

    def wait_for(self, pred, limit=15.0, what="condition"):
        end = time.monotonic() + limit
        while time.monotonic() < end:
            st = self.status()
            if st is not None and pred(st):
                return st
            time.sleep(0.1)
        self.fail("timed out waiting for %s; last status: %s" % (what, self.status()))

    def stop(self, sup):
        sup.send_signal(signal.SIGTERM)
        out, err = sup.communicate(timeout=30)
        return out, err


class TestLifecycle(SupervisorCase):
    def test_starts_in_order_and_stops_in_reverse_with_sigkill_fallback(self):
        trace = os.path.join(self.dir, "trace")
        def proc(name, ignore_term=False):
            trap = "trap '' TERM" if ignore_term else "trap 'echo stop %s >> %s; exit 0' TERM" % (name, trace)
            return {"name": name, "command": ["/bin/sh", "-c", "%s; echo start %s >> %s; while :; do sleep 0.05; done" % (trap, name, trace)],
                    "stop_timeout": 1.0}
        path = self.pipeline([proc("a"), proc("b"), proc("stubborn", ignore_term=True), proc("c")])
        sup = self.start(path)
        self.wait_for(lambda st: all(r["state"] == "running" and r["pid"] for r in st.values()), what="all running")
        time.sleep(0.3)
        t0 = time.monotonic()
        out, err = self.stop(sup)
        took = time.monotonic() - t0
        self.assertEqual(sup.returncode, 0, err)
        with open(trace) as f:
            lines = f.read().split()
        starts = [lines[i + 1] for i in range(0, len(lines), 2) if lines[i] == "start"]
        stops = [lines[i + 1] for i in range(0, len(lines), 2) if lines[i] == "stop"]
        self.assertEqual(starts, ["a", "b", "stubborn", "c"])
        self.assertEqual(stops, ["c", "b", "a"])  # reverse order; stubborn ignored SIGTERM
        self.assertIn("stubborn: still running 1.0 s after SIGTERM: SIGKILL", err)
        self.assertGreaterEqual(took, 1.0)  # it waited for the stubborn one before killing it
        self.assertIn("NAME", out)  # final status table

    def test_restart_with_exponential_backoff_then_gives_up_on_crash_loop(self):
        path = self.pipeline([{"name": "crasher", "command": ["/bin/sh", "-c", "echo boom; exit 3"],
                               "backoff_initial": 0.1, "backoff_max": 10, "crash_restarts": 3, "crash_window": 60},
                              {"name": "steady", "command": ["/bin/sh", "-c", "while :; do sleep 0.1; done"]}])
        sup = self.start(path)
        st = self.wait_for(lambda st: st["crasher"]["state"] == "failed", what="crash loop detection")
        self.assertEqual(st["crasher"]["last_exit"], 3)
        self.assertIn("crash loop", st["crasher"]["reason"])
        self.assertEqual(st["steady"]["state"], "running")  # the rest keeps running
        out, err = self.stop(sup)
        delays = [float(x) for x in re.findall(r"crasher: exited with 3; restarting in ([0-9.]+) s", err)]
        self.assertEqual(delays, [0.1, 0.2, 0.4])
        self.assertIn("crasher: GIVING UP", err)
        self.assertEqual(sup.returncode, 1)  # a process was given up on
        with open(os.path.join(self.dir, "logs", "crasher.log")) as f:
            log = f.read()
        self.assertEqual(log.count("boom"), 4)  # first start + 3 restarts

    def test_on_failure_and_never_policies(self):
        path = self.pipeline([{"name": "done-ok", "command": ["/bin/true"], "restart": "on-failure"},
                              {"name": "once", "command": ["/bin/false"], "restart": "never"}])
        sup = self.start(path)
        st = self.wait_for(lambda st: st["done-ok"]["state"] == "exited" and st["once"]["state"] == "exited", what="both exited")
        self.assertEqual(st["done-ok"]["restarts"], 0)
        self.assertEqual(st["once"]["last_exit"], 1)
        self.stop(sup)

    def test_nice_lowers_the_process_and_its_session_group(self):
        """nice = 19: the kernel reports nice 19 for the process and, where it groups sessions (autogroup), for
        its session's group; a process without the key stays at 0 in a session of its own."""
        loop = ["/bin/sh", "-c", "while :; do sleep 0.05; done"]
        sup = self.start(self.pipeline([{"name": "viewer-server", "command": loop, "nice": 19},
                                        {"name": "cell", "command": loop}]))
        st = self.wait_for(lambda st: all(r["state"] == "running" and r["pid"] for r in st.values()), what="both running")
        pids = {name: st[name]["pid"] for name in ("viewer-server", "cell")}
        self.assertNotEqual(os.getsid(pids["viewer-server"]), os.getsid(pids["cell"]))
        for name, want in (("viewer-server", 19), ("cell", 0)):
            with open("/proc/%d/stat" % pids[name]) as f:
                stat = f.read()
            self.assertEqual(int(stat[stat.rindex(")") + 2:].split()[19 - 3]), want, name)  # field 19: nice
            if os.path.exists("/proc/%d/autogroup" % pids[name]):
                with open("/proc/%d/autogroup" % pids[name]) as f:
                    self.assertRegex(f.read(), r"^/autogroup-\d+ nice %d$" % want, name)
        self.stop(sup)

    def test_log_rotation(self):
        # About 350 kB of output: even when a loaded machine lets the pipe fill so that every read takes a
        # whole 64 KiB, that is more than three rotations, so both backups must exist.
        path = self.pipeline([{"name": "chatty", "command": ["/bin/sh", "-c", "i=0; while [ $i -lt 10000 ]; do echo line $i xxxxxxxxxxxxxxxxxxxxxxxx; i=$((i+1)); done; sleep 30"]}],
                             log_max_bytes=20000, log_backups=2)
        sup = self.start(path)
        logs = os.path.join(self.dir, "logs")
        last_line = "line 9999 xxxxxxxxxxxxxxxxxxxxxxxx"

        def tail():
            try:
                with open(os.path.join(logs, "chatty.log")) as f:
                    return f.read().rstrip()
            except OSError:
                return ""
        end = time.monotonic() + 20
        while time.monotonic() < end and not tail().endswith(last_line):
            time.sleep(0.1)
        self.stop(sup)
        names = sorted(os.listdir(logs))
        self.assertEqual(names, ["chatty.log", "chatty.log.1", "chatty.log.2"])
        for n in names:
            size = os.path.getsize(os.path.join(logs, n))
            self.assertGreater(size, 0)
            # Rotation happens before a write that would pass the limit: a file passes it only when one
            # read of the pipe (at most 64 KiB) alone is larger.
            self.assertLessEqual(size, max(20000, 65536))
        # The newest lines are in chatty.log, the last line written is the last line there.
        self.assertTrue(tail().endswith(last_line))  # the newest lines are in chatty.log

    def test_status_table_and_bad_pipeline(self):
        path = self.pipeline([{"name": "sleeper", "command": ["/bin/sh", "-c", "sleep 30"]}])
        sup = self.start(path)
        self.wait_for(lambda st: st["sleeper"]["state"] == "running")
        table = subprocess.run([sys.executable, SUPERVISOR, "status", "--run-dir", self.run_dir],
                               stdout=subprocess.PIPE, text=True).stdout
        self.assertRegex(table, r"NAME\s+STATE\s+PID\s+RESTARTS\s+UPTIME\s+LAST EXIT\s+HEARTBEAT")
        self.assertRegex(table, r"sleeper\s+running\s+\d+\s+0\s+")
        # The same run directory cannot be used twice.
        second = subprocess.run([sys.executable, SUPERVISOR, "run", path], stdout=subprocess.PIPE,
                                stderr=subprocess.PIPE, text=True, timeout=30)
        self.assertEqual(second.returncode, 3)
        self.assertIn("another supervisor (pid %d) runs on output folder %s" % (sup.pid, self.run_dir), second.stderr)
        self.stop(sup)
        bad = os.path.join(self.dir, "bad.toml")
        with open(bad, "w") as f:
            f.write("[[process]]\nname = \"x\"\ncommand = \"not a list\"\n")
        r = subprocess.run([sys.executable, SUPERVISOR, "run", bad], stderr=subprocess.PIPE, text=True)
        self.assertEqual(r.returncode, 2)
        self.assertIn("command must be a non-empty list", r.stderr)


class TestPipelineFile(SupervisorCase):
    """A pipeline file with a value of the wrong type or an unknown key: one message naming the file and the
    key, exit 2, no traceback, nothing started."""

    def run_bad(self, text):
        bad = os.path.join(self.dir, "typed.toml")
        with open(bad, "w") as f:
            f.write(text)
        r = subprocess.run([sys.executable, SUPERVISOR, "run", bad], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                           text=True, timeout=30)
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertNotIn("Traceback", r.stderr)
        self.assertIn(bad, r.stderr)
        return r.stderr

    def test_type_errors_name_the_file_and_key(self):
        proc = '\n[[process]]\nname = "x"\ncommand = ["/bin/true"]\n'
        cases = [
            ('[supervisor]\nlog_max_bytes = "big"\n' + proc, "key 'log_max_bytes' must be an integer"),
            ('[supervisor]\nheartbeat_watch = 1\n' + proc, "key 'heartbeat_watch' must be true or false"),
            ('[supervisor]\nstop_timeout = true\n' + proc, "key 'stop_timeout' must be a number"),
            (proc + 'heartbeat_timeout = "2.5"\n', "process 0: key 'heartbeat_timeout' must be a number"),
            (proc + 'env = ["A=1"]\n', "process 0: key 'env' must be a table"),
            (proc + 'crash_restarts = 2.5\n', "process 0: key 'crash_restarts' must be an integer"),
            ('[[process]]\nname = "x"\ncommand = ["a", 3]\n', "command must be a non-empty list of strings"),
            ('supervisor = 3\n' + proc, "key 'supervisor' must be a table"),
            ('process = [1, 2]\n', "process 0: key 'process' must be a list of tables"),
            (proc + 'nice = "low"\n', "process 0: key 'nice' must be an integer"),
            (proc + 'nice = 20\n', "process 'x': nice must be 0 to 19"),
            (proc + 'nice = -1\n', "process 'x': nice must be 0 to 19"),
        ]
        for text, expected in cases:
            with self.subTest(expected=expected):
                self.assertIn(expected, self.run_bad(text))

    def test_unknown_key_names_the_nearest(self):
        err = self.run_bad('[supervisor]\nlog_max_byte = 10\n\n[[process]]\nname = "x"\ncommand = ["/bin/true"]\n')
        self.assertIn("unknown key 'log_max_byte' (nearest known: 'log_max_bytes')", err)
        err = self.run_bad('[[process]]\nname = "x"\ncommand = ["/bin/true"]\nrestarts = "always"\n')
        self.assertIn("process 0: unknown key 'restarts' (nearest known: 'restart')", err)


def children_of(pid):
    """The pids of every descendant of `pid` (from /proc), so that none is missed."""
    found, todo = [], [pid]
    while todo:
        p = todo.pop()
        try:
            tasks = os.listdir("/proc/%d/task" % p)
        except FileNotFoundError:
            continue
        for t in tasks:
            try:
                with open("/proc/%d/task/%s/children" % (p, t)) as f:
                    kids = [int(k) for k in f.read().split()]
            except FileNotFoundError:
                kids = []
            found += kids
            todo += kids
    return found


def alive(pid):
    try:
        with open("/proc/%d/stat" % pid) as f:
            return f.read().split(")")[-1].split()[0] != "Z"  # a zombie is gone, only not reaped yet
    except (FileNotFoundError, ProcessLookupError):  # gone before the open, or reaped between open and read
        return False


class TestOutputFolder(SupervisorCase):
    """One supervisor per output folder (--out / $OUT, ${OUT} in the pipeline file), and no process outlives
    the supervisor that started it, even when it is killed with SIGKILL."""

    def out_pipeline(self, processes, **sup):
        sup.setdefault("run_dir", "${OUT}/supervisor")
        sup.setdefault("log_dir", "${OUT}/logs")
        return self.pipeline(processes, **sup)

    def start_out(self, path, out, *extra):
        p = subprocess.Popen([sys.executable, SUPERVISOR, "run", "--out", out] + list(extra) + [path],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        self.procs.append(p)
        return p

    def test_placeholders_expand_and_an_unset_one_is_refused(self):
        out = os.path.join(self.dir, "o1")
        marker = os.path.join("${OUT}", "marker")
        path = self.out_pipeline([{"name": "w", "command": ["/bin/sh", "-c", 'echo "$0 ${X:-}" > "$1"; sleep 30',
                                                           "${WHO:-nobody}", marker]}])
        sup = self.start_out(path, out, "--set", "WHO=someone")
        self.run_dir = os.path.join(out, "supervisor")
        self.wait_for(lambda st: st["w"]["state"] == "running")
        deadline = time.monotonic() + 10
        while not os.path.exists(os.path.join(out, "marker")) and time.monotonic() < deadline:
            time.sleep(0.05)
        with open(os.path.join(out, "marker")) as f:
            self.assertEqual(f.read().strip(), "someone")
        self.assertTrue(os.path.exists(os.path.join(out, "logs", "w.log")))
        self.stop(sup)
        # Without --out and $OUT: refused, one line naming the file and the key, nothing created.
        env = {k: v for k, v in os.environ.items() if k != "OUT"}
        r = subprocess.run([sys.executable, SUPERVISOR, "run", path], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                           text=True, timeout=30, env=env, cwd=self.dir)
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertEqual(len(r.stderr.splitlines()), 1, r.stderr)
        self.assertIn("pipeline file '%s': [supervisor] key 'run_dir': ${OUT} is not set" % path, r.stderr)
        self.assertFalse(os.path.exists(os.path.join(self.dir, "out")))
        # check prints the expanded pipeline and starts nothing.
        r = subprocess.run([sys.executable, SUPERVISOR, "check", "--out", out, path], stdout=subprocess.PIPE,
                           stderr=subprocess.PIPE, text=True, timeout=30)
        self.assertEqual(r.returncode, 0, r.stderr)
        checked = json.loads(r.stdout)
        self.assertEqual(checked["process"][0]["command"][-1], os.path.join(out, "marker"))
        self.assertEqual(checked["process"][0]["command"][-2], "nobody")

    def test_second_supervisor_on_one_output_folder_is_refused_with_the_first_pid(self):
        out = os.path.join(self.dir, "shared")
        self.run_dir = os.path.join(out, "supervisor")
        first = self.start_out(self.out_pipeline([{"name": "s", "command": ["/bin/sh", "-c", "sleep 30"]}]), out)
        self.wait_for(lambda st: st["s"]["state"] == "running")
        # Another pipeline file, another run directory: the output folder alone decides.
        other = self.pipeline([{"name": "s", "command": ["/bin/sh", "-c", "sleep 30"]}],
                              run_dir=os.path.join(self.dir, "elsewhere"), log_dir=os.path.join(self.dir, "elsewhere-logs"))
        r = subprocess.run([sys.executable, SUPERVISOR, "run", "--out", out, other], stdout=subprocess.PIPE,
                           stderr=subprocess.PIPE, text=True, timeout=30)
        self.assertEqual(r.returncode, 3, r.stderr)
        self.assertIn("another supervisor (pid %d) runs on output folder %s" % (first.pid, out), r.stderr)
        self.assertFalse(os.path.exists(os.path.join(self.dir, "elsewhere-logs")), "the refused one touched nothing")
        # A second output folder runs side by side.
        out2 = os.path.join(self.dir, "second")
        second = self.start_out(self.out_pipeline([{"name": "s", "command": ["/bin/sh", "-c", "sleep 30"]}]), out2)
        self.wait_for(lambda st: st["s"]["state"] == "running", what="the second folder's supervisor")
        self.run_dir = os.path.join(out2, "supervisor")
        self.wait_for(lambda st: st["s"]["state"] == "running", what="the second folder's supervisor")
        self.stop(second)
        # The lock dies with its holder, even by SIGKILL: a new supervisor starts on the folder at once.
        first.kill()
        first.wait()
        self.run_dir = os.path.join(out, "supervisor")
        third = self.start_out(self.out_pipeline([{"name": "s", "command": ["/bin/sh", "-c", "sleep 30"]}]), out)
        self.wait_for(lambda st: st["s"]["state"] == "running", what="a supervisor after a SIGKILLed one")
        self.stop(third)

    def test_no_process_outlives_a_sigkilled_supervisor(self):
        """SIGKILL at a random moment (while processes start, restart or run), several seeds: every process
        the supervisor started (the pipeline processes, which ignore SIGTERM here, and its bus helpers) is gone
        within 5 s."""
        import random
        procs = [{"name": "p%d" % i, "command": ["/bin/sh", "-c", "trap '' TERM; exec sleep 1000"],
                  "wait_heartbeat": False} for i in range(3)]
        procs.append({"name": "flaky", "command": ["/bin/sh", "-c", "sleep 0.3; exit 1"], "backoff_initial": 0.1})
        for seed in range(6):
            with self.subTest(seed=seed):
                rng = random.Random(seed)
                out = os.path.join(self.dir, "kill-%d" % seed)
                sup = self.start_out(self.out_pipeline(procs, heartbeat_watch=True), out)
                deadline = time.monotonic() + 20
                while not children_of(sup.pid) and time.monotonic() < deadline:
                    time.sleep(0.02)
                time.sleep(rng.uniform(0.0, 2.5))  # from its first child on: starting, restarting, running
                kids = children_of(sup.pid)
                sup.kill()
                sup.wait()
                self.assertTrue(kids, "the supervisor had started something")
                deadline = time.monotonic() + 5
                while any(alive(k) for k in kids) and time.monotonic() < deadline:
                    time.sleep(0.05)
                self.assertEqual([k for k in kids if alive(k)], [], "processes left 5 s after SIGKILL")


class TestBus(SupervisorCase):
    def test_heartbeat_stall_restarts_the_process(self):
        path = self.pipeline([{"name": "robot", "command": ["hg-robot-bridge", "--cell", os.path.join(SRC, "config", "cell.yaml")],
                               "wait_heartbeat": True,
                               "heartbeat_timeout": 2.5, "backoff_initial": 0.2}], heartbeat_watch=True)
        sup = self.start(path)
        st = self.wait_for(lambda st: st["robot"]["state"] == "running" and st["robot"]["heartbeat_age"] is not None,
                           what="first heartbeat")
        first_pid = st["robot"]["pid"]
        os.kill(first_pid, signal.SIGSTOP)  # alive, but silent
        st = self.wait_for(lambda st: st["robot"]["pid"] not in (None, first_pid) and st["robot"]["heartbeat_age"] is not None,
                           limit=20, what="restart after the heartbeat stopped")
        self.assertEqual(st["robot"]["restarts"], 1)
        self.assertIn("heartbeat stopped", str(st["robot"]["last_exit"]))
        self.stop(sup)

    def test_second_supervisor_on_the_same_bus_refuses(self):
        path = self.pipeline([{"name": "sleeper", "command": ["/bin/sh", "-c", "sleep 30"]}],
                             heartbeat_watch=True, single_instance_wait=2.5)
        sup = self.start(path)
        self.wait_for(lambda st: st["sleeper"]["state"] == "running")
        time.sleep(1.5)  # the first one's announcements are on the bus
        other_dir = os.path.join(self.dir, "other-run")
        path2 = self.pipeline([{"name": "sleeper", "command": ["/bin/sh", "-c", "sleep 30"]}],
                              heartbeat_watch=True, single_instance_wait=2.5, run_dir=other_dir)
        r = subprocess.run([sys.executable, SUPERVISOR, "run", path2], stdout=subprocess.PIPE,
                           stderr=subprocess.PIPE, text=True, timeout=60)
        self.assertEqual(r.returncode, 3, r.stderr)
        self.assertIn("another supervisor (pid %d) already runs on this LCM bus" % sup.pid, r.stderr)
        self.stop(sup)


if __name__ == "__main__":
    unittest.main()
