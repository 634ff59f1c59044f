#!/usr/bin/env python3
"""hg-foxglove's cost to the cell (issue 25, docs/BENCHMARKS.md "hg-foxglove"): the pipeline's stage times
with 1.59 M-point clouds at the camera's rate, with and without Foxglove viewers connected. Runs in a
network namespace of its own (tests/netns.sh; re-executes itself there).

  tools/bench/foxglove_bench.py [--runs 16] [--pairs 3] [--block-seconds 10] [--settle 3] [--rate 5]
                                [--clients 2] [--robot-time-scale 1000] [--viewers-priority idle]
                                [--viewer foxglove|sink] [--bootstrap 2000] [--foxglove-arg ARG ...]
                                [--viewer-exclude REGEX] [--cloud FILE] [--json FILE] [--keep]
  tools/bench/foxglove_bench.py --pool FILE [FILE ...] [--bootstrap 2000]

Each run is the shipped pipeline (config/pipeline.toml, its hg-foxglove included) under the supervisor,
with hg-bench-station-feed in place of the camera bridge: hg-gen's preset high-4 (`hg-gen --preset high-4
--noise 0.0000122 --jagged --seed 7`: 1,591,654 points, a 19 MB plate_cloud_t) published --rate times a
second from the start, as a free-running camera. A run holds --pairs pairs of blocks, each pair one block
without viewers and one with --clients of them, in turn (0 2 0 2 0 2 in one run, 2 0 2 0 2 0 in the next), so
that the two blocks of a pair see the same processes, the same machine and the same half minute: the
machine's speed drifts over minutes, and a pair's two blocks drift together. A block: the viewers (tools/bench/
foxglove_client.js: @foxglove/ws-protocol's client from build/npm, subscribed to every channel hg-foxglove
advertises, the full-size clouds included, but those --viewer-exclude matches) connect, or the last block's
leave; --settle seconds; then jobs one after another, each to its end, for --block-seconds (the simulated
cell approves a plan that reaches every edge; one that waits for an operator is approved here; the robot
--robot-time-scale times faster than real time, so that a block holds many jobs, each a sample of the
planner's stages).

  viewers  = in a cell a viewer (Foxglove, Lichtblick) runs on the engineer's own computer, not on the
           cell's; here the viewers are node processes on the same 2-core machine, each reading and parsing
           every message it gets (19 MB clouds as JSON). So by default they run at idle
           scheduling priority (`chrt --idle 0`, --viewers-priority idle) in a session whose scheduling
           group has nice 19 (docs/RUNNING.md, Priority): they get only CPU the cell leaves free, as a
           remote viewer takes none of it, and what they cost is not counted against hg-foxglove.
           What stays on the cell is hg-foxglove's work, the kernel's loopback TCP (charged partly to the
           sender) and the memory bandwidth they share. --viewers-priority normal: viewers on the cell's
           machine competing at normal priority (a worst case, not the issue's). --viewer sink: instead of
           node, tools/bench/foxglove_sink.py, a client of the same protocol that subscribes alike and only
           reads its socket (1 MiB reads, nothing parsed but frame headers): what a viewer on another computer
           leaves on the cell, its TCP connection, with the receive's copies on top.

  stages = those of hg-overview's summary.json (what tools/run.sh writes as out/summary.json), read back
           from the recorded bus: capture_to_cloud_ms, cloud_to_outline_ms, outline_compute_ms (the outline's
           stages), plan_ms, plan_compute_ms, robot_run_ms, request_to_end_ms, and plan_delivery_ms = plan_ms -
           plan_compute_ms per job (the request's and the path's way through the bus, beside 19 MB clouds: a
           part of plan_ms, not a stage of summary.json, so shown without a verdict).
           The outline service works on every cloud it can take, job or not: the outline's stages are
           sampled on every cloud and outline logged during the block (a job's own is one of them); the
           others once per job. The bus is decoded here, by hand (the fields needed, as lcmtypes/*.lcm lay
           them out); one job's stages a run are compared with hg-overview's summary.json, and a difference
           of more than 1 us stops the benchmark.
  ratio  = per stage the median of every sample of the blocks with viewers / that of the blocks without
           (issue 25's target: <= 1.05), with its 95 % interval from a bootstrap that draws pairs of blocks
           and then samples within each block of a drawn pair (--bootstrap rounds; pairs differ among
           themselves, not only their samples, and the two blocks of a pair are drawn together because they
           share their minute), and the no-viewer blocks' own medians over their pooled median (the spread
           without viewers). The verdict: "within 5 %" when the interval lies in 0.95-1.05, "not 5 % slower"
           when only its top is <= 1.05, "over 5 % slower" when its bottom is above 1.05, "over 5 % faster
           (conditions differ)" when its top is below 0.95, "not resolved" otherwise (more runs narrow it).
  clouds = published by the feed, recorded by lcm-logger, received by the outline service (its last
           heartbeat's `received`) in the whole run: a 19 MB cloud is ~13 k UDP datagrams on LCM's multicast and
           is sometimes lost; a lost one is counted and reported, not a failure (the next comes 1/rate s later).
  cpu    = hg-foxglove's CPU time during the block by thread (/proc/PID/task), as a share of one core:
           hg-fox-convert (the conversion, idle priority), hg-fox-server (the WebSocket server's writes, nice
           server-nice) and hg-foxglove (LCM, heartbeat; normal priority). And the whole machine's busy
           cores during the block (/proc/stat: every process and the kernel's interrupts), with viewers minus
           without per pair: what the viewers and their server add, wherever it runs; the machine's context
           switches and the interrupts one core sends the other to wake a thread or run a function there
           (/proc/interrupts RES, CAL); and the outline service's user and system CPU and minor page faults
           (/proc/PID/stat, its ended threads included).

The bus (95 MB/s at 5 Hz, about 8 GB a run) is recorded on /dev/shm when it has room, and each run's
directory is deleted after its figures are read (--keep keeps them). Prints each block, a table and a JSON
line (also written to --json FILE). A benchmark, not a test.
"""

