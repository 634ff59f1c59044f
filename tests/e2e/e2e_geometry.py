"""The expected grind path, derived without the planner: the scene's ground truth polygons (table frame)
are carried to the robot base frame through the truth's camera pose and the planner's configured
hand-eye calibration, and a waypoint of a correct path lies one tool radius outside the material
(outside the outer edge, inside a hole). Plain Python (no numpy in the test environment)."""

import math
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


def pose_xyz_rpy(xyz, rpy):
    """R = Rz(yaw) Ry(pitch) Rx(roll), as docs/path_planner.md states for camera_xyz + camera_rpy."""
    cr, sr = math.cos(rpy[0]), math.sin(rpy[0])
    cp, sp = math.cos(rpy[1]), math.sin(rpy[1])
    cy, sy = math.cos(rpy[2]), math.sin(rpy[2])
    r = [[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
         [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
         [-sp, cp * sr, cp * cr]]
    return [r[0] + [xyz[0]], r[1] + [xyz[1]], r[2] + [xyz[2]], [0.0, 0.0, 0.0, 1.0]]


# ---- the planner's configuration, read independently of the planner's code ----
def read_yaml_scalars(path):
    """Top-level `key: value` lines of a YAML file (numbers, [lists], strings)."""
    out = {}
    with open(path) as f:
        for line in f:
            m = re.match(r"^([A-Za-z_][\w-]*)\s*:\s*(.+?)\s*$", line)
            if not m:
                continue
            key, val = m.group(1), m.group(2).split(" #")[0].strip()
            if val.startswith("["):
                out[key] = [float(x) for x in val.strip("[]").split(",")]
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
