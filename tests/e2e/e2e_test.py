"""End-to-end tests of the whole pipeline (issue 8), driving the real binaries under tools/supervisor with
the shipped config/pipeline.toml (private paths, see e2e_pipeline.py). One CTest entry per class, each in
a network namespace of its own (tests/netns.sh):

  E2EWholePipeline  a job goes DONE; its grind path matches the scene's ground truth carried to the robot
                    base frame and offset by the tool radius; every hole is ground; its START repeated
                    afterwards is answered DONE and plans and runs nothing more.
  E2EKill           kill -9 of each process in turn mid-job: restarted by the supervisor, the job ends
                    (DONE, or FAILED/ABORTED with a reason) within a bound, and a new job goes DONE; the
                    job recorder killed mid-job still records the job's end.
  E2EInterruptedRun tools/run.sh stopped mid-job (Ctrl-C), then run again: the second run ends DONE; the job
                    history has the first job ABORTED and the second DONE; a third run asking for the second
                    job again is answered DONE from the job history: no second path, no second run.
  E2EReplay         the recorded run log, replayed into a fresh outline service + planner, gives the same
                    outline and path.
  E2EGenicam        config/pipeline-genicam.toml: the camera bridge reads a fake GigE Vision 3-D camera
                    (hg-fake-genicam, GVCP/GVSP on 127.0.0.1) through Aravis; the job goes DONE and its grind
                    path matches the ground truth as in E2EWholePipeline.
  E2ETwoHosts       the camera bridge in one network namespace, the rest in another, joined by a veth pair,
                    LCM multicast with ttl=1: the job goes DONE.

Every wait has a deadline (the pipeline's own timeouts bound a job: planner outline_timeout 10 s, robot
path-timeout 60 s); nothing here asserts on time."""

import json
import math
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import e2e_geometry as G  # noqa: E402
import e2e_pipeline as E  # noqa: E402

JOB_TIMEOUT = 120  # s: capture + outline + plan + a 10x simulated run is ~15 s; generous for a loaded machine
# Planner tolerance for noisy parts (docs/path_planner.md: offset <= 1.0 mm noisy), away from corners.
OFFSET_TOLERANCE = 1.0e-3
# A neighbourhood of a true corner (turn >= 20 deg) left out of the offset check: the planner fits corners
# over corner_scale = 8 pitches (~11 mm at the pm806's 1.34 mm pitch; ~18 mm on its noisy frames, where the
# scale is raised to 60 noise levels) and smoothing rounds what is inside.
CORNER_TURN = math.radians(20)
CORNER_EXCLUSION = 0.010
# The grind points lie on the plate's top face (z_offset 0): the camera's fitted plane, within 1 mm.
TOP_FACE_TOLERANCE = 1.0e-3


# The shipped pipeline's planner (small-hole: fail): a hole too small for the tool FAILS the job. (With
# small-hole: skip a skipped hole is an unground stretch of the plan: it waits for an operator's approval and
# can never end DONE unexcluded.) E2EWholePipeline checks independently that every true hole is ground.
PLANNER_ARGS = []
# Known issue (issue 8 brief): the robot bridge refuses a path whose corner needs more than max-accel
# (v^2/r; the planner does not slow down at corners yet). Now and then a noisy frame gives a grind corner
# of ~0.2 mm radius, too tight at the default 0.02 m/s. The jobs that must go DONE ask for half that grind
# speed in the job request (a documented job_request_t parameter): the robot bridge is not weakened.
JOB_ARGS = ["--grind-speed", "0.01"]


def camera_scene():
    """Scene and profile of the shipped camera process (its hg-virtual:// URI)."""
    cmd = E.process_command("camera")
    uri = cmd[cmd.index("--openni2.uri") + 1]
    m = re.match(r"hg-virtual://([\w-]+)\?(.*)", uri)
    query = dict(kv.split("=", 1) for kv in m.group(2).split("&"))
    return m.group(1), query.get("profile", "pm806")


