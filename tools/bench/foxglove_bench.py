#!/usr/bin/env python3
"""hg-foxglove's cost to the cell (issue 25, docs/BENCHMARKS.md "hg-foxglove"): the pipeline's stage times
with 1.59 M-point clouds at the camera's rate, with and without Foxglove viewers connected. Runs in a
network namespace of its own (tests/netns.sh; re-executes itself there).

  tools/bench/foxglove_bench.py [--runs 8] [--jobs 20] [--rate 5] [--clients 2] [--viewers-priority idle]
                                [--bootstrap 2000] [--cloud FILE] [--keep]

Each run is the shipped pipeline (config/pipeline.toml, its hg-foxglove included) under the supervisor,
with hg-bench-station-feed in place of the camera bridge: hg-gen's preset high-4 (`hg-gen --preset high-4
--noise 0.0000122 --jagged --seed 7`: 1,591,654 points, a 19 MB plate_cloud_t) published --rate times a
second from the start, as a free-running camera. The run's viewers (tools/bench/foxglove_client.js:
@foxglove/ws-protocol's client from build/npm, subscribed to every channel hg-foxglove advertises, the
full-size clouds included) connect before the first job; then --jobs jobs one after another, each to its
end (the simulated cell approves a plan that reaches every edge; one that waits for an operator is approved
here). The runs alternate 0 and --clients viewers (0, 2, 0, 2, ...), so both see the same machine.

  viewers  = in a cell a viewer (Foxglove, Lichtblick) runs on the engineer's own computer, not on the
           cell's; here the viewers are node processes on the same 2-core machine, each reading and parsing
           every message it gets (19 MB clouds as JSON). So by default they run at idle
           scheduling priority (`chrt --idle 0`, --viewers-priority idle): they get only CPU the cell leaves
           free, as a remote viewer takes none of it, and what they cost is not counted against hg-foxglove.
           What stays on the cell is hg-foxglove's work, the kernel's loopback TCP (charged partly to the
           sender) and the memory bandwidth they share. --viewers-priority normal: viewers on the cell's
           machine competing at normal priority (a worst case, not the issue's).

  stages = hg-overview's summary.json of each job on the recorded bus (what tools/run.sh writes as
           out/summary.json): capture_to_cloud_ms, cloud_to_outline_ms, outline_compute_ms, plan_ms,
           plan_compute_ms, robot_run_ms, request_to_end_ms; and plan_delivery_ms = plan_ms - plan_compute_ms
           per job (the request's and the path's way through the bus, beside 19 MB clouds). plan_ms is
           lcm-logger's receive time of the path minus that of the outline or request, plan_compute_ms the
           planner's own time (grind_path_t.compute_time). A job's sample of the outline's stages is its
           outline's: jobs planned on one outline count it once.
  ratio  = per stage the median of every sample of the runs with viewers / that of the runs without (issue
           25's target: <= 1.05), with its 95 % interval from a bootstrap that draws runs and then samples
           within each drawn run (--bootstrap rounds; the runs differ among themselves, not only their jobs),
           and the no-viewer runs' own medians over their pooled median (the spread without viewers). The
           verdict: "within 5 %" when the interval lies in 0.95-1.05, "not 5 % slower" when only its top is
           <= 1.05, "over 5 % slower" when its bottom is above 1.05, "over 5 % faster (conditions differ)"
           when its top is below 0.95, "not resolved" otherwise (more runs or jobs narrow it).
  clouds = published by the feed, recorded by lcm-logger, received by the outline service (its last
           heartbeat's `received`): a 19 MB cloud is ~13 k UDP datagrams on LCM's multicast and is sometimes
           lost; a lost one is counted and reported, not a failure (the next comes 1/rate s later).
  cpu    = hg-foxglove's CPU time during the jobs by thread (/proc/PID/task), as a share of one core:
           hg-fox-convert (the conversion, idle priority) and hg-foxglove (every other thread: LCM, heartbeat,
           the WebSocket server's writes; normal priority). The runs with viewers minus those without is what
           the viewers cost the cell's cores at normal priority in hg-foxglove (their kernel TCP work is partly
           charged there too).

The bus (95 MB/s at 5 Hz) is recorded on /dev/shm when it has room, and each run's directory is deleted
after its figures are read (--keep keeps them). Prints a table and a JSON line. A benchmark, not a test.
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
# Stages of the job's outline: jobs that follow each other faster than the outline service planned on the same
# outline, and count it once.
OUTLINE_STAGES = ("capture_to_cloud_ms", "cloud_to_outline_ms", "outline_compute_ms")
TARGET = 1.05  # issue 25: every stage within 5 % of a run without viewers


def loadavg():
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


def pipeline(E, cloud, rate, name):
    """The shipped pipeline with the feed as its camera (at `rate`), the robot 100x faster than real time."""
    import tomllib
    p = E.Pipeline(name, lcm_url=LCM_URL, without=("camera",),
                   extra_args={"planner": ["--small-hole", "skip", "--outline-timeout", "60"],
                               "robot": ["--sim-time-scale", "100", "--path-timeout", "240"]})
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


def log_clouds(path):
    """Plate cloud seqs in the LCM log and the outline service's last heartbeat `received` count."""
    seqs, received = [], None
    with open(path, "rb") as f:
        while True:
            head = f.read(28)
            if len(head) < 28:
                break
            _, _, _, clen, dlen = struct.unpack(">IqqII", head)
            channel = f.read(clen).decode(errors="replace")
            if channel == "HG_PLATE_CLOUD":
                seqs.append(struct.unpack(">q", f.read(16)[8:16])[0])
                f.seek(dlen - 16, 1)
            elif channel == "HG_HEARTBEAT":
                received = outline_received(f.read(dlen), received)
            else:
                f.seek(dlen, 1)
    return seqs, received