import argparse
import json
import os
import shutil
import statistics
import struct
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
SRC = os.path.abspath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(SRC, "tools"))
sys.path.insert(0, HERE)
sys.dont_write_bytecode = True  # --help and --version leave no files behind
from hgversion import version  # noqa: E402

# A 16 MB plate_cloud_t arrives in ~13 k UDP fragments: a receive buffer of 4 MB (the machine's rmem_max), as
# station_bench.py.
LCM_URL = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304"
STAGES = ("capture_to_cloud_ms", "cloud_to_outline_ms", "outline_compute_ms", "plan_ms", "plan_compute_ms",
          "plan_delivery_ms", "robot_run_ms", "request_to_end_ms")
# The outline's stages: the outline service works on every cloud it can take, job or not, so each cloud and outline
# on the bus is a sample of them (a job's own is one of those).
OUTLINE_STAGES = ("capture_to_cloud_ms", "cloud_to_outline_ms", "outline_compute_ms")
TARGET = 1.05  # issue 25: every stage within 5 % of a run without viewers
# plan_delivery_ms is this benchmark's split of plan_ms, not a stage of summary.json: shown, judged under plan_ms.
NOT_JUDGED = ("plan_delivery_ms",)


def loadavg():
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


def pipeline(E, cloud, rate, robot_time_scale, name, foxglove_args=()):
    """The shipped pipeline with the feed as its camera (at `rate`), the simulated robot `robot_time_scale` times
    faster than real time."""
    import tomllib
    p = E.Pipeline(name, lcm_url=LCM_URL, without=("camera",),
                   extra_args={"foxglove": list(foxglove_args),
                               "planner": ["--small-hole", "skip", "--outline-timeout", "60"],
                               "robot": ["--sim-time-scale", str(robot_time_scale)]})
    with open(p.toml, "rb") as f:
        mine = tomllib.load(f)
    cam = {"name": "camera", "command": [E.bin_path("hg-bench-station-feed"), "--cloud", cloud, "--rate", str(rate)],
           "cwd": p.dir}
    E.write_toml(p.toml, mine["supervisor"], [cam] + mine["process"])
    p.names = ["camera"] + p.names
    return p


def run_job(E, p, job):
    """Sends one job and waits for its end; approves it when it waits for an operator."""
    p.send(job)
    s = p.wait_status(job, lambda s: s["state"] in E.FINAL or s["state"] == "AWAITING_APPROVAL", 300,
                      "job %s planned or ended" % job)
    if s["state"] == "AWAITING_APPROVAL":
        out = E.run([E.bin_path("hg-lcm-send"), "--lcm-url", LCM_URL, "approve", "--job-id", job, "--by", "bench"],
                    timeout=20)
        if out.returncode != 0:
            raise RuntimeError("hg-lcm-send approve: " + out.stderr)
    return p.wait_final(job, 300)


# ---- the recorded bus: the LCM log's events and the few fields the stages need, decoded by hand in the order
# lcmtypes/*.lcm lays them out (hg-overview's summary.json of sampled jobs checks the decoding, check_jobs) ----
SYNC = 0xEDA1DA01
WANTED = ("HG_PLATE_CLOUD", "HG_OUTLINE", "HG_GRIND_PATH", "HG_JOB_REQUEST", "HG_JOB_STATUS", "HG_HEARTBEAT")
FINAL_STATES = (4, 5, 6, 7, 10, 11, 12)  # job_status_t: DONE FAILED ABORTED REFUSED INCOMPLETE REJECTED NEEDS_RESCAN
DONE = 4


