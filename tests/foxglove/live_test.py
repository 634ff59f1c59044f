"""hg-foxglove on a real job: the shipped pipeline (config/pipeline.toml, with its hg-foxglove) under
tools/supervisor as tests/e2e runs it, a job sent, and tests/foxglove/live_check.js (@foxglove/ws-protocol's
client, ajv, @foxglove/schemas) connected throughout. The bus is recorded at the same time, so the
expectation (which channels exist) comes from the LCM log, not from the server; the same log then goes
through hg-mcap and tests/foxglove/mcap_check.js (@mcap/core): an MCAP of a real pipeline run.
Runs in its own network namespace (CTest: tests/netns.sh)."""
import json
import os
import struct
import subprocess
import sys
import time
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "e2e"))
import e2e_pipeline as E  # noqa: E402

NODE_ENV = dict(os.environ, NODE_PATH=os.path.join(os.environ.get("HG_NPM_DIR", os.path.join(E.SRC, "build", "npm")),
                                                   "node_modules"))


def log_channels(path):
    """Channel -> event count of an LCM log (the lcm-logger format)."""
    counts = {}
    with open(path, "rb") as f:
        data = f.read()
    pos = 0
    while pos + 28 <= len(data):
        sync, _, _, clen, dlen = struct.unpack(">IqqII", data[pos:pos + 28])
        if sync != 0xEDA1DA01:
            raise ValueError("%s: no sync word at byte %d" % (path, pos))
        ch = data[pos + 28:pos + 28 + clen].decode()
        counts[ch] = counts.get(ch, 0) + 1
        pos += 28 + clen + dlen
    return counts


