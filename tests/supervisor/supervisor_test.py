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
        self.assertIn("another supervisor already runs with run directory", second.stderr)
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
        ]
        for text, expected in cases:
            with self.subTest(expected=expected):
                self.assertIn(expected, self.run_bad(text))

    def test_unknown_key_names_the_nearest(self):
        err = self.run_bad('[supervisor]\nlog_max_byte = 10\n\n[[process]]\nname = "x"\ncommand = ["/bin/true"]\n')
        self.assertIn("unknown key 'log_max_byte' (nearest known: 'log_max_bytes')", err)
        err = self.run_bad('[[process]]\nname = "x"\ncommand = ["/bin/true"]\nrestarts = "always"\n')
        self.assertIn("process 0: unknown key 'restarts' (nearest known: 'restart')", err)


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