def log_events(path):
    """(channel, log utime, data) of the wanted channels; of a plate cloud only its header's seq and utime."""
    with open(path, "rb") as f:
        while True:
            head = f.read(28)
            if len(head) < 28:
                return
            sync, _, utime, clen, dlen = struct.unpack(">IqqII", head)
            if sync != SYNC:
                raise ValueError("%s: lost the LCM log's sync at byte %d" % (path, f.tell() - 28))
            channel = f.read(clen).decode(errors="replace")
            if channel == "HG_PLATE_CLOUD":
                data = f.read(24)
                f.seek(dlen - 24, 1)
            elif channel in WANTED:
                data = f.read(dlen)
            else:
                f.seek(dlen, 1)
                continue
            yield channel, utime, data


def skip_loops(r):
    """outline_t's loops (outline_loop_t: hole, n, u[n], v[n], area, perimeter)."""
    for _ in range(r.int32()):
        r.int8()
        n = r.int32()
        r.i += 16 * n + 16


def outline_fields(r):
    """outline_t after its header: cloud_seq and compute_time (seconds)."""
    cloud_seq = r.int64()
    r.i += 13 * 8 + 1 + 7 * 8  # plane (4 x 3 doubles), thickness, flange_valid, flange pose
    r.int8(), r.string(), r.double()  # status, error_text, alpha_radius
    skip_loops(r)
    r.int32(), r.int32(), r.int32(), r.string(), r.string(), r.int32(), r.int64()
    r.double(), r.double(), r.double()  # time_triangulate, time_alpha, time_loops
    return cloud_seq, r.double()


def path_fields(r):
    """grind_path_t after its header: job_id, outline_seq, revision, compute_time (seconds)."""
    job, outline_seq = r.string(), r.int64()
    r.string()
    n = r.int32()
    r.i += n * (3 * 8 + 4 * 8 + 8 + 1 + 2) + 8 + 8 + 1  # waypoints, tool_radius, tilt, flipped
    return job, outline_seq, r.int32(), r.double()


class Bus:
    """What the stages need of a recorded run, by channel."""

    def __init__(self):
        self.clouds, self.outlines, self.paths, self.requests, self.statuses = [], [], {}, {}, {}
        self.outline_service_received = None
        self.path_copies = 0  # paths the planner published again (the robot bridge had not acknowledged them)

    def add(self, channel, log, data):
        from pipeline_latency import Reader
        r = Reader(data)
        seq, utime, _ = r.header() if channel != "HG_PLATE_CLOUD" else (r.int64(), r.int64(), None)
        if channel == "HG_PLATE_CLOUD":
            self.clouds.append((seq, utime, log))
        elif channel == "HG_OUTLINE":
            self.outlines.append((seq, log) + outline_fields(r))
        elif channel == "HG_GRIND_PATH":
            job, outline_seq, revision, compute = path_fields(r)
            # As hg-overview: the last plan of the job, but a copy (the planner publishes a path again until the
            # robot bridge acknowledges it: the same seq, utime, revision and compute time) keeps the first's time.
            key = (seq, utime, revision, compute)
            if job not in self.paths or self.paths[job][3] != key:
                self.paths[job] = (outline_seq, log, compute, key)
            else:
                self.path_copies += 1
        elif channel == "HG_JOB_REQUEST":
            job, _, action = r.string(), r.string(), r.int8()
            if action == 0:  # ACTION_START
                self.requests[job] = log
        elif channel == "HG_JOB_STATUS":
            job, _, source, state = r.string(), r.string(), r.string(), r.int8()
            r.double(), r.string()
            self.statuses.setdefault(job, []).append((state, source, r.int8() != 0, log))
        elif channel == "HG_HEARTBEAT" and r.string() == "hg-outline-service":
            r.int32(), r.int8(), r.string(), r.double()
            self.outline_service_received = r.int64()


def read_bus(path):
    bus = Bus()
    for channel, log, data in log_events(path):
        bus.add(channel, log, data)
    return bus


def final_status_time(statuses):
    """The log time of the job's end as hg-overview takes it: the robot bridge's DONE or any other terminal state,
    the first one said; an answer (to a repeat or a QUERY) only when nothing else ended the job."""
    end = None
    for state, source, answer, log in statuses:
        ends = (state == DONE and source == "hg-robot-bridge") or (state in FINAL_STATES and state != DONE)
        if ends and not (end and not end[1]) and (not end or not answer):
            end = (log, answer)
    return end[0] if end else None


def last_before(items, key, limit):
    """The last (seq, ..., log) item with seq == key logged at or before limit."""
    found = None
    for it in items:
        if it[0] == key and it[-1] <= limit:
            found = it
    return found