class FoxgloveLive(unittest.TestCase):
    def test_client_sees_every_channel_and_the_plate_during_a_job(self):
        p = E.Pipeline("foxglove", extra_args={"planner": ["--small-hole", "skip"],
                                               "foxglove": []})
        ok, client = False, None
        try:
            p.start()
            result_file, stop = os.path.join(p.dir, "live.json"), os.path.join(p.dir, "live.stop")
            client = subprocess.Popen(["node", os.path.join(HERE, "live_check.js"), "ws://127.0.0.1:8765", result_file,
                                       stop], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=NODE_ENV)
            self.assertEqual(client.stdout.readline().strip(), "ready")
            self.check_priority(p)
            time.sleep(9)  # the probes (about 5 s), then the job
            p.send("fox-live-1", extra=["--grind-speed", "0.01"])
            # Any end: what the client must see is what the bus carried (the log), whatever the job's fate.
            final = p.wait_final("fox-live-1", 240)
            print("job fox-live-1 ended", final["state"], "by", final["source"], final["message"])
            time.sleep(3)  # the last statuses and two heartbeats reach the client
            open(stop, "w").close()
            out, _ = client.communicate(timeout=60)
            self.assertEqual(client.returncode, 0, out)
            with open(result_file) as f:
                r = json.load(f)
            p.stop()
            skipped = self.check_mcap(p)
            self.check(r, log_channels(p.log), skipped)
            self.check_log_lines(r, p)
            ok = True
        finally:
            if client and client.poll() is None:
                client.kill()
                client.wait()
            p.cleanup(failed=not ok)

    def check_priority(self, p):
        """The shipped pipeline gives hg-foxglove nice 19, and its session's scheduling group too, the cell's
        processes 0 (docs/RUNNING.md, Priority): the kernel's own view in /proc."""
        st = p.status()
        for name, want in (("foxglove", 19), ("outline", 0), ("planner", 0)):
            with open("/proc/%d/stat" % st[name]["pid"]) as f:
                stat = f.read()
            self.assertEqual(int(stat[stat.rindex(")") + 2:].split()[19 - 3]), want, name)  # field 19: nice
            group = "/proc/%d/autogroup" % st[name]["pid"]
            if os.path.exists(group):
                with open(group) as f:
                    self.assertTrue(f.read().strip().endswith(" nice %d" % want), name)

    def check(self, r, in_log, skipped):
        """skipped: channel -> events hg-mcap could not decode (a process that sent garbage): the server
        must have refused those too, so a channel with only such events is advertised but shows nothing."""
        advertised = {a["topic"]: a for a in r["advertised"]}
        for ch in in_log:
            self.assertIn(ch, advertised, "channel %s of the bus was not advertised" % ch)
            if ch.startswith("HG_"):  # hullgrind's channels; others (LCM's own LCM_SELF_TEST) are raw
                self.assertEqual(advertised[ch]["encoding"], "json", ch)
                self.assertTrue(advertised[ch]["schemaName"].startswith("hullgrind."), ch)
        # The job's picture: a cloud, an outline, the robot and statuses at least; a path when one was planned.
        derived = {"HG_PLATE_CLOUD": "/hg/plate/points", "HG_OUTLINE": "/hg/outline", "HG_GRIND_PATH": "/hg/grind_path",
                   "HG_ROBOT_STATUS": "/tf", "HG_JOB_STATUS": "/hg/log"}
        for ch in ("HG_PLATE_CLOUD", "HG_OUTLINE", "HG_JOB_STATUS", "HG_ROBOT_STATUS", "HG_HEARTBEAT"):
            self.assertIn(ch, in_log, "the job put nothing on " + ch)
        for ch, n in in_log.items():
            if skipped.get(ch, 0) == n:
                self.assertEqual(r["counts"].get(ch, 0), 0, ch + ": the server sent what does not decode")
                print("every message on %s was garbage (%d), skipped by hg-mcap and hg-foxglove" % (ch, n))
                continue
            self.assertGreater(r["counts"].get(ch, 0), 0, "nothing received on " + ch)
            if ch in derived:
                self.assertGreater(r["counts"].get(derived[ch], 0), 0, "nothing received on " + derived[ch])
        self.assertEqual(r["invalid"], [], "messages that did not decode or validate")
        self.assertEqual(r["errors"], [])
        self.assertGreaterEqual(r["clouds_checked"], 1, "no PointCloud matched to its plate cloud")
        self.assertEqual(r["cloud_failures"], [])
        if r["counts"].get("/hg/grind_path"):
            self.assertGreaterEqual(r["paths_checked"], 1, "no SceneUpdate matched to its grind path")
            self.assertGreater(r["edge_points"], 0, "the plans carried no smoothed edge")
            self.assertEqual(r["path_failures"], [])
        pr = r["probes"]
        self.assertEqual((pr["sdk"]["protocol"], pr["sdk"]["first"]), ("foxglove.sdk.v1", "serverInfo"))
        self.assertEqual(pr["no_subprotocol"].get("status"), 400, pr["no_subprotocol"])
        for name in ("text_garbage", "binary", "bad_subscribe"):
            self.assertEqual(pr[name].get("code"), 1008, "%s: %s" % (name, pr[name]))
            self.assertTrue(pr[name].get("reason"), name)
        self.assertIn("closed for garbage", r["heartbeat"])
        garbage = int(r["heartbeat"].split(" closed for garbage")[0].split("; ")[-1])
        self.assertGreaterEqual(garbage, 3, r["heartbeat"])
        self.assertIn(" dropped ", r["heartbeat"])  # per client; the drops themselves: foxglove_ws_server_test

    def check_log_lines(self, r, p):
        """The processes' log lines on the bus (HG_LOG) came to the client as log_line_t and as foxglove.Log on
        /hg/log, and each is a line of its process's own log file (the supervisor's logs/, from stderr)."""
        self.assertEqual(r["log_unshown"], [], "log lines on HG_LOG without their /hg/log line")
        logs = ""
        for name in os.listdir(os.path.join(p.dir, "logs")):
            with open(os.path.join(p.dir, "logs", name), errors="replace") as f:
                logs += f.read()
        levels = ["DEBUG", "INFO ", "WARN ", "ERROR"]
        for line in r["log_lines"]:
            self.assertIn(" %s %s: %s\n" % (levels[line["level"]], line["process"], line["text"]), logs,
                          "a log line on the bus that is in no process's log file")
        seen = {line["process"] for line in r["log_lines"]}
        for proc in ("hg-camera-bridge", "hg-outline-service", "hg-path-planner", "hg-robot-bridge", "hg-foxglove"):
            self.assertIn(proc, seen, "no log line of %s on the bus" % proc)
        print("%d log lines of %s on the bus, each in its process's log file" % (len(r["log_lines"]), sorted(seen)))

    def check_mcap(self, p):
        mcap = os.path.join(p.dir, "run.mcap")
        conv = E.run([E.bin_path("hg-mcap"), p.log, "-o", mcap, "--cell", os.path.join(E.CONFIG, "cell-sim.yaml")], 300)
        self.assertEqual(conv.returncode, 0, conv.stderr)
        skip = []
        for line in conv.stderr.splitlines():
            if "skipped events:" in line:
                skip = line.split("skipped events:")[1].split()
        skip_args = [a for s in skip for a in ("--skip", s)]
        chk = E.run(["node", os.path.join(HERE, "mcap_check.js"), mcap, p.log, "--expect-tf"] + skip_args, 600, env=NODE_ENV)
        self.assertEqual(chk.returncode, 0, chk.stdout + chk.stderr)
        print(conv.stderr.strip(), "\n", chk.stdout.strip())
        skipped = {}
        for s in skip:
            ch = s.rsplit("#", 1)[0]
            skipped[ch] = skipped.get(ch, 0) + 1
        return skipped


if __name__ == "__main__":
    unittest.main()