def outline_received(data, previous):
    from pipeline_latency import Reader
    r = Reader(data)
    r.header()
    if r.string() != "hg-outline-service":
        return previous
    r.int32(), r.int8(), r.string(), r.double()
    return r.int64()


def published(p):
    """The feed's own count ("published N clouds", its last line when it stops)."""
    text = p.read(os.path.join(p.dir, "logs", "camera.log")) if os.path.exists(
        os.path.join(p.dir, "logs", "camera.log")) else ""
    for line in reversed(text.splitlines()):
        if line.startswith("published ") and line.endswith(" clouds"):
            return int(line.split()[1])
    return None


def stage_summaries(p, jobs):
    rows = []
    for job in jobs:
        out_dir = os.path.join(p.dir, "overview", job)
        res = p.overview(job, out_dir)
        try:
            with open(os.path.join(out_dir, "summary.json")) as f:
                s = json.load(f)
        except (OSError, ValueError):
            sys.stderr.write("bench: hg-overview on %s: %s\n" % (job, res.stderr.strip()))
            continue
        row = dict(s["stages"], job=job, final=s["final_state"], points=s.get("cloud_points"))
        if "plan_ms" in row and "plan_compute_ms" in row:
            row["plan_delivery_ms"] = row["plan_ms"] - row["plan_compute_ms"]
        rows.append(row)
    return rows


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
    idle priority, hg-foxglove the rest (LCM, heartbeat, the WebSocket server's writes) at normal priority."""
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


def cpu_share(before, after, seconds):
    """Share of one core per thread name between two thread_cpu() readings."""
    return {k: round((after.get(k, 0) - before.get(k, 0)) / seconds, 4) for k in after} if seconds > 0 else {}


def one_run(E, args, cloud, index, n_clients):
    from pipeline_latency import start_clients, stop_clients
    p = pipeline(E, cloud, args.rate, "fox-%d-%d" % (index, n_clients))
    jobs = ["fox-%d-%02d" % (index, j) for j in range(args.jobs)]
    load, finals, clients, received, fox_cpu = [loadavg()], [], [], [], {}
    try:
        p.start()
        clients = start_clients(n_clients, idle=args.viewers_priority == "idle")
        time.sleep(3)  # viewers connected and subscribed, a few clouds on the bus
        load.append(loadavg())
        fox = descendant(p.supervisor.pid, "hg-foxglove")
        cpu0, t0 = thread_cpu(fox) if fox else {}, time.monotonic()
        for job in jobs:
            finals.append(run_job(E, p, job)["state"])
        fox_cpu = cpu_share(cpu0, thread_cpu(fox), time.monotonic() - t0) if fox else {}
        load.append(loadavg())
    except Exception:
        print(p.diagnostics(), flush=True)
        raise
    finally:
        received = stop_clients(clients)
        p.stop()
        for f in p.files:
            f.close()
    rows = stage_summaries(p, jobs)
    seqs, outline_got = log_clouds(p.log)
    res = {"run": index + 1, "clients": n_clients, "viewers_priority": args.viewers_priority, "jobs": len(jobs),
           "finals": finals, "loadavg": load,
           "stages": {k: statistics.median([r[k] for r in rows if k in r]) for k in STAGES
                      if any(k in r for r in rows)},
           "job_stages": rows, "clouds_published": published(p), "clouds_recorded": len(set(seqs)),
           "clouds_received_by_outline_service": outline_got,
           "log_mb": round(os.path.getsize(p.log) / 1e6), "foxglove_cpu": fox_cpu,
           "viewers": [{"messages": sum(t["messages"] for t in got.values()),
                        "mb": round(sum(t["bytes"] for t in got.values()) / 1e6),
                        "plate_points": got.get("/hg/plate/points", {}).get("messages", 0),
                        "plate_clouds": got.get("HG_PLATE_CLOUD", {}).get("messages", 0)} for got in received]}
    if args.keep:
        print("run directory: " + p.dir, flush=True)
    else:
        shutil.rmtree(p.dir, ignore_errors=True)
    return res


def print_run(r):
    top = r["clouds_published"]
    print("run %d, %d viewers (%s priority): %s; load %s; clouds published %s, recorded %d, received by the outline "
          "service %s; log %d MB" % (r["run"], r["clients"], r["viewers_priority"], ",".join(r["finals"]), " -> ".join(r["loadavg"]),
                         top, r["clouds_recorded"], r["clouds_received_by_outline_service"], r["log_mb"]))
    print("  stages (median ms): " + ", ".join("%s %.0f" % (k[:-3], v) for k, v in r["stages"].items()))
    print("  hg-foxglove's CPU during the jobs, share of a core by thread: " +
          (", ".join("%s %.3f" % kv for kv in sorted(r["foxglove_cpu"].items())) or "not found"))
    for i, v in enumerate(r["viewers"]):
        print("  viewer %d: %d messages, %d MB; /hg/plate/points %d, HG_PLATE_CLOUD %d" % (
            i + 1, v["messages"], v["mb"], v["plate_points"], v["plate_clouds"]))
    sys.stdout.flush()


def samples(run, stage):
    """A run's values of one stage: one per job, one per outline for the outline's stages."""
    values = [r[stage] for r in run["job_stages"] if stage in r]
    if stage in OUTLINE_STAGES:
        seen = {}
        for r in run["job_stages"]:
            if stage in r:
                seen.setdefault(r.get("outline_compute_ms"), r[stage])
        values = list(seen.values())
    return values


def pooled_median(groups):
    return statistics.median([v for g in groups for v in g])


def bootstrap_ratio(without, with_, rounds, rng):
    """95 % interval of pooled median (with) / pooled median (without), resampling runs and then the samples
    within each drawn run: the runs differ among themselves (the machine's state), and so does each run's job."""
    def draw(groups):
        runs = [rng.choice(groups) for _ in groups]
        return pooled_median([[rng.choice(g) for _ in g] for g in runs])
    ratios = sorted(draw(with_) / draw(without) for _ in range(rounds))
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


def ratios(runs, n, rounds=2000, seed=1):
    """Per stage: the pooled medians of all samples of each condition, their ratio, its bootstrap interval, and
    the no-viewer runs' own medians over their pooled median (how far runs without viewers differ alone)."""
    import random
    rng = random.Random(seed)
    out = {}
    for k in STAGES:
        without = [g for g in (samples(r, k) for r in runs if r["clients"] == 0) if g]
        with_ = [g for g in (samples(r, k) for r in runs if r["clients"] == n) if g]
        if not without or not with_ or pooled_median(without) <= 0:
            continue
        base = pooled_median(without)
        lo, hi = bootstrap_ratio(without, with_, rounds, rng)
        alone = [statistics.median(g) / base for g in without]
        out[k] = {"without": base, "with": pooled_median(with_), "ratio": pooled_median(with_) / base,
                  "ci95": [lo, hi], "verdict": verdict(lo, hi), "samples": [sum(map(len, without)), sum(map(len, with_))],
                  "no_viewer_runs": [min(alone), max(alone)]}
    return out


def bench(args):
    sys.path.insert(0, os.path.join(SRC, "tests", "e2e"))
    import e2e_pipeline as E
    from station_bench import make_cloud
    shm = "/dev/shm"
    if os.path.isdir(shm) and shutil.disk_usage(shm).free > 8e9:
        tempfile.tempdir = shm  # the recorded bus: 95 MB/s at 5 Hz
    tmp = tempfile.mkdtemp(prefix="hg-foxglove-bench-")
    try:
        cloud = args.cloud or make_cloud(E, tmp)
        runs = []
        for i in range(args.runs):
            runs.append(one_run(E, args, cloud, i, 0 if i % 2 == 0 else args.clients))
            print_run(runs[-1])
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    r = ratios(runs, args.clients, args.bootstrap)
    print("\nhg-foxglove benchmark: %s" % " ".join(["tools/bench/foxglove_bench.py"] + sys.argv[1:]))
    print("pooled medians of every job (of every outline for the outline's stages) per condition; 95 % interval "
          "of the ratio by bootstrap over runs and jobs; the no-viewer runs' own medians / their pooled median")
    print("%-20s %9s %9s %7s %15s %13s %13s %s" % ("stage", "0 viewers", "%d viewers" % args.clients, "ratio",
                                                "95 % interval", "samples", "0-viewer runs", "verdict"))
    for k, v in r.items():
        print("%-20s %9.2f %9.2f %7.3f %7.3f-%-7.3f %6d /%6d %6.2f-%-6.2f %s" % (
            k, v["without"], v["with"], v["ratio"], v["ci95"][0], v["ci95"][1], v["samples"][0], v["samples"][1],
            v["no_viewer_runs"][0], v["no_viewer_runs"][1], v["verdict"]))
    for n in sorted({r["clients"] for r in runs}):
        shares = [r["foxglove_cpu"] for r in runs if r["clients"] == n and r["foxglove_cpu"]]
        names = sorted({k for c in shares for k in c})
        print("hg-foxglove's CPU with %d viewers, share of a core (median of runs): %s" % (
            n, ", ".join("%s %.3f" % (k, statistics.median(c.get(k, 0) for c in shares)) for k in names) or "-"))
    print(json.dumps({"command": " ".join(["tools/bench/foxglove_bench.py"] + sys.argv[1:]), "rate_hz": args.rate,
                      "viewers_priority": args.viewers_priority,
                      "runs": runs, "ratios": r}))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    ap.add_argument("--runs", type=int, default=8, help="pipeline runs, alternating 0 and --clients viewers [8]")
    ap.add_argument("--jobs", type=int, default=20, help="jobs per run [20]")
    ap.add_argument("--rate", type=float, default=5, help="clouds per second, the camera's rate [5: the pipeline's]")
    ap.add_argument("--clients", type=int, default=2, help="viewers in every second run [2]")
    ap.add_argument("--viewers-priority", choices=("idle", "normal"), default="idle",
                    help="the viewers' scheduling priority: idle (chrt --idle 0: as if on another computer) [idle]")
    ap.add_argument("--bootstrap", type=int, default=2000, help="bootstrap rounds of each ratio's interval [2000]")
    ap.add_argument("--cloud", help="the cloud file (default: hg-gen's high-4, made in a temporary folder)")
    ap.add_argument("--keep", action="store_true", help="keep each run's directory (logs, run.lcmlog)")
    ap.add_argument("--version", action="version", version="foxglove_bench.py " + version())
    args = ap.parse_args()
    if os.environ.get("HG_IN_NETNS") != "1":
        os.execv(os.path.join(SRC, "tests", "netns.sh"),
                 [os.path.join(SRC, "tests", "netns.sh"), "/usr/bin/python3", os.path.abspath(__file__)] + sys.argv[1:])
    os.environ.setdefault("HG_BIN_DIR", os.path.join(SRC, "build", "bin"))
    bench(args)


if __name__ == "__main__":
    main()