def write_truth(path):
    """The shipped scene's ground truth (the virtual OpenNI2 device serves the same renderer's frames)."""
    return E.scene_truth(*camera_scene(), path)


def planner_extra_args(truth):
    """None: the pipeline runs as shipped, and the planner takes the pixel pitch on the plate from the outline
    (outline_t.point_spacing, docs/path_planner.md); no test supplies it."""
    return []


class PipelineCase(unittest.TestCase):
    pipeline = None

    def tearDown(self):
        if self.pipeline is not None:
            # A failed test keeps its run directory (logs, run.lcmlog) and says where.
            result = self._outcome.result
            self.pipeline.cleanup(failed=any(t is self for t, _ in result.failures + result.errors))

    def run_job(self, p, job_id, timeout=JOB_TIMEOUT, extra=JOB_ARGS):
        p.send(job_id, extra=extra)
        return p.wait_final(job_id, timeout)

    def assert_done(self, final, p):
        self.assertEqual((final["state"], final["source"]), ("DONE", E.ROBOT),
                         "job did not end DONE: %s\n%s" % (final, p.diagnostics()))


class E2EWholePipeline(PipelineCase):
    def test_job_done_and_path_matches_ground_truth(self):
        tmp = tempfile.mkdtemp(prefix="hg-e2e-truth-")
        self.addCleanup(shutil.rmtree, tmp, True)
        truth = write_truth(os.path.join(tmp, "truth.json"))
        self.pipeline = p = E.Pipeline("whole", extra_args={"planner": PLANNER_ARGS + planner_extra_args(truth)})
        p.start()
        final = self.run_job(p, "e2e-whole-1")
        self.assert_done(final, p)
        states = [(s["source"], s["state"]) for s in p.statuses("e2e-whole-1") if s["state"] != "RUNNING"]
        self.assertIn(("hg-path-planner", "PLANNED"), states)
        self.check_repeated_start(p, "e2e-whole-1")
        time.sleep(0.5)  # lcm-logger flushes every 100 ms
        out_dir = os.path.join(p.dir, "out")
        ov = p.overview("e2e-whole-1", out_dir)
        self.assertEqual(ov.returncode, 0, ov.stdout + ov.stderr)
        with open(os.path.join(out_dir, "path.json")) as f:
            path = json.load(f)
        self.check_path_against_truth(path, truth)

    def check_repeated_start(self, p, job):
        """A retrying writer sends the START of a finished job again: answered, never planned or run again."""
        for _ in range(5):
            p.send(job, extra=JOB_ARGS)
        answers = lambda: [s for s in p.statuses(job) if s["source"] == E.ROBOT and "repeated START" in s["message"]]
        p.wait(lambda: len(answers()) >= 5, 60, "the robot bridge's answers to the repeated START")
        self.assertTrue(all(s["state"] == "DONE" for s in answers()), str(answers()))
        time.sleep(1.0)  # what a wrongly restarted job would have said by now (capture + plan take < 1 s)
        st = p.statuses(job)
        # An answer (to a QUERY of the recorder or the station) repeats a status; it is no second plan or run.
        planned = [s for s in st if s["source"] == "hg-path-planner" and s["state"] == "PLANNED" and not s["answer"]]
        started = [s for s in st if s["source"] == E.ROBOT and s["state"] == "RUNNING" and s["message"].startswith("running ")
                   and not s["answer"]]
        self.assertEqual(len(planned), 1, "planned %d times: %s" % (len(planned), planned))
        self.assertEqual(len(started), 1, "run %d times" % len(started))

    def check_path_against_truth(self, path, truth):
        # Expected frames: table --(truth camera_from_table)--> camera --(the cell's hand-eye calibration)--> base.
        cfg = G.planner_settings(os.path.join(E.CONFIG, "path_planner.yaml"), E.process_command("planner"))
        cell = G.read_cell(G.cell_of(E.process_command("planner"), E.CONFIG))
        camera_to_base = cell["camera-to-base"]
        base_to_table = G.rigid_inverse(G.matmul(camera_to_base, truth["camera_from_table"]))
        radius = cell["tool-radius"]  # the job request leaves it at 0: the cell's tool
        self.assertEqual(len(truth["parts"]), 1, "the shipped scene has one part (camera: --parts largest)")
        part = truth["parts"][0]
        rings = [part["outer"]] + part["holes"]
        corners = [c for r in rings for c in G.corners(r, CORNER_TURN)]

        grind = [w for w in path["waypoints"] if w["kind"] == "grind"]
        self.assertGreater(len(grind), 0, "no grind waypoints")
        per_ring = [[] for _ in rings]
        worst = (0.0, None)
        checked = 0
        for i, w in enumerate(grind):
            q = G.apply(base_to_table, w["position"])
            self.assertLessEqual(abs(q[2] - part["thickness"]), TOP_FACE_TOLERANCE,
                                 "grind waypoint %d is %.2f mm off the plate's top face" % (i, 1e3 * (q[2] - part["thickness"])))
            ds = [G.ring_dist(q, r) for r in rings]
            k = min(range(len(rings)), key=lambda j: ds[j])
            per_ring[k].append(q)
            on_air_side = (not G.inside(q, rings[0])) if k == 0 else G.inside(q, rings[k])
            self.assertTrue(on_air_side, "grind waypoint %d (%.1f, %.1f mm, table frame) is inside the material"
                            % (i, 1e3 * q[0], 1e3 * q[1]))
            if corners and min(math.hypot(q[0] - c[0], q[1] - c[1]) for c in corners) < radius + CORNER_EXCLUSION:
                continue
            checked += 1
            err = abs(ds[k] - radius)
            if err > worst[0]:
                worst = (err, (i, k, 1e3 * q[0], 1e3 * q[1], 1e3 * (ds[k] - radius)))
        sys.stderr.write("e2e: %d grind waypoints, %d away from corners, worst offset error %.3f mm %s\n"
                         % (len(grind), checked, 1e3 * worst[0], worst[1]))
        self.assertGreater(checked, len(grind) // 2)
        # Every ring - the outer edge and every hole - is ground all the way round: each point of the true
        # boundary (every 2 mm) has a grind waypoint of that ring within the tool radius plus a resampling step
        # and tolerance (sqrt(2) r at a concave 90 deg corner, where the offset corner is farthest).
        reach = math.sqrt(2) * radius + cfg.get("step", 0.002) + OFFSET_TOLERANCE
        for k, ring in enumerate(rings):
            self.assertTrue(per_ring[k], "%s has no grind loop" % ("the outer edge" if k == 0 else "hole %d" % k))
            for s in G.resample(ring, 0.002):
                near = min(math.hypot(s[0] - q[0], s[1] - q[1]) for q in per_ring[k])
                self.assertLessEqual(near, reach, "%s not ground near (%.1f, %.1f) mm (table frame): nearest grind "
                                     "waypoint %.1f mm away" % ("outer edge" if k == 0 else "hole %d" % k,
                                                                1e3 * s[0], 1e3 * s[1], 1e3 * near))
        # Last, so that a failure here says the loops are all there. Every ring, the slot included (it was
        # exempted at 1.5 mm until the camera bridge stopped eroding edge pixels beside dropouts and mixed
        # pixels and the planner fitted fillets).
        self.assertLessEqual(worst[0], OFFSET_TOLERANCE,
                             "offset error %.3f mm > %.1f mm at grind waypoint %d (ring %d, table frame %.1f, %.1f mm, "
                             "signed %.3f mm)" % ((1e3 * worst[0], 1e3 * OFFSET_TOLERANCE) + worst[1]))



class E2EGenicam(E2EWholePipeline):
    def test_job_done_and_path_matches_ground_truth(self):
        genicam = os.path.join(E.CONFIG, "pipeline-genicam.toml")
        device = next(p["command"] for p in E.shipped_pipeline(genicam)["process"] if p["name"] == "genicam-device")
        scene, profile = device[device.index("--scene") + 1], device[device.index("--profile") + 1]
        self.assertEqual((scene, profile), camera_scene(), "the two pipelines should show the same scene")
        tmp = tempfile.mkdtemp(prefix="hg-e2e-truth-")
        self.addCleanup(shutil.rmtree, tmp, True)
        truth = E.scene_truth(scene, profile, os.path.join(tmp, "truth.json"))
        self.pipeline = p = E.Pipeline("genicam", pipeline_file=genicam,
                                       extra_args={"planner": PLANNER_ARGS + planner_extra_args(truth)})
        p.start()
        final = self.run_job(p, "e2e-genicam-1")
        self.assert_done(final, p)
        camera_log = E.Pipeline.read(os.path.join(p.dir, "logs", "camera.log"))
        self.assertIn("opened genicam", camera_log)
        time.sleep(0.5)  # lcm-logger flushes every 100 ms
        out_dir = os.path.join(p.dir, "out")
        ov = p.overview("e2e-genicam-1", out_dir)
        self.assertEqual(ov.returncode, 0, ov.stdout + ov.stderr)
        with open(os.path.join(out_dir, "path.json")) as f:
            self.check_path_against_truth(json.load(f), truth)

class E2EKill(PipelineCase):
    # (process, the job status on which it is killed): each while it is the stage working on the job.
    PLAN = [("camera", ("hg-robot-bridge", "ACCEPTED")),   # capture requested
            ("outline", ("hg-path-planner", "PLANNING")),  # planner waits for the outline
            ("planner", ("hg-path-planner", "PLANNING")),  # planning
            ("robot", (E.ROBOT, "RUNNING")),               # robot moving
            ("dds", (E.ROBOT, "RUNNING")),                 # gateway forwarding statuses
            ("recorder", (E.ROBOT, "RUNNING"))]            # job history being written
    # A job hit by a kill ends within the pipeline's own bounds: robot path-timeout 60 s (+ margin).
    KILLED_JOB_TIMEOUT = 120

    def test_kill_each_process_mid_job(self):
        self.pipeline = p = E.Pipeline("kill", extra_args={"planner": PLANNER_ARGS})
        p.start()
        report = []
        for n, (name, (source, state)) in enumerate(self.PLAN):
            st = p.status()
            self.assertIsNotNone(st, "no supervisor status\n" + p.diagnostics())
            before = st[name]
            job = "e2e-kill-%d-%s" % (n, name)
            p.send(job, extra=JOB_ARGS)
            p.wait_status(job, lambda s: (s["source"], s["state"]) == (source, state), JOB_TIMEOUT,
                          "%s %s of %s" % (source, state, job))
            pid = before["pid"]
            self.assertIsNotNone(pid, "%s not running before the kill" % name)
            os.kill(pid, signal.SIGKILL)
            final = p.wait_final(job, self.KILLED_JOB_TIMEOUT)
            if final["state"] != "DONE":
                self.assertTrue(final["message"].strip(), "%s %s without a reason" % (job, final["state"]))
            # Restarted by the supervisor: a new pid, a restart more, running (first heartbeat) again.
            p.wait(lambda: (lambda st: st is not None and st[name]["state"] == "running" and st[name]["pid"] not in (None, pid)
                            and st[name]["restarts"] > before["restarts"])(p.status()), 60,
                   "%s restarted by the supervisor" % name)
            p.wait_all_running(60)
            if name == "robot":
                # docs/robot_bridge.md: a bridge restarted mid-job reports it ABORTED and holds FAULT until RESET.
                self.assertEqual((final["state"], final["source"]), ("ABORTED", E.ROBOT), str(final))
                self.assertIn("restarted", final["message"])
                reset = "e2e-kill-%d-reset" % n
                p.send(reset, action="reset")
                r = p.wait_status(reset, lambda s: s["source"] == E.ROBOT and s["state"] in E.FINAL, 30, "RESET answer")
                self.assertEqual(r["state"], "DONE", str(r))
            elif name in ("dds", "recorder"):
                # Not on the job's path: the job is not disturbed.
                self.assert_done(final, p)
            if name == "recorder":
                # The restarted recorder marked the job interrupted, then heard its end: nothing lost.
                rec = p.wait_record(job, lambda r: r.get("final"), 30, "the record of %s to end" % job)
                self.assertEqual(rec["state"], "DONE", str(rec))
                self.assertIn("resumed_after_interruption", rec, str(rec))
            report.append("%s: %s %s" % (name, final["state"], final["message"]))
            after = "e2e-kill-%d-after" % n
            self.assert_done(self.run_job(p, after), p)
        sys.stderr.write("e2e kill: " + "; ".join(report) + "\n")


class E2EInterruptedRun(PipelineCase):
    """`make run` (tools/run.sh) interrupted while the robot runs the job, then `make run` again."""

    def run_sh(self, p, job_id, **kw):
        env = dict(os.environ, OUT=p.dir, BIN=E.BIN)
        return [os.path.join(E.SRC, "tools", "run.sh"), "--pipeline", p.toml, "--job-id", job_id], env

    def test_run_after_an_interrupted_run_ends_done(self):
        # Only for its private pipeline file and directory: run.sh starts the pipeline itself (OUT = p.dir).
        self.pipeline = p = E.Pipeline("rerun")
        cmd, env = self.run_sh(p, "e2e-rerun-1")
        with open(os.path.join(p.dir, "run1.out"), "w") as out:
            first = subprocess.Popen(cmd, env=env, stdout=out, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                                     start_new_session=True)
            try:
                p.wait(lambda: os.path.exists(p.status_file) and
                       any(s["state"] == "RUNNING" for s in p.statuses("e2e-rerun-1")) or first.poll() is not None,
                       JOB_TIMEOUT, "the first run's robot RUNNING")
                self.assertIsNone(first.poll(), "the first run ended before it was interrupted:\n" +
                                  p.read(out.name))
                os.killpg(first.pid, signal.SIGINT)  # Ctrl-C
                first.wait(120)
            finally:
                if first.poll() is None:
                    os.killpg(first.pid, signal.SIGKILL)
                    first.wait()
        # The interrupted run left its job in the robot's state file, as a real robot's would be.
        self.assertTrue(os.path.exists(os.path.join(p.dir, "robot.state")), p.read(out.name))
        cmd, env = self.run_sh(p, "e2e-rerun-2")
        second = E.run(cmd, timeout=600, env=env)
        self.assertEqual(second.returncode, 0, "the run after an interrupted one:\n" + second.stdout + second.stderr)
        self.assertRegex(second.stdout, r"hg-robot-bridge DONE")
        self.assertNotIn("REFUSED", second.stdout)
        first_rec, second_rec = p.record("e2e-rerun-1"), p.record("e2e-rerun-2")
        self.assertEqual((first_rec["state"], first_rec["final"]), ("ABORTED", True), str(first_rec))
        self.assertEqual((second_rec["state"], second_rec["final"]), ("DONE", True), str(second_rec))
        for f in ("path.json", "outline.json", "events.jsonl"):
            self.assertTrue(os.path.exists(os.path.join(p.dir, "jobs", "e2e-rerun-2", f)), f)
        show = E.run([os.path.join(E.SRC, "tools", "hg-jobs"), "--dir", os.path.join(p.dir, "jobs"), "list"], timeout=60)
        self.assertRegex(show.stdout, r"e2e-rerun-1 .* ABORTED")
        self.assertRegex(show.stdout, r"e2e-rerun-2 .* DONE")
        # A third pipeline on the same folder, asked for the job that ended DONE: the job history (jobs-dir)
        # answers it; no second path, no second run.
        with open(os.path.join(p.dir, "jobs", "e2e-rerun-2", "events.jsonl")) as f:
            paths_before = sum(1 for line in f if json.loads(line).get("event") == "path")
        cmd, env = self.run_sh(p, "e2e-rerun-2")
        third = E.run(cmd, timeout=600, env=env)
        self.assertEqual(third.returncode, 0, third.stdout + third.stderr)
        self.assertRegex(third.stdout, r"hg-robot-bridge DONE \(answer\).*the job history holds it as DONE")
        self.assertNotRegex(third.stdout, r"PLANNED|RUNNING|ACCEPTED")
        with open(os.path.join(p.dir, "jobs", "e2e-rerun-2", "events.jsonl")) as f:
            events = [json.loads(line) for line in f]
        self.assertEqual(sum(1 for e in events if e.get("event") == "path"), paths_before)
        third_rec = p.record("e2e-rerun-2")
        self.assertEqual((third_rec["state"], third_rec["final"], third_rec["ended"]),
                         ("DONE", True, second_rec["ended"]), str(third_rec))


class E2EReplay(PipelineCase):
    def test_replay_gives_same_outline_and_path(self):
        self.pipeline = p = E.Pipeline("replay", extra_args={"planner": PLANNER_ARGS})
        p.start()
        job = "e2e-replay-1"
        self.assert_done(self.run_job(p, job), p)
        time.sleep(0.5)
        p.stop()
        live = os.path.join(p.dir, "live")
        ov = p.overview(job, live)
        self.assertEqual(ov.returncode, 0, ov.stdout + ov.stderr)

        # Fresh outline service and planner (the shipped commands), their output recorded; only the camera's
        # clouds and the job requests are played back.
        procs = []
        try:
            for name in ("outline", "planner"):
                cmd = [p._rewrite_arg(a) for a in E.process_command(name)] + (PLANNER_ARGS if name == "planner" else [])
                if "--jobs-dir" in cmd:  # a re-computation of a job the history holds as DONE: without the history
                    at = cmd.index("--jobs-dir")
                    del cmd[at:at + 2]
                if "/" not in cmd[0]:
                    cmd[0] = E.bin_path(cmd[0])
                procs.append(subprocess.Popen(cmd, cwd=p.dir, stdout=p._file("replay-%s.log" % name),
                                              stderr=subprocess.STDOUT, start_new_session=True))
            beats = E.run([E.bin_path("hg-lcm-dump"), "--channels", "^HG_HEARTBEAT$", "--type", "heartbeat_t",
                           "--timeout", "30"] + ["--count", "6"], timeout=60)
            seen = {json.loads(l)["msg"]["pid"] for l in beats.stdout.splitlines()}
            self.assertTrue(all(q.pid in seen for q in procs), "replay processes not up: %s" % beats.stdout[-500:])
            replay_log = os.path.join(p.dir, "replay.lcmlog")
            rec = subprocess.Popen([E.RECORD, replay_log], stdout=p._file("replay-record.out"), stderr=subprocess.STDOUT,
                                   start_new_session=True)
            procs.append(rec)
            p.wait(lambda: os.path.getsize(os.path.join(p.dir, "replay-record.out")) > 0, 30, "the replay recorder")
            dump = subprocess.Popen([E.bin_path("hg-lcm-dump"), "--channels", "^HG_JOB_STATUS$", "--type", "job_status_t"],
                                    stdout=p._file("replay-status.jsonl"), stderr=subprocess.DEVNULL, start_new_session=True)
            procs.append(dump)
            time.sleep(0.5)
            play = E.run(["lcm-logplayer", "--regexp=^(HG_PLATE_CLOUD|HG_JOB_REQUEST)$", p.log], timeout=120)
            self.assertEqual(play.returncode, 0, play.stderr)

            def planned():
                with open(os.path.join(p.dir, "replay-status.jsonl")) as f:
                    for line in f:
                        m = json.loads(line)["msg"]
                        if m["job_id"] == job and m["source"] == "hg-path-planner" and E.STATES[m["state"]] in ("PLANNED", "FAILED"):
                            return True
                return False
            p.wait(planned, 60, "the replayed job planned")
            time.sleep(0.5)
        finally:
            for q in reversed(procs):
                if q.poll() is None:
                    q.send_signal(signal.SIGINT)
                    try:
                        q.wait(10)
                    except subprocess.TimeoutExpired:
                        q.kill()
                        q.wait()
        replayed = os.path.join(p.dir, "replayed")
        os.makedirs(replayed)
        ov = E.run([E.bin_path("hg-overview"), replay_log, "--out", replayed, "--job-id", job, "--planner-config",
                    os.path.join(E.CONFIG, "path_planner.yaml"), "--cell",
                    G.cell_of(E.process_command("planner"), E.CONFIG)], timeout=120)
        self.assertIn(ov.returncode, (0, 1), ov.stderr)  # 1: no robot in the replay, the job is not DONE
        for name in ("outline.json", "path.json"):
            self.assertTrue(os.path.exists(os.path.join(replayed, name)), "replay gave no %s: %s" % (name, ov.stdout))
        a, b = (json.loads(E.Pipeline.read(os.path.join(d, "outline.json"))) for d in (live, replayed))
        self.assertEqual(a["status"], 0)
        self.assertEqual(len(a["loops"]), len(b["loops"]))
        for i, (la, lb) in enumerate(zip(a["loops"], b["loops"])):
            self.assertEqual(la["hole"], lb["hole"], "loop %d" % i)
            self.assertEqual(len(la["points"]), len(lb["points"]), "loop %d" % i)
            self.assert_close(la["points"], lb["points"], "outline loop %d" % i)
        a, b = (json.loads(E.Pipeline.read(os.path.join(d, "path.json"))) for d in (live, replayed))
        self.assertEqual(len(a["waypoints"]), len(b["waypoints"]))
        for i, (wa, wb) in enumerate(zip(a["waypoints"], b["waypoints"])):
            self.assertEqual(wa["kind"], wb["kind"], "waypoint %d" % i)
            self.assert_close([wa["position"], wa["orientation"], [wa["speed"]]],
                              [wb["position"], wb["orientation"], [wb["speed"]]], "waypoint %d" % i)

    def assert_close(self, a, b, what):
        for i, (pa, pb) in enumerate(zip(a, b)):
            for x, y in zip(pa, pb):
                self.assertLessEqual(abs(x - y), 1e-9, "%s, item %d: %r != %r" % (what, i, pa, pb))


class E2ETwoHosts(PipelineCase):
    # The "second host": two network namespaces created here, inside the test's own namespace
    # (tests/netns.sh), joined by a veth pair. The 10.77.0.x addresses exist only on that veth pair inside
    # these two namespaces; nothing here touches the machine's real interfaces, and the namespaces vanish
    # with their holder processes.
    URL = "udpm://239.255.76.67:7667?ttl=1"

    def setUp(self):
        self.holders = []
        # The veth pair and its 10.77.0.x addresses must only ever exist inside the test's private namespace:
        # refuse to build them in the machine's own (run through tests/netns.sh, as CTest does).
        links = E.run(["ip", "-o", "link", "show"], timeout=10).stdout.splitlines()
        names = [l.split(":")[1].strip().split("@")[0] for l in links if ":" in l]
        self.assertEqual(names, ["lo"], "E2ETwoHosts must run in a network namespace of its own, with only "
                         "loopback (tests/netns.sh python3 -m unittest ...); this one has %s" % names)

    def tearDown(self):
        super().tearDown()
        for h in self.holders:
            if h.poll() is None:
                h.kill()
                h.wait()

    def namespace(self):
        h = subprocess.Popen(["unshare", "--net", "--", "sleep", "600"], start_new_session=True)
        self.holders.append(h)
        path = "/proc/%d/ns/net" % h.pid
        end = time.monotonic() + 10
        while os.readlink(path) == os.readlink("/proc/self/ns/net"):  # unshare has not switched yet
            if time.monotonic() > end:
                self.fail("unshare --net did not make a namespace")
            time.sleep(0.02)
        return h.pid, ["nsenter", "--net=" + path, "--"]

    def sh(self, prefix, *cmd):
        out = E.run(prefix + list(cmd), timeout=30)
        self.assertEqual(out.returncode, 0, "%s: %s" % (" ".join(cmd), out.stderr))

    def probe(self, sender, receiver, url):
        """How many of 10 job requests on a probe channel, sent from `sender` with `url`, `receiver` hears."""
        dump = subprocess.Popen(receiver + [E.bin_path("hg-lcm-dump"), "--lcm-url", self.URL, "--channels", "^HG_E2E_PROBE$",
                                            "--timeout", "4"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        try:
            time.sleep(1.0)
            for i in range(10):
                E.run(sender + [E.bin_path("hg-lcm-send"), "--lcm-url", url, "job", "--job-id", "probe-%d" % i,
                                "--channel", "HG_E2E_PROBE"], timeout=20)
                time.sleep(0.1)
            out, _ = dump.communicate(timeout=30)
        finally:
            if dump.poll() is None:
                dump.kill()
                dump.wait()
        return len(out.splitlines())

    def test_camera_on_another_host(self):
        cam_pid, cam = self.namespace()
        rest_pid, rest = self.namespace()
        self.sh([], "ip", "link", "add", "hgcam0", "type", "veth", "peer", "name", "hgrest0")
        self.sh([], "ip", "link", "set", "hgcam0", "netns", str(cam_pid))
        self.sh([], "ip", "link", "set", "hgrest0", "netns", str(rest_pid))
        for prefix, dev, addr in ((cam, "hgcam0", "10.77.0.1/24"), (rest, "hgrest0", "10.77.0.2/24")):
            self.sh(prefix, "ip", "link", "set", "lo", "up")
            self.sh(prefix, "ip", "addr", "add", addr, "dev", dev)
            self.sh(prefix, "ip", "link", "set", dev, "up")
            self.sh(prefix, "ip", "route", "add", "224.0.0.0/4", "dev", dev)

        # Control: what crosses is routed multicast. A message sent in the camera namespace with ttl=0 (the
        # default URL: host-local) must not reach the other namespace; with ttl=1 it must.
        self.assertEqual(self.probe(cam, rest, "udpm://239.255.76.67:7667?ttl=0"), 0, "ttl=0 traffic crossed the veth")
        self.assertGreater(self.probe(cam, rest, self.URL), 0, "ttl=1 traffic did not cross the veth")

        # The rest of the pipeline under the supervisor in the "rest" namespace; the camera alone in its own.
        self.pipeline = p = E.Pipeline("twohost", lcm_url=self.URL, without=("camera",), netns_exec=rest,
                                         extra_args={"planner": PLANNER_ARGS})
        p.start()
        cmd = [p._rewrite_arg(a) for a in E.process_command("camera")] + ["--lcm-url", self.URL]
        camera = subprocess.Popen(cam + cmd, stdout=p._file("camera.log"),
                                  stderr=subprocess.STDOUT, start_new_session=True)
        self.holders.insert(0, camera)
        # The camera's heartbeat crosses the veth: seen in the rest namespace with the camera's pid.
        beats = E.run(rest + [E.bin_path("hg-lcm-dump"), "--lcm-url", self.URL, "--channels", "^HG_HEARTBEAT$",
                              "--type", "heartbeat_t", "--timeout", "30"] + ["--count", "40"], timeout=60)
        cam_beats = [json.loads(l)["msg"] for l in beats.stdout.splitlines()]
        cam_beats = [m for m in cam_beats if m["process"] == "hg-camera-bridge"]
        self.assertTrue(cam_beats, "no camera heartbeat crossed to the other namespace\n" + E.Pipeline.read(os.path.join(p.dir, "camera.log")))
        final = self.run_job(p, "e2e-twohost-1")
        self.assert_done(final, p)
        camera.send_signal(signal.SIGTERM)
        camera.wait(10)
        time.sleep(0.5)
        ov = p.overview("e2e-twohost-1", os.path.join(p.dir, "out"))
        self.assertEqual(ov.returncode, 0, ov.stdout + ov.stderr)
        self.assertIn("plate cloud", ov.stdout)  # the cloud, published in the camera namespace, was recorded here


if __name__ == "__main__":
    unittest.main()
