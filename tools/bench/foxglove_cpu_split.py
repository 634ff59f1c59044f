#!/usr/bin/env python3
"""Where the CPU goes in foxglove_bench's blocks with and without viewers: a system-wide `perf` sample
profile split by the blocks' windows (docs/BENCHMARKS.md, "hg-foxglove", "Who takes the outline
service's CPU").

  perf record -a -e cpu-clock -F 250 -k CLOCK_MONOTONIC -o perf.data -- \\
      tools/bench/foxglove_bench.py --runs 1 --pairs 2 --block-seconds 40 --json blocks.json
  perf script -i perf.data -F comm,tid,time,ip,sym,dso > samples.txt
  tools/bench/foxglove_cpu_split.py blocks.json samples.txt [--hz 250] [--top 20]

Prints, per thread name (perf's comm) and per (thread, function), the share of a core in the blocks
without viewers and with them, largest change first, and the outline service's CPU per outline computed.
The blocks' windows are wall-clock times (the bench's JSON); the samples are CLOCK_MONOTONIC, so run this
on the machine that recorded them, before it reboots (the offset between the two clocks is read now)."""
import argparse
import collections
import json
import os
import re
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
sys.dont_write_bytecode = True  # --help and --version leave no files behind
from hgversion import version  # noqa: E402

SAMPLE = re.compile(r"^\s*(.+?)\s+(\d+)\s+([\d.]+):\s+[0-9a-f]+\s+(.*?)\s+\((.*)\)\s*$")


def windows(blocks_json):
    """(start, end, clients) of each block on CLOCK_MONOTONIC, and the outlines each condition computed."""
    offset = time.time() - time.monotonic()
    with open(blocks_json) as f:
        blocks = json.load(f)["blocks"]
    wins = [(b["window"][0] / 1e6 - offset, b["window"][1] / 1e6 - offset, b["clients"]) for b in blocks]
    outlines = collections.Counter()
    for b in blocks:
        outlines[b["clients"]] += len(b["samples"]["outline_compute_ms"])
    return wins, outlines


def count(samples_txt, wins):
    by_comm = collections.defaultdict(collections.Counter)
    by_sym = collections.defaultdict(collections.Counter)
    with open(samples_txt, errors="replace") as f:
        for line in f:
            m = SAMPLE.match(line)
            if not m:
                continue
            comm, _, t, sym, dso = m.groups()
            t = float(t)
            for start, end, clients in wins:
                if start <= t < end:
                    by_comm[clients][comm] += 1
                    by_sym[clients][(comm, sym, dso.rsplit("/", 1)[-1])] += 1
    return by_comm, by_sym


def table(counts, seconds, hz, top, name):
    without, with_ = sorted(counts)[0], sorted(counts)[-1]
    keys = set(counts[without]) | set(counts[with_])
    share = {k: (counts[without][k] / seconds[without] / hz, counts[with_][k] / seconds[with_] / hz) for k in keys}
    rows = sorted(keys, key=lambda k: share[k][1] - share[k][0])
    print("%-70s %9s %9s %8s" % (name, "%d viewers" % without, "%d viewers" % with_, "change"))
    shown = rows[::-1][:top] + (rows[:5][::-1] if len(rows) > top + 5 else rows[:max(0, len(rows) - top)][::-1])
    for k in shown:  # the largest rises, then the largest falls, each row once
        label = k if isinstance(k, str) else "%s %s (%s)" % k
        print("%-70s %9.3f %9.3f %+8.3f" % (label[:70], share[k][0], share[k][1], share[k][1] - share[k][0]))
    return share


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("blocks_json")
    ap.add_argument("samples_txt")
    ap.add_argument("--hz", type=float, default=250, help="perf record's -F [250]")
    ap.add_argument("--top", type=int, default=20, help="rows of each table [20]")
    ap.add_argument("--version", action="version", version="foxglove_cpu_split.py " + version())
    a = ap.parse_args()
    wins, outlines = windows(a.blocks_json)
    seconds = collections.Counter()
    for start, end, clients in wins:
        seconds[clients] += end - start
    by_comm, by_sym = count(a.samples_txt, wins)
    if len(by_comm) != 2:
        sys.exit("foxglove_cpu_split: no samples in the blocks of both conditions (a perf file of another run?)")
    share = table(by_comm, seconds, a.hz, a.top, "thread (share of a core)")
    print()
    table(by_sym, seconds, a.hz, a.top, "thread, function (library)")
    for i, clients in enumerate(sorted(by_comm)):
        cpu = share.get("hg-outline-serv", (0, 0))[i] * seconds[clients]
        print("outline service, %d viewers: %d outlines, %.3f s of CPU each" % (clients, outlines[clients],
                                                                              cpu / max(1, outlines[clients])))


if __name__ == "__main__":
    main()