def ms(a, b):
    return (b - a) * 1e-3


def job_stages(bus, job):
    """A job's stages as hg-overview's summary.json gives them (tools/overview/overview.cpp summary_json), and
    plan_delivery_ms = plan_ms - plan_compute_ms."""
    s, request, end = {}, bus.requests.get(job), final_status_time(bus.statuses.get(job, []))
    path = bus.paths.get(job)
    outline = last_before([(o[0], o[2], o[3], o[1]) for o in bus.outlines], path[0], path[1]) if path else None
    cloud = last_before([(c[0], c[1], c[2]) for c in bus.clouds], outline[1], outline[3]) if outline else None
    if cloud:
        s["capture_to_cloud_ms"] = ms(cloud[1], cloud[2])
        s["cloud_to_outline_ms"] = ms(cloud[2], outline[3])
    if outline:
        s["outline_compute_ms"] = outline[2] * 1e3
    if outline and path and request is not None:
        s["plan_ms"] = ms(max(outline[3], request), path[1])
    if path:
        s["plan_compute_ms"] = path[2] * 1e3
    if path and end is not None:
        s["robot_run_ms"] = ms(path[1], end)
    if request is not None and end is not None:
        s["request_to_end_ms"] = ms(request, end)
    if "plan_ms" in s:
        s["plan_delivery_ms"] = s["plan_ms"] - s["plan_compute_ms"]
    return s


def bus_stages(bus, t0, t1):
    """The outline's stages of every cloud and outline logged between t0 and t1 (log utimes): the same
    quantities as a job's, sampled on every cloud the outline service worked on, not only the jobs' own."""
    clouds = {}
    for seq, utime, log in bus.clouds:
        clouds.setdefault(seq, []).append((utime, log))
    out = {"capture_to_cloud_ms": [ms(u, l) for _, u, l in bus.clouds if t0 <= l <= t1],
           "cloud_to_outline_ms": [], "outline_compute_ms": []}
    for seq, log, cloud_seq, compute in bus.outlines:
        if not t0 <= log <= t1:
            continue
        out["outline_compute_ms"].append(compute * 1e3)
        before = [l for _, l in clouds.get(cloud_seq, []) if l <= log]
        if before:
            out["cloud_to_outline_ms"].append(ms(before[-1], log))
    return out


def check_jobs(E, p, bus, jobs):
    """hg-overview's summary.json stages of these jobs against this decoding: the same to 1 us, or the bench stops."""
    for job in jobs:
        out_dir = os.path.join(p.dir, "overview", job)
        res = p.overview(job, out_dir)
        if not os.path.exists(os.path.join(out_dir, "summary.json")):
            raise RuntimeError("bench: hg-overview wrote no summary of job %s (exit %d): %s" % (
                job, res.returncode, res.stderr.strip()))
        with open(os.path.join(out_dir, "summary.json")) as f:
            theirs = json.load(f)["stages"]
        mine = job_stages(bus, job)
        for k, v in theirs.items():
            if k not in mine or abs(mine[k] - v) > 1e-3:
                raise RuntimeError("bench: %s of job %s: hg-overview %s, this decoding %s (%s)" % (
                    k, job, v, mine.get(k), res.stderr.strip()))


# ---- blocks: a pipeline run holds one block without viewers and one with them, in the order given ----
def published(p):
    """The feed's own count ("published N clouds", its last line when it stops)."""
    path = os.path.join(p.dir, "logs", "camera.log")
    text = p.read(path) if os.path.exists(path) else ""
    for line in reversed(text.splitlines()):
        if line.startswith("published ") and line.endswith(" clouds"):
            return int(line.split()[1])
    return None


def descendant(root, comm):
    """The pid of the process named `comm` below `root` (our supervisor's hg-foxglove, not another one's)."""
    parent, name = {}, {}
    for d in filter(str.isdigit, os.listdir("/proc")):
        try:
            with open("/proc/%s/stat" % d) as f:
                text = f.read()
        except (OSError, ValueError):
            continue
        pid = int(d)
        name[pid] = text[text.index("(") + 1:text.rindex(")")]
        parent[pid] = int(text[text.rindex(")") + 2:].split()[1])
    for pid, n in name.items():
        p = pid
        while n == comm and p in parent and p > 1:
            p = parent[p]
            if p == root:
                return pid
    return None


