#!/usr/bin/env python3
"""Loops of hg-outline on the 18 hg-gen presets against hg-gen's truth (docs/outline-auto-radius.md).

Usage: preset_loops.py DIR [HG_OUTLINE_OPTION ...]
DIR holds <preset>.pcd and <preset>.pcd.truth.json from `hg-gen --all DIR ...`. For each preset: runs
build/bin/hg-outline (or $HG_OUTLINE) with the given options, writes DIR/<preset>.json and prints the
regularity q = nn_spacing_median / spacing, R / h, truth and found loops (outer + holes), spurious holes
(a hole loop containing no truth hole's centroid) and missed truth holes. The presets' holes are convex,
so a truth hole's centroid lies inside it.
"""
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), ".."))
sys.dont_write_bytecode = True  # --help and --version leave no files behind
from hgversion import version  # noqa: E402

PRESETS = [f"{group}-{i}" for group in ("low", "down", "high") for i in range(1, 7)]


def inside(ring, p):
    """Even-odd point in polygon."""
    result = False
    for i in range(len(ring)):
        a, b = ring[i], ring[i - 1]
        if (a[1] > p[1]) != (b[1] > p[1]) and p[0] < a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]):
            result = not result
    return result


def centroid(ring):
    area = cx = cy = 0.0
    for i in range(len(ring)):
        (x0, y0), (x1, y1) = ring[i - 1], ring[i]
        w = x0 * y1 - x1 * y0
        area, cx, cy = area + w, cx + (x0 + x1) * w, cy + (y0 + y1) * w
    return cx / (3 * area), cy / (3 * area)


def score(directory, name, options, binary):
    cloud = os.path.join(directory, name + ".pcd")
    with open(cloud + ".truth.json") as f:
        truth = json.load(f)
    truth_holes = [centroid(h) for part in truth["parts"] for h in part["holes"]]
    out = os.path.join(directory, name + ".json")
    subprocess.run([binary, cloud, "-o", out] + options, check=True, stdout=subprocess.DEVNULL)
    with open(out) as f:
        res = json.load(f)
    outers = sum(1 for loop in res["loops"] if not loop["hole"])
    holes = [loop["points"] for loop in res["loops"] if loop["hole"]]
    hit = [any(inside(ring, c) for ring in holes) for c in truth_holes]
    spurious = sum(1 for ring in holes if not any(inside(ring, c) for c in truth_holes))
    right = outers == len(truth["parts"]) and spurious == 0 and all(hit)
    h = res["spacing"]
    print(f"| {name} | {res['points_used']} | {res['nn_spacing_median'] / h:.3f} | {res['alpha_radius'] / h:.2f} | "
          f"{len(truth['parts'])} + {len(truth_holes)} | {outers} + {len(holes)} | {spurious} | "
          f"{hit.count(False)} | {res['holes_dropped']} | {'right' if right else 'WRONG'} |", flush=True)
    return right


def main():
    if len(sys.argv) >= 2 and sys.argv[1] in ("--help", "-h"):
        print(__doc__)
        return 0
    if len(sys.argv) >= 2 and sys.argv[1] == "--version":
        print("preset_loops " + version())
        return 0
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    binary = os.environ.get("HG_OUTLINE", "build/bin/hg-outline")
    print("| preset | points | q | R / h | truth | found | spurious | missed | dropped | |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    right = sum(score(sys.argv[1], name, sys.argv[2:], binary) for name in PRESETS)
    print(f"\n{right} / {len(PRESETS)} right")


if __name__ == "__main__":
    main()
