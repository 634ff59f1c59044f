#!/usr/bin/env python3
"""Pipeline latency benchmark (issue 8): depth frame -> published grind path, with every process of
config/pipeline.toml running on this machine under tools/supervisor, in a network namespace of its own.

  tools/bench/pipeline_latency.py [--profile pm806|lsr-l ...] [--frames 50] [--bin BUILD/bin] [--keep]
                                  [--foxglove-clients N]

For each profile: the shipped pipeline with the camera on the synthetic source of that profile in job
trigger mode (it renders a frame when a job asks, so no renderer runs in the background and steals CPU
from the pipeline), the planner with small-hole: skip (a noisy
frame's few-pixel gap would otherwise fail the job and leave no path to time), the robot simulated 100x
faster than real time (only so that 50 jobs fit in a few
minutes; the robot is idle while the next frame is processed either way). Jobs are sent one after another,
each outline_max_age + 0.5 s after the previous one ended (DONE, or REFUSED by the robot: its path counts), so the planner
waits for the new frame's outline instead of reusing the previous one. The bus is recorded and read back
here (LCM log format and the few header fields needed, decoded by hand):

  latency  = log time of grind_path_t - plate_cloud_t.header.utime of the cloud that path was planned
             from (path.outline_seq -> outline.cloud_seq -> cloud), i.e. capture -> published path;
  render   = cloud logged - cloud utime - the camera's own processing time (heartbeat last_latency:
             segmentation + publish). The synthetic source stamps header.utime once the frame is rendered
             (as a camera stamps a frame it has captured; the rendering stands in for exposure and transfer),
             so this is ~0 now; before commit 8369fa6 it stamped before rendering and the render was in here;
  stages   = cloud utime -> cloud logged (segmentation + send), cloud -> outline logged (outline
             service), outline -> path logged (planner).

--foxglove-clients N connects N Foxglove viewers to the pipeline's hg-foxglove (tools/bench/foxglove_client.js:
@foxglove/ws-protocol's client from build/npm, subscribed to every channel, the full-size clouds included)
before the first job: the stage times with and without them are the live server's cost (issue 25).

Prints medians (and 90th percentiles) per profile, the load average before and after, and a JSON line.
Targets (issue 8): median <= 60 ms at 1280x960 (pm806), <= 250 ms at 2048x1536 (lsr-l). Not a test.
"""

import argparse
import json
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
SRC = os.path.abspath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(SRC, "tools"))
sys.dont_write_bytecode = True  # --help and --version leave no files behind
from hgversion import version  # noqa: E402
sys.path.insert(0, os.path.join(SRC, "tests", "e2e"))  # the e2e tests' pipeline driver (same owner)

TARGET_MS = {"pm806": 60.0, "lsr-l": 250.0}
SIZE = {"pm806": "1280x960", "lsr-l": "2048x1536"}
# The profiles' mounting heights above the table (sim/scene/scene.cpp): the planner's hand-eye
# calibration must say where the camera hangs, or the lsr-l plate lands below the table and is refused.
MOUNT_HEIGHT = {"pm806": 1.5, "lsr-l": 2.0}


# ---- LCM log file: events of sync word, event number, utime, channel length, data length ----
def read_log(path, channels):
    out = []
    with open(path, "rb") as f:
        while True:
            head = f.read(28)
            if len(head) < 28:
                break
            sync, _, utime, clen, dlen = struct.unpack(">IqqII", head)
            if sync != 0xEDA1DA01:
                raise ValueError("%s: lost LCM log sync at byte %d" % (path, f.tell() - 28))
            channel = f.read(clen).decode()
            if channel in channels:
                out.append((channel, utime, f.read(dlen)))
            else:
                f.seek(dlen, 1)
    return out


class Reader:
    """Big-endian LCM fields after the 8-byte fingerprint; nested structs have no fingerprint."""

    def __init__(self, data):
        self.d, self.i = data, 8

    def _take(self, fmt):
        value = struct.unpack_from(fmt, self.d, self.i)[0]
        self.i += struct.calcsize(fmt)
        return value

    def int64(self):
        return self._take(">q")

    def int32(self):
        return self._take(">i")

    def int8(self):
        return self._take(">b")

    def double(self):
        return self._take(">d")

    def string(self):
        n = self.int32()
        self.i += n
        return self.d[self.i - n:self.i - 1].decode()

    def header(self):
        return self.int64(), self.int64(), self.string()  # seq, utime, frame_id


def decode_events(events):
    clouds, outlines, paths, requests, beats = {}, {}, {}, {}, []
    for channel, log_utime, data in events:
        r = Reader(data)
        seq, utime, _ = r.header()
        if channel == "HG_PLATE_CLOUD":
            clouds[seq] = {"utime": utime, "log": log_utime}
        elif channel == "HG_OUTLINE":
            outlines[seq] = {"cloud_seq": r.int64(), "log": log_utime}
        elif channel == "HG_GRIND_PATH":
            job = r.string()
            paths[job] = {"outline_seq": r.int64(), "log": log_utime}
        elif channel == "HG_JOB_REQUEST":
            job = r.string()
            r.string()
            if r.int8() == 0:
                requests[job] = log_utime
        elif channel == "HG_HEARTBEAT":
            process = r.string()
            if process == "hg-camera-bridge":
                r.int32(), r.int8(), r.string()
                r.double()
                received, published, _, _ = r.int64(), r.int64(), r.int64(), r.int64()
                beats.append({"log": log_utime, "published": published, "latency": r.double()})
    return clouds, outlines, paths, requests, beats