def thread_cpu(pid):
    """CPU seconds (user + system) of a process's threads by thread name: hg-fox-convert is the conversion at
    idle priority, hg-fox-server the WebSocket server's writes (nice server-nice), hg-foxglove the rest (LCM,
    heartbeat) at normal priority."""
    out = {}
    tick = os.sysconf("SC_CLK_TCK")
    try:
        for tid in os.listdir("/proc/%d/task" % pid):
            with open("/proc/%d/task/%s/stat" % (pid, tid)) as f:
                text = f.read()
            name = text[text.index("(") + 1:text.rindex(")")]
            fields = text[text.rindex(")") + 2:].split()
            out[name] = out.get(name, 0) + (int(fields[11]) + int(fields[12])) / tick
    except (OSError, ValueError):
        pass
    return out


def process_cpu(pid):
    """A whole process's user and system CPU seconds and minor page faults (/proc/PID/stat: its threads that
    have ended included, such as the outline's strip threads)."""
    try:
        with open("/proc/%d/stat" % pid) as f:
            text = f.read()
    except OSError:
        return {}
    fields = text[text.rindex(")") + 2:].split()
    tick = os.sysconf("SC_CLK_TCK")
    return {"user": int(fields[11]) / tick, "sys": int(fields[12]) / tick, "minflt": int(fields[7])}


def cpu_share(before, after, seconds):
    """Share of one core per thread name between two thread_cpu() readings."""
    return {k: round((after.get(k, 0) - before.get(k, 0)) / seconds, 4) for k in after} if seconds > 0 else {}


def machine_counters():
    """The whole machine's counters: CPU seconds busy (/proc/stat: user, nice, system, irq, softirq, steal),
    context switches, and the interrupts one core sends another to wake a thread or run a function there
    (/proc/interrupts RES and CAL, all cores): each costs the core it lands on, whatever that core runs."""
    c = {}
    with open("/proc/stat") as f:
        for line in f:
            w = line.split()
            if w[0] == "cpu":
                c["busy"] = sum(int(w[1 + i]) for i in (0, 1, 2, 5, 6, 7)) / os.sysconf("SC_CLK_TCK")
            elif w[0] == "ctxt":
                c["ctxt"] = int(w[1])
    with open("/proc/interrupts") as f:
        for line in f:
            w = line.split()
            if w and w[0] in ("RES:", "CAL:"):
                c[w[0][:-1].lower()] = sum(int(x) for x in w[1:] if x.isdigit())
    return c


COUNTER_RATES = (("ctxt", "context switches"), ("res", "rescheduling interrupts"), ("cal", "function call interrupts"))


def run_block(E, args, p, fox, outline, tag, n_clients, pair):
    """Connects n_clients viewers, lets them settle, sends jobs for --block-seconds, disconnects them."""
    from pipeline_latency import start_clients, stop_clients
    clients, received = start_clients(n_clients, idle=args.viewers_priority == "idle", viewer=args.viewer), []
    try:
        time.sleep(args.settle)  # viewers connected and subscribed; a block without them: the last ones gone
        b = {"clients": n_clients, "pair": pair, "loadavg": [loadavg()], "jobs": [], "finals": []}
        cpu0, m0, t0, w0 = thread_cpu(fox) if fox else {}, machine_counters(), time.monotonic(), time.time()
        o0 = process_cpu(outline) if outline else {}
        while time.monotonic() - t0 < args.block_seconds:
            b["jobs"].append("%s-%03d" % (tag, len(b["jobs"])))
            b["finals"].append(run_job(E, p, b["jobs"][-1])["state"])
        b["window"] = [int(w0 * 1e6), int(time.time() * 1e6)]
        b["foxglove_cpu"] = cpu_share(cpu0, thread_cpu(fox), time.monotonic() - t0) if fox else {}
        m1, seconds = machine_counters(), time.monotonic() - t0
        o1 = process_cpu(outline) if outline else {}
        b["outline_service"] = {k: round((o1[k] - o0[k]) / seconds, 4) for k in o1 if k in o0}
        b["machine_busy"] = round((m1["busy"] - m0["busy"]) / seconds, 3)  # cores
        for k, _ in COUNTER_RATES:
            if k in m0 and k in m1:
                b[k + "_per_s"] = round((m1[k] - m0[k]) / seconds)
        b["loadavg"].append(loadavg())
    finally:
        received = stop_clients(clients)
    b["viewers"] = [{"messages": sum(t["messages"] for t in got.values()),
                     "mb": round(sum(t["bytes"] for t in got.values()) / 1e6),
                     "plate_points": got.get("/hg/plate/points", {}).get("messages", 0),
                     "plate_clouds": got.get("HG_PLATE_CLOUD", {}).get("messages", 0), "topics": got}
                    for got in received]
    return b


def block_samples(bus, b):
    """The block's samples: the outline's stages of every cloud and outline in its window, the others per job."""
    s = bus_stages(bus, *b["window"])
    rows = [job_stages(bus, job) for job in b["jobs"]]
    for k in STAGES:
        if k not in OUTLINE_STAGES:
            s[k] = [r[k] for r in rows if k in r]
    return s


