#!/usr/bin/env python3
"""The plan stage of every job of a recorded bus in its parts (docs/BENCHMARKS.md, "hg-foxglove"): where
summary.json's plan_ms goes.

  tools/bench/plan_stage_parts.py RUN.lcmlog [RUN.lcmlog ...]

plan_ms is lcm-logger's receive time of the path minus that of the request (or of the outline, when it came
after the request). The planner's statuses on the same bus split it: request -> PLANNING (the request's way to
the planner, which answers PLANNING first), PLANNING -> PLANNED (the planning), PLANNED -> path (the path's
way to the logger: PLANNED is published just before it); and the planner's own compute time, which the
path carries (grind_path_t.compute_time). Receive times are lcm-logger's (the kernel's time stamp of the
datagram on the logger's socket), so a part can come out negative when one message's stamp is late. Prints
one line per job and the median, minimum and maximum of each part; reads the log only.
"""

import argparse
import os
import statistics
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))
sys.path.insert(0, HERE)
sys.dont_write_bytecode = True  # --help and --version leave no files behind
from hgversion import version  # noqa: E402
from pipeline_latency import read_log  # noqa: E402

PLANNER = "hg-path-planner"
START, PLANNING, PLANNED = 0, 1, 2
PARTS = ("plan_ms", "request_to_planning_ms", "planning_to_planned_ms", "compute_ms", "planned_to_path_ms")


def path_compute_time(r):
    """grind_path_t after job_id: outline_seq, frame, n waypoints (position, orientation, speed, kind,
    loop_index), tool_radius, tilt, flipped, revision, compute_time."""
    r.int64(), r.string()
    n = r.int32()
    r.i += n * (3 * 8 + 4 * 8 + 8 + 1 + 2) + 8 + 8 + 1 + 4
    return r.double()


def job_times(path):
    from pipeline_latency import Reader
    jobs, outline = {}, None
    for channel, t, data in read_log(path, ("HG_JOB_REQUEST", "HG_JOB_STATUS", "HG_GRIND_PATH", "HG_OUTLINE")):
        r = Reader(data)
        r.header()
        if channel == "HG_OUTLINE":
            outline = t
            continue
        j = jobs.setdefault(r.string(), {})
        if channel == "HG_JOB_REQUEST":
            r.string()
            if r.int8() == START:
                j.setdefault("request", t)
                j.setdefault("outline", outline)
        elif channel == "HG_GRIND_PATH":
            j.setdefault("path", t)
            j.setdefault("compute", path_compute_time(r) * 1e3)
        else:
            r.string()  # part_id
            if r.string() == PLANNER:
                j.setdefault({PLANNING: "planning", PLANNED: "planned"}.get(r.int8(), "other"), t)
    return jobs


def parts(j):
    ms = lambda a, b: (j[b] - j[a]) / 1e3  # noqa: E731
    start = "request" if j["outline"] is None or j["outline"] <= j["request"] else "outline"
    return (ms(start, "path"), ms("request", "planning"), ms("planning", "planned"), j["compute"],
            ms("planned", "path"))


def report(path):
    print(path)
    rows = []
    for job, j in job_times(path).items():
        if all(k in j for k in ("request", "planning", "planned", "path", "compute")):
            rows.append(parts(j))
            print("  %-12s " % job + "  ".join("%s %7.2f" % (k, v) for k, v in zip(PARTS, rows[-1])))
    for i, k in enumerate(PARTS):
        v = [r[i] for r in rows]
        if v:
            print("  %-24s median %7.2f  min %7.2f  max %7.2f  (%d jobs)" % (k, statistics.median(v), min(v), max(v),
                                                                         len(v)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    ap.add_argument("logs", nargs="+", metavar="RUN.lcmlog", help="recorded buses (foxglove_bench.py --keep keeps them)")
    ap.add_argument("--version", action="version", version="plan_stage_parts.py " + version())
    for path in ap.parse_args().logs:
        report(path)


if __name__ == "__main__":
    main()