def percentile(xs, q):
    xs = sorted(xs)
    if not xs:
        return float("nan")
    k = (len(xs) - 1) * q
    lo = int(k)
    hi = min(lo + 1, len(xs) - 1)
    return xs[lo] + (xs[hi] - xs[lo]) * (k - lo)


def loadavg():
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


def idle_session():
    """preexec_fn: a session of its own whose scheduling group (Linux autogroup) has nice 19. The kernel shares
    the CPU between sessions first, so `chrt --idle` alone would leave the viewers a session's full share
    (docs/RUNNING.md, Priority)."""
    os.setsid()
    try:
        with open("/proc/self/autogroup", "w") as f:
            f.write("19\n")
    except OSError:
        pass  # no autogroups: SCHED_IDLE alone is idle


def start_clients(n, idle=False, viewer="foxglove"):
    """n Foxglove viewers on ws://127.0.0.1:8765, each subscribed to every channel once advertised; idle: at
    idle scheduling priority (`chrt --idle 0`) in a session of nice 19, so that they use only CPU the cell
    leaves free, as if on another computer. viewer: "foxglove" is @foxglove/ws-protocol's client on node
    (foxglove_client.js), "sink" a client that only reads its socket (foxglove_sink.py)."""
    npm = os.environ.get("HG_NPM_DIR", os.path.join(SRC, "build", "npm"))
    env = dict(os.environ, NODE_PATH=os.path.join(npm, "node_modules"))
    chrt = ["chrt", "--idle", "0"] if idle else []
    command = ([sys.executable, os.path.join(HERE, "foxglove_sink.py")] if viewer == "sink" else
               ["node", os.path.join(HERE, "foxglove_client.js")])
    return [subprocess.Popen(chrt + command, stdout=subprocess.PIPE, text=True,
                             env=env, preexec_fn=idle_session if idle else None) for _ in range(n)]


def stop_clients(clients):
    """What each client received: {topic: {messages, bytes}}."""
    got = []
    for c in clients:
        c.terminate()
        out, _ = c.communicate(timeout=30)
        got.append(json.loads(out.strip().splitlines()[-1]) if out.strip() else {})
    return got


def bench_profile(E, profile, frames, warmup, n_clients=0):
    """Runs the jobs; returns the pipeline (its run directory holds run.lcmlog), the measured job ids and
    the load averages before and after."""
    import tomllib
    # The simulated cell (config/cell-sim.yaml) with this profile's camera height, for the planner and the robot.
    with open(os.path.join(E.CONFIG, "cell-sim.yaml")) as f:
        cell_text = f.read()
    row = "    - [0, 0, -1, 1.5]"
    assert row in cell_text, "config/cell-sim.yaml: the camera row this bench rewrites is not there"
    cell = os.path.join(tempfile.gettempdir(), "hg-bench-cell-%s-%d.yaml" % (profile, os.getpid()))
    with open(cell, "w") as f:
        f.write(cell_text.replace(row, "    - [0, 0, -1, %r]" % MOUNT_HEIGHT[profile]))
    p = E.Pipeline("bench-" + profile, without=("camera",),
                   extra_args={"robot": ["--sim-time-scale", "100", "--cell", cell],
                               "planner": ["--small-hole", "skip", "--cell", cell]})
    # The camera first, as in the shipped file, on the synthetic source of this profile.
    with open(p.toml, "rb") as f:
        mine = tomllib.load(f)
    cam = dict(next(q for q in E.shipped_pipeline()["process"] if q["name"] == "camera"))
    cam["command"] = ["hg-camera-bridge", "--source", "synthetic", "--synthetic.scene", "plate-hole-slot",
                      "--synthetic.profile", profile, "--trigger", "job", "--parts", "largest"]
    cam["cwd"] = p.dir
    E.write_toml(p.toml, mine["supervisor"], [cam] + mine["process"])
    p.names = ["camera"] + p.names
    load_before = loadavg()
    jobs = ["bench-%s-%03d" % (profile, i) for i in range(warmup + frames)]
    clients = []
    try:
        p.start()
        clients = start_clients(n_clients)
        time.sleep(2 if clients else 0)  # connected and subscribed before the first job
        for job in jobs:
            p.send(job)
            final = p.wait_final(job, 120)
            if final["state"] != "DONE":
                sys.stderr.write("bench: %s ended %s: %s\n" % (job, final["state"], final["message"]))
            # The planner reuses an outline younger than outline_max_age (2 s): this job's outline came
            # before its final status, so 2.5 s from here it is too old and the next job waits for its own.
            time.sleep(2.5)
        time.sleep(0.5)  # lcm-logger flushes every 100 ms
    finally:
        load_after = loadavg()
        received = stop_clients(clients)
        p.stop()
        for f in p.files:
            f.close()
    for i, got in enumerate(received):
        points = got.get("/hg/plate/points", {})
        print("foxglove client %d: %d messages, %.0f MB; /hg/plate/points %d, HG_PLATE_CLOUD %d" % (
            i + 1, sum(t["messages"] for t in got.values()), sum(t["bytes"] for t in got.values()) / 1e6,
            points.get("messages", 0), got.get("HG_PLATE_CLOUD", {}).get("messages", 0)))
    return p, jobs[warmup:], load_before, load_after