def one_run(E, args, cloud, index, order):
    """One pipeline run: its blocks (viewer counts in `order`), their samples read back from the recorded bus."""
    p = pipeline(E, cloud, args.rate, args.robot_time_scale, "fox-%d" % index, args.foxglove_arg)
    blocks = []
    try:
        p.start()
        fox = descendant(p.supervisor.pid, "hg-foxglove")
        outline = descendant(p.supervisor.pid, "hg-outline-serv")  # the kernel keeps 15 characters of a name
        for k, n in enumerate(order):
            blocks.append(run_block(E, args, p, fox, outline, "fox-%d-%d" % (index, k), n,
                                    "%d-%d" % (index + 1, k // 2)))
    except Exception:
        print(p.diagnostics(), flush=True)
        raise
    finally:
        p.stop()
        for f in p.files:
            f.close()
    bus = read_bus(p.log)
    check = blocks[index % len(blocks)]["jobs"]
    check_jobs(E, p, bus, check[len(check) // 2:len(check) // 2 + 1])
    run = {"run": index + 1, "clouds_published": published(p), "clouds_recorded": len({c[0] for c in bus.clouds}),
           "clouds_received_by_outline_service": bus.outline_service_received, "path_copies": bus.path_copies,
           "log_mb": round(os.path.getsize(p.log) / 1e6)}
    for b in blocks:
        b.update(run, samples=block_samples(bus, b))
    if args.keep:
        print("run directory: " + p.dir, flush=True)
    else:
        shutil.rmtree(p.dir, ignore_errors=True)
    return blocks


def print_block(b):
    print("run %d, pair %s, %d viewers (%s priority): %d jobs (%s); load %s; clouds published %s, recorded %d, "
          "received by the outline service %s; paths published again %d; log %d MB" % (
              b["run"], b["pair"], b["clients"], b["viewers_priority"], len(b["jobs"]),
              ", ".join("%s %d" % (s, b["finals"].count(s)) for s in sorted(set(b["finals"]))),
              " -> ".join(b["loadavg"]), b["clouds_published"], b["clouds_recorded"],
              b["clouds_received_by_outline_service"], b["path_copies"], b["log_mb"]))
    print("  stages (median ms, samples): " + ", ".join(
        "%s %.1f (%d)" % (k[:-3], statistics.median(v), len(v)) for k, v in b["samples"].items() if v))
    print("  hg-foxglove's CPU during the block, share of a core by thread: " +
          (", ".join("%s %.3f" % kv for kv in sorted(b["foxglove_cpu"].items())) or "not found") +
          "; the machine busy %.3f cores" % b.get("machine_busy", float("nan")) +
          "".join(", %d %s/s" % (b[k + "_per_s"], name) for k, name in COUNTER_RATES if k + "_per_s" in b))
    o = b.get("outline_service")
    if o:
        print("  the outline service: user %.3f, system %.3f cores, %d minor page faults/s" % (
            o["user"], o["sys"], o["minflt"]))
    for i, v in enumerate(b["viewers"]):
        print("  viewer %d: %d messages, %d MB; /hg/plate/points %d, HG_PLATE_CLOUD %d" % (
            i + 1, v["messages"], v["mb"], v["plate_points"], v["plate_clouds"]))
    sys.stdout.flush()


# ---- the ratio of each stage, its interval and the verdict ----
def pooled_median(groups):
    return statistics.median([v for g in groups for v in g])


def bootstrap_ratio(pairs, rounds, rng):
    """95 % interval of pooled median (with) / pooled median (without) over pairs of blocks [(without, with)],
    resampling pairs and then the samples within each block of a drawn pair: pairs differ among themselves (the
    machine's state), the two blocks of a pair share theirs, and each sample differs."""
    def resample(g):
        return [rng.choice(g) for _ in g]

    def draw():
        drawn = [rng.choice(pairs) for _ in pairs]
        return (pooled_median([resample(w) for _, w in drawn]) /
                pooled_median([resample(wo) for wo, _ in drawn]))
    ratios = sorted(draw() for _ in range(rounds))
    return ratios[int(0.025 * rounds)], ratios[int(0.975 * rounds) - 1]


def verdict(lo, hi):
    """What the ratio's interval shows about the target, both ways: faster by more than 5 % is no harm the
    viewers did, but says that the two conditions differed in more than the viewers (the machine's load)."""
    if lo > TARGET:
        return "over 5 % slower"
    if hi < 2 - TARGET:
        return "over 5 % faster (conditions differ)"
    if hi <= TARGET:
        return "within 5 %" if lo >= 2 - TARGET else "not 5 % slower"
    return "not resolved"


def ratios(blocks, n, rounds=2000, seed=1):
    """Per stage: the pooled medians of all samples of each condition, their ratio, its bootstrap interval, and
    the no-viewer blocks' own medians over their pooled median (how far blocks without viewers differ alone)."""
    import random
    rng = random.Random(seed)
    out = {}
    for k in STAGES:
        by_pair = {}
        for b in blocks:
            if b["samples"].get(k) and b["clients"] in (0, n):
                by_pair.setdefault(b["pair"], {})[b["clients"]] = b["samples"][k]
        pairs = [(g[0], g[n]) for g in by_pair.values() if len(g) == 2]
        without, with_ = [wo for wo, _ in pairs], [w for _, w in pairs]
        if not pairs or pooled_median(without) <= 0:
            continue
        base = pooled_median(without)
        lo, hi = bootstrap_ratio(pairs, rounds, rng)
        alone = [statistics.median(g) / base for g in without]
        out[k] = {"without": base, "with": pooled_median(with_), "ratio": pooled_median(with_) / base,
                  "ci95": [lo, hi], "verdict": verdict(lo, hi) if k not in NOT_JUDGED else "(a part of plan)",
                  "samples": [sum(map(len, without)), sum(map(len, with_))],
                  "pairs": len(pairs), "no_viewer_blocks": [min(alone), max(alone)]}
    return out


def print_ratios(args, r):
    print("\nhg-foxglove benchmark: %s" % " ".join(["tools/bench/foxglove_bench.py"] + sys.argv[1:]))
    print("pooled medians per condition (every cloud and outline for the outline's stages, every job for the "
          "others), over the pairs of blocks that have samples of the stage; 95 % interval of the ratio by bootstrap "
          "over pairs and samples; the no-viewer blocks' own "
          "medians / their pooled median")
    print("%-20s %9s %9s %7s %15s %15s %13s %s" % ("stage", "0 viewers", "%d viewers" % args.clients, "ratio",
                                                "95 % interval", "samples", "0-viewer blocks", "verdict"))
    for k, v in r.items():
        print("%-20s %9.2f %9.2f %7.3f %7.3f-%-7.3f %6d /%6d %6.2f-%-6.2f %s" % (
            k, v["without"], v["with"], v["ratio"], v["ci95"][0], v["ci95"][1], v["samples"][0], v["samples"][1],
            v["no_viewer_blocks"][0], v["no_viewer_blocks"][1], v["verdict"]))


def bench(args):
    sys.path.insert(0, os.path.join(SRC, "tests", "e2e"))
    import e2e_pipeline as E
    from station_bench import make_cloud
    shm = "/dev/shm"
    if os.path.isdir(shm) and shutil.disk_usage(shm).free > 12e9:
        tempfile.tempdir = shm  # the recorded bus: 95 MB/s at 5 Hz
    tmp = tempfile.mkdtemp(prefix="hg-foxglove-bench-")
    blocks = []
    try:
        cloud = args.cloud or make_cloud(E, tmp)
        for i in range(args.runs):
            order = ((0, args.clients) if i % 2 == 0 else (args.clients, 0)) * args.pairs
            for b in one_run(E, args, cloud, i, order):
                b["viewers_priority"] = args.viewers_priority
                blocks.append(b)
                print_block(b)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    r = ratios(blocks, args.clients, args.bootstrap)
    print_ratios(args, r)
    for n in sorted({b["clients"] for b in blocks}):
        shares = [b["foxglove_cpu"] for b in blocks if b["clients"] == n and b["foxglove_cpu"]]
        names = sorted({k for c in shares for k in c})
        print("hg-foxglove's CPU with %d viewers, share of a core (median of blocks): %s" % (
            n, ", ".join("%s %.3f" % (k, statistics.median(c.get(k, 0) for c in shares)) for k in names) or "-"))
    print_busy(blocks)
    for b in blocks:
        b["samples"] = {k: [round(x, 3) for x in v] for k, v in b["samples"].items()}
    line = json.dumps({"command": " ".join(["tools/bench/foxglove_bench.py"] + sys.argv[1:]), "rate_hz": args.rate,
                       "viewers_priority": args.viewers_priority, "viewer": args.viewer, "blocks": blocks,
                       "ratios": r})
    print(line)
    if args.json:
        with open(args.json, "w") as f:
            f.write(line + "\n")


def print_busy(blocks):
    """The machine's busy cores and its counters' rates by condition (median of blocks), and the pairs' median
    difference."""
    print_machine(blocks, "machine_busy", "the machine busy, cores", "%.3f", "%+.3f")
    for k, name in COUNTER_RATES:
        print_machine(blocks, k + "_per_s", name + " a second", "%.0f", "%+.0f")
    for k, what, fmt in (("user", "cores in user mode", "%.3f"), ("sys", "cores in the kernel", "%.3f"),
                         ("minflt", "minor page faults a second", "%.0f")):
        for b in blocks:
            if k in b.get("outline_service", {}):
                b["outline_" + k] = b["outline_service"][k]
        print_machine(blocks, "outline_" + k, "the outline service's " + what, fmt, "%+" + fmt[1:])


def print_machine(blocks, key, what, fmt, diff_fmt):
    by_pair = {}
    for b in blocks:
        if key in b:
            by_pair.setdefault(b["pair"], {})[b["clients"]] = b[key]
    diffs = [v[max(v)] - v[min(v)] for v in by_pair.values() if len(v) == 2]  # with viewers minus without
    if not diffs:
        return
    medians = ", ".join(("%d viewers " + fmt) % (n, statistics.median(v[n] for v in by_pair.values() if n in v))
                        for n in sorted({n for v in by_pair.values() for n in v}))
    print(("%s (median of blocks): %s; with viewers minus without, median of %d pairs: " + diff_fmt)
          % (what, medians, len(diffs), statistics.median(diffs)))


def pool(args):
    """The ratios over the blocks of several --json files (runs of one build at different times): a pair stays
    within its file."""
    blocks = []
    for i, path in enumerate(args.pool):
        with open(path) as f:
            d = json.load(f)
        print("%s: %s" % (path, d["command"]))
        for b in d["blocks"]:
            b["pair"] = "%d:%s" % (i, b["pair"])
            blocks.append(b)
    args.clients = max(b["clients"] for b in blocks)
    print_ratios(args, ratios(blocks, args.clients, args.bootstrap))
    print_busy(blocks)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    ap.add_argument("--runs", type=int, default=16,
                    help="pipeline runs, each --pairs pairs of blocks, which condition first alternating [16]")
    ap.add_argument("--pairs", type=int, default=3,
                    help="pairs of blocks a run: one without viewers and one with them each [3]")
    ap.add_argument("--block-seconds", type=float, default=10, help="seconds of jobs in each block [10]")
    ap.add_argument("--settle", type=float, default=3,
                    help="seconds between connecting (or disconnecting) the viewers and the block's first job [3]")
    ap.add_argument("--rate", type=float, default=5, help="clouds per second, the camera's rate [5: the pipeline's]")
    ap.add_argument("--clients", type=int, default=2, help="viewers in the blocks with viewers [2]")
    ap.add_argument("--robot-time-scale", type=float, default=1000,
                    help="the simulated robot's speed-up (more jobs, so more plans, a block) [1000]")
    ap.add_argument("--viewer", choices=("foxglove", "sink"), default="foxglove",
                    help="foxglove: @foxglove/ws-protocol's client on node (foxglove_client.js); sink: a client that "
                    "only reads its socket, as a viewer on another computer costs the cell (foxglove_sink.py)")
    ap.add_argument("--viewers-priority", choices=("idle", "normal"), default="idle",
                    help="the viewers' scheduling priority: idle (chrt --idle 0 in a session of nice 19: as if on "
                         "another computer) [idle]")
    ap.add_argument("--foxglove-arg", action="append", default=[],
                    help="an argument added to hg-foxglove's command line (repeat; e.g. "
                         "--foxglove-arg=--server-nice=0)")
    ap.add_argument("--bootstrap", type=int, default=2000, help="bootstrap rounds of each ratio's interval [2000]")
    ap.add_argument("--cloud", help="the cloud file (default: hg-gen's high-4, made in a temporary folder)")
    ap.add_argument("--viewer-exclude", metavar="REGEX",
                    help="the viewers do not subscribe to the topics this matches (a diagnosis: which topics cost)")
    ap.add_argument("--json", help="also write the JSON line (every block's samples, the ratios) to this file")
    ap.add_argument("--keep", action="store_true", help="keep each run's directory (logs, run.lcmlog)")
    ap.add_argument("--pool", nargs="+", metavar="FILE",
                    help="run nothing: the ratios over the blocks of these --json files (runs of one build)")
    ap.add_argument("--version", action="version", version="foxglove_bench.py " + version())
    args = ap.parse_args()
    if args.pool:
        return pool(args)
    if os.environ.get("HG_IN_NETNS") != "1":
        os.execv(os.path.join(SRC, "tests", "netns.sh"),
                 [os.path.join(SRC, "tests", "netns.sh"), "/usr/bin/python3", os.path.abspath(__file__)] + sys.argv[1:])
    os.environ.setdefault("HG_BIN_DIR", os.path.join(SRC, "build", "bin"))
    if args.viewer_exclude:
        os.environ["HG_VIEWER_EXCLUDE"] = args.viewer_exclude  # read by foxglove_client.js
    bench(args)


if __name__ == "__main__":
    main()
