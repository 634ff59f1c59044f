"""`make station` as a user runs it: tools/station.sh starts the simulated cell in a network namespace of its
own and forwards the station to 127.0.0.1:PORT outside it; a first user `operator` with a generated
password, printed once and kept in OUT/station/first-password (mode 0600); a job started through the
forwarded API runs to DONE on the cell file given; Ctrl-C stops everything; a second start keeps the users.
Runs in a network namespace and PID namespace of its own (CTest: tests/netns.sh --own-pids), which plays
the host: station.sh makes the cell's namespace inside it."""

import os
import re
import shutil
import signal
import subprocess
import tempfile
import time
import unittest

import station_browser_test  # its request helper (the page tests themselves are not run here)

SRC = os.environ.get("HG_SOURCE_DIR", os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
BIN = os.environ.get("HG_BIN_DIR", os.path.join(SRC, "build", "bin"))
STATION_SH = os.path.join(SRC, "tools", "station.sh")
PORT = 18080
URL = "http://127.0.0.1:%d" % PORT
READY = re.compile(r"^hullgrind station: http://127\.0\.0\.1:(\d+)/  \((.*)\)$", re.M)


def http(method, path, body=None, cookie="", csrf=""):
    return station_browser_test.http(method, path, body, cookie, csrf, base=URL)


def wait(pred, timeout, what):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        v = pred()
        if v:
            return v
        time.sleep(0.3)
    raise AssertionError("waited %.0f s for %s" % (timeout, what))


class StationSh(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="hg-station-sh-")
        self.out = os.path.join(self.tmp, "cell-out")
        # A cell file of its own (the shipped one, copied), to see that the cell given is the cell used.
        self.cell = os.path.join(self.tmp, "my-cell.yaml")
        shutil.copy(os.path.join(SRC, "config", "cell-sim.yaml"), self.cell)

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def start(self):
        """station.sh as from a terminal: its own process group (Ctrl-C reaches the group), not inside
        the test's namespace marker, so that it makes its own."""
        env = {k: v for k, v in os.environ.items() if k not in ("HG_IN_NETNS", "OUT")}
        env["BIN"] = BIN
        self.log = os.path.join(self.tmp, "station-%d.log" % time.monotonic_ns())
        self.proc = subprocess.Popen([STATION_SH, "--out", self.out, "--cell", self.cell, "--port", str(PORT)],
                                     stdout=open(self.log, "w"), stderr=subprocess.STDOUT, env=env,
                                     stdin=subprocess.DEVNULL, start_new_session=True)
        return wait(lambda: READY.search(self.text()) or self.ended(), 180, "the station's ready line")

    def text(self):
        with open(self.log) as f:
            return f.read()

    def ended(self):
        if self.proc.poll() is not None:
            raise AssertionError("station.sh ended with %s:\n%s" % (self.proc.returncode, self.text()[-3000:]))
        return None

    def stop(self):
        os.killpg(self.proc.pid, signal.SIGINT)  # Ctrl-C
        self.proc.wait(timeout=60)
        left = subprocess.run(["pgrep", "-af", BIN + "/hg-"], stdout=subprocess.PIPE, text=True).stdout
        self.assertEqual(left, "", "processes left after Ctrl-C")

    def test_first_start_job_ctrl_c_second_start(self):
        ready = self.start()
        self.assertEqual(int(ready.group(1)), PORT)
        pw_file = os.path.join(self.out, "station", "first-password")
        self.assertEqual(os.stat(pw_file).st_mode & 0o777, 0o600)
        with open(pw_file) as f:
            password = f.read().strip()
        self.assertIn("user operator, password %s " % password, ready.group(2))
        status, body, headers = http("POST", "/api/login", {"user": "operator", "password": password})
        self.assertEqual(status, 200, body)
        cookie, csrf = headers["Set-Cookie"].split(";")[0], body["csrf"]
        status, cell, _ = http("GET", "/api/cell", cookie=cookie)
        self.assertEqual(status, 200)
        self.assertEqual(os.path.basename(cell["cell"]["file"]), "my-cell.yaml", cell["cell"])
        status, body, _ = http("POST", "/api/jobs", {"part_id": "station-sh-plate"}, cookie, csrf)
        self.assertEqual(status, 202, body)
        job = body["job_id"]

        def state():
            st, b, _ = http("GET", "/api/jobs/" + job, cookie=cookie)
            return b["live"]["state"] if st == 200 and b.get("live") else ""
        wait(lambda: state() in ("DONE", "FAILED", "REFUSED", "NEEDS_RESCAN", "REJECTED", "INCOMPLETE"), 240,
             "the job's end")
        self.assertEqual(state(), "DONE")
        self.assertTrue(os.path.isdir(os.path.join(self.out, "jobs", job)), "the job's record in OUT/jobs")
        self.stop()

        ready = self.start()  # the users stay; no new password
        self.assertNotIn("password", ready.group(2).split("(")[0])
        self.assertIn("first password is in", ready.group(2))
        with open(pw_file) as f:
            self.assertEqual(f.read().strip(), password)
        status, _, _ = http("POST", "/api/login", {"user": "operator", "password": password})
        self.assertEqual(status, 200)
        self.stop()


if __name__ == "__main__":
    unittest.main()