def analyse(log, jobs):
    clouds, outlines, paths, requests, beats = decode_events(
        read_log(log, {"HG_PLATE_CLOUD", "HG_OUTLINE", "HG_GRIND_PATH", "HG_JOB_REQUEST", "HG_HEARTBEAT"}))
    rows = []
    for job in jobs:
        path = paths.get(job)
        if path is None or path["outline_seq"] not in outlines:
            continue
        outline = outlines[path["outline_seq"]]
        cloud = clouds.get(outline["cloud_seq"])
        if cloud is None or job not in requests or cloud["log"] < requests[job]:
            continue  # planned on an older frame than the job's own: not a frame -> path latency
        # The camera's processing time of this frame: its first heartbeat after the cloud was logged.
        beat = next((b for b in beats if b["log"] >= cloud["log"] and b["latency"] >= 0), None)
        ms = lambda a, b: (b - a) * 1e-3
        row = {"job": job, "latency": ms(cloud["utime"], path["log"]),
               "cloud": ms(cloud["utime"], cloud["log"]), "outline": ms(cloud["log"], outline["log"]),
               "plan": ms(outline["log"], path["log"])}
        row["render"] = row["cloud"] - beat["latency"] * 1e3 if beat else float("nan")
        rows.append(row)
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--version", action="version", version="pipeline_latency " + version())
    ap.add_argument("--profile", action="append", choices=sorted(TARGET_MS), help="camera profile(s) [both]")
    ap.add_argument("--frames", type=int, default=50, help="measured frames (jobs) per profile [50]")
    ap.add_argument("--warmup", type=int, default=2, help="jobs before the measured ones, not counted [2]")
    ap.add_argument("--bin", default=os.path.join(SRC, "build", "bin"), help="the build's bin directory [build/bin]")
    ap.add_argument("--keep", action="store_true", help="keep the run directories (logs, run.lcmlog)")
    ap.add_argument("--foxglove-clients", type=int, default=0,
                    help="Foxglove viewers connected to hg-foxglove during the jobs [0]")
    a = ap.parse_args()
    if os.environ.get("HG_IN_NETNS") != "1":  # LCM stays in a namespace of its own
        os.execv(os.path.join(SRC, "tests", "netns.sh"), [os.path.join(SRC, "tests", "netns.sh"), sys.executable] + sys.argv)
    os.environ["HG_BIN_DIR"] = os.path.abspath(a.bin)
    import e2e_pipeline as E
    results = []
    for profile in a.profile or ["pm806", "lsr-l"]:
        p, jobs, before, after = bench_profile(E, profile, a.frames, a.warmup, a.foxglove_clients)
        rows = analyse(p.log, jobs)
        if a.keep:
            print("run directory: " + p.dir)
        else:
            shutil.rmtree(p.dir, ignore_errors=True)
        med = {k: percentile([r[k] for r in rows], 0.5) for k in ("latency", "render", "cloud", "outline", "plan")}
        p90 = percentile([r["latency"] for r in rows], 0.9)
        res = {"profile": profile, "size": SIZE[profile], "foxglove_clients": a.foxglove_clients, "frames": len(rows), "of": len(jobs),
               "median_ms": round(med["latency"], 1), "p90_ms": round(p90, 1),
               "median_render_ms": round(med["render"], 1),
               "median_without_render_ms": round(percentile([r["latency"] - r["render"] for r in rows], 0.5), 1),
               "median_stage_ms": {k: round(med[k], 1) for k in ("cloud", "outline", "plan")},
               "target_ms": TARGET_MS[profile], "loadavg_before": before, "loadavg_after": after}
        results.append(res)
        print("%-6s %-9s frames %2d/%2d  latency median %6.1f ms (p90 %6.1f)  of which synthetic render %5.1f ms;"
              " without render %6.1f ms  [target %.0f ms]" % (profile, SIZE[profile], len(rows), len(jobs), med["latency"], p90,
                                                              med["render"], res["median_without_render_ms"], TARGET_MS[profile]))
        print("       stages (medians): capture->cloud logged %.1f ms, cloud->outline %.1f ms, outline->path %.1f ms;"
              " load average %s before, %s after" % (med["cloud"], med["outline"], med["plan"], before, after))
        sys.stdout.flush()
    print(json.dumps(results))


if __name__ == "__main__":
    main()
