#!/usr/bin/env python3
"""hg-foxglove's cost to the cell (issue 25, docs/BENCHMARKS.md "hg-foxglove"): the pipeline's stage times
with 1.59 M-point clouds at the camera's rate, with and without Foxglove viewers connected. Runs in a
network namespace of its own (tests/netns.sh; re-executes itself there).

  tools/bench/foxglove_bench.py [--runs 4] [--jobs 5] [--rate 5] [--clients 2] [--viewers-priority idle]
                                [--cloud FILE] [--keep]

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
           robot_run_ms, request_to_end_ms. Per run the median over its jobs; per stage the median of the
           runs with viewers / the median of the runs without (issue 25's target: <= 1.05).
  clouds = published by the feed, recorded by lcm-logger, received by the outline service (its last
           heartbeat's `received`): a 19 MB cloud is ~13 k UDP datagrams on LCM's multicast and is sometimes
           lost; a lost one is counted and reported, not a failure (the next comes 1/rate s later).

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
STAGES = ("capture_to_cloud_ms", "cloud_to_outline_ms", "outline_compute_ms", "plan_ms", "robot_run_ms",
          "request_to_end_ms")


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
        rows.append(dict(s["stages"], job=job, final=s["final_state"], points=s.get("cloud_points")))
    return rows


def one_run(E, args, cloud, index, n_clients):
    from pipeline_latency import start_clients, stop_clients
    p = pipeline(E, cloud, args.rate, "fox-%d-%d" % (index, n_clients))
    jobs = ["fox-%d-%02d" % (index, j) for j in range(args.jobs)]
    load, finals, clients, received = [loadavg()], [], [], []
    try:
        p.start()
        clients = start_clients(n_clients, idle=args.viewers_priority == "idle")
        time.sleep(3)  # viewers connected and subscribed, a few clouds on the bus
        load.append(loadavg())
        for job in jobs:
            finals.append(run_job(E, p, job)["state"])
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
           "log_mb": round(os.path.getsize(p.log) / 1e6),
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
    for i, v in enumerate(r["viewers"]):
        print("  viewer %d: %d messages, %d MB; /hg/plate/points %d, HG_PLATE_CLOUD %d" % (
            i + 1, v["messages"], v["mb"], v["plate_points"], v["plate_clouds"]))
    sys.stdout.flush()


def ratios(runs, n):
    out = {}
    for k in STAGES:
        without = [r["stages"][k] for r in runs if r["clients"] == 0 and k in r["stages"]]
        with_ = [r["stages"][k] for r in runs if r["clients"] == n and k in r["stages"]]
        if without and with_ and statistics.median(without) > 0:
            out[k] = {"without": statistics.median(without), "with": statistics.median(with_),
                      "ratio": statistics.median(with_) / statistics.median(without)}
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
    r = ratios(runs, args.clients)
    print("\nhg-foxglove benchmark: %s" % " ".join(["tools/bench/foxglove_bench.py"] + sys.argv[1:]))
    print("%-22s %12s %12s %8s" % ("stage (median of runs)", "0 viewers", "%d viewers" % args.clients, "ratio"))
    for k, v in r.items():
        print("%-22s %12.1f %12.1f %8.3f" % (k, v["without"], v["with"], v["ratio"]))
    print(json.dumps({"command": " ".join(["tools/bench/foxglove_bench.py"] + sys.argv[1:]), "rate_hz": args.rate,
                      "viewers_priority": args.viewers_priority,
                      "runs": runs, "ratios": r}))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    ap.add_argument("--runs", type=int, default=4, help="pipeline runs, alternating 0 and --clients viewers [4]")
    ap.add_argument("--jobs", type=int, default=5, help="jobs per run [5]")
    ap.add_argument("--rate", type=float, default=5, help="clouds per second, the camera's rate [5: the pipeline's]")
    ap.add_argument("--clients", type=int, default=2, help="viewers in every second run [2]")
    ap.add_argument("--viewers-priority", choices=("idle", "normal"), default="idle",
                    help="the viewers' scheduling priority: idle (chrt --idle 0: as if on another computer) [idle]")
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
