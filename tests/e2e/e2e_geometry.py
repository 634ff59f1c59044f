"""The expected grind path, derived without the planner: the scene's ground truth polygons (table frame)
are carried to the robot base frame through the truth's camera pose and the planner's configured
hand-eye calibration, and a waypoint of a correct path lies one tool radius outside the material
(outside the outer edge, inside a hole). Plain Python (no numpy in the test environment)."""

import math
import os
import re


# ---- small linear algebra on 4x4 row-major lists ----
def matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def rigid_inverse(t):
    r = [[t[j][i] for j in range(3)] for i in range(3)]  # R^T
    p = [-sum(r[i][k] * t[k][3] for k in range(3)) for i in range(3)]
    return [r[0] + [p[0]], r[1] + [p[1]], r[2] + [p[2]], [0.0, 0.0, 0.0, 1.0]]


def apply(t, p):
    return [sum(t[i][k] * p[k] for k in range(3)) + t[i][3] for i in range(3)]


# ---- the planner's configuration and the cell file, read independently of the product's code ----
def read_yaml_scalars(path):
    """Top-level `key: value` lines of a YAML file (numbers, [lists], strings)."""
    out = {}
    with open(path) as f:
        for line in f:
            m = re.match(r"^([A-Za-z_][\w-]*)\s*:\s*(.+?)\s*$", line)
            if not m:
                continue
            key, val = m.group(1), m.group(2).split(" #")[0].strip()
            if val.startswith("["):  # numbers, or names (path-modifiers)
                items = [x.strip() for x in val.strip("[]").split(",")]
                try:
                    out[key] = [float(x) for x in items]
                except ValueError:
                    out[key] = items
            else:
                try:
                    out[key] = float(val)
                except ValueError:
                    out[key] = val.strip('"')
    return out


def planner_settings(yaml_path, command):
    """Config file values, overridden by `--key value` of the planner's command line (lists as a,b,c)."""
    cfg = read_yaml_scalars(yaml_path)
    for i, a in enumerate(command[:-1]):
        if a.startswith("--") and a != "--config":
            key, val = a[2:], command[i + 1]
            try:
                cfg[key] = [float(x) for x in val.split(",")] if "," in val else float(val)
            except ValueError:
                cfg[key] = val  # a word (e.g. --small-hole skip)
    return cfg


def read_cell(path):
    """The cell file's calibration.camera-to-base (4 rows) and tool radius and tilt, read line by line
    (docs/cell.md's layout as config/cell.yaml writes it), independently of the product's reader."""
    rows, tool, section = [], {}, None
    with open(path) as f:
        for line in f:
            text = line.split("#")[0].rstrip()
            if not text.strip():
                continue
            indent = len(text) - len(text.lstrip())
            if indent == 0:
                section = text.split(":")[0]
            elif text.strip().endswith(":"):
                section = section.split(".")[0] + "." + text.strip()[:-1]
            elif section == "calibration.camera-to-base" and text.strip().startswith("- ["):
                rows.append([float(x) for x in text.strip()[2:].strip("[]").split(",")])
            elif section == "tool":
                key, val = text.strip().split(":")
                tool[key.strip()] = float(val)
    if len(rows) != 4 or not all(len(r) == 4 for r in rows) or set(tool) != {"radius", "tilt"}:
        raise ValueError("%s: no camera-to-base rows or tool radius/tilt where docs/cell.md puts them" % path)
    return {"camera-to-base": rows, "tool-radius": tool["radius"], "tool-tilt": tool["tilt"]}


def cell_of(command, config_dir):
    """The cell file a process command names with --cell (relative paths: the pipeline file's folder)."""
    path = command[command.index("--cell") + 1]
    return path if os.path.isabs(path) else os.path.join(config_dir, path)


# ---- planar geometry ----
def seg_dist(p, a, b):
    ax, ay = b[0] - a[0], b[1] - a[1]
    L2 = ax * ax + ay * ay
    t = 0.0 if L2 == 0 else max(0.0, min(1.0, ((p[0] - a[0]) * ax + (p[1] - a[1]) * ay) / L2))
    dx, dy = a[0] + t * ax - p[0], a[1] + t * ay - p[1]
    return math.hypot(dx, dy)


def ring_dist(p, ring):
    n = len(ring)
    return min(seg_dist(p, ring[i], ring[(i + 1) % n]) for i in range(n))


def inside(p, ring):
    c = False
    n = len(ring)
    for i in range(n):
        a, b = ring[i], ring[(i + 1) % n]
        if (a[1] > p[1]) != (b[1] > p[1]):
            x = a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1])
            if x > p[0]:
                c = not c
    return c


def corners(ring, min_turn):
    """Vertices where the boundary turns by at least min_turn (radians): a polygonised circle's vertices
    turn by a few degrees and are not corners."""
    out = []
    n = len(ring)
    for i in range(n):
        a, b, c = ring[i - 1], ring[i], ring[(i + 1) % n]
        h1 = math.atan2(b[1] - a[1], b[0] - a[0])
        h2 = math.atan2(c[1] - b[1], c[0] - b[0])
        turn = abs((h2 - h1 + math.pi) % (2 * math.pi) - math.pi)
        if turn >= min_turn:
            out.append(b)
    return out


def resample(ring, spacing):
    out = []
    n = len(ring)
    for i in range(n):
        a, b = ring[i], ring[(i + 1) % n]
        L = math.hypot(b[0] - a[0], b[1] - a[1])
        k = max(1, int(math.ceil(L / spacing)))
        out += [(a[0] + (b[0] - a[0]) * j / k, a[1] + (b[1] - a[1]) * j / k) for j in range(k)]
    return out
