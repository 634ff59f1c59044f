#!/usr/bin/env python3
"""Writes the binary and grid fixtures of tests/outline_io (the small text ones are written by hand).

Independent of the C++ readers: plain `struct` packing from the format descriptions.
Run from anywhere: python3 tests/data/outline_io/make_fixtures.py
"""
import math
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))

# Six known points, integer or binary-fraction values so every type below stores them exactly.
KNOWN = [(0.0, 0.0, 1.0), (10.0, 0.0, 1.0), (10.0, 10.0, 1.5), (0.0, 10.0, 2.0), (5.0, 2.5, -3.0), (2.0, 8.0, 0.25)]


def write(name, data):
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(data)


def lzf_literal_runs(raw):
    """LZF stream made only of literal runs (control byte = length - 1, at most 32 bytes per run)."""
    out = bytearray()
    for i in range(0, len(raw), 32):
        chunk = raw[i:i + 32]
        out.append(len(chunk) - 1)
        out += chunk
    return bytes(out)


def pcd_header(fields, sizes, types, counts, n, data):
    return ("# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\n"
            f"FIELDS {' '.join(fields)}\nSIZE {' '.join(map(str, sizes))}\nTYPE {' '.join(types)}\n"
            f"COUNT {' '.join(map(str, counts))}\nWIDTH {n}\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\n"
            f"POINTS {n}\nDATA {data}\n").encode()


def known_pcd_binary():
    # x float32, an rgb-like uint32, y double, a 3-float normal, z int16*0.25? no: z float32.
    fields, sizes, types, counts = ["x", "rgb", "y", "normal", "z"], [4, 4, 8, 4, 4], ["F", "U", "F", "F", "F"], [1, 1, 1, 3, 1]
    recs = b""
    for i, (x, y, z) in enumerate(KNOWN):
        recs += struct.pack("<fIdffff", x, 0xFF0000 + i, y, float("nan"), 0.0, 1.0, z)  # NaN in a skipped field
    write("known_binary.pcd", pcd_header(fields, sizes, types, counts, len(KNOWN), "binary") + recs)
    # binary_compressed: the same fields, one field after the other (x[], rgb[], y[], normal[], z[]).
    soa = b"".join(struct.pack("<f", p[0]) for p in KNOWN)
    soa += b"".join(struct.pack("<I", 0xFF0000 + i) for i in range(len(KNOWN)))
    soa += b"".join(struct.pack("<d", p[1]) for p in KNOWN)
    soa += b"".join(struct.pack("<fff", 0.0, 0.0, 1.0) for _ in KNOWN)
    soa += b"".join(struct.pack("<f", p[2]) for p in KNOWN)
    comp = lzf_literal_runs(soa)
    write("known_compressed.pcd",
          pcd_header(fields, sizes, types, counts, len(KNOWN), "binary_compressed") + struct.pack("<II", len(comp), len(soa)) + comp)


def known_ply_binary():
    # An element before the vertices, vertex with a list property inside, faces after.
    head = ("ply\nformat binary_little_endian 1.0\ncomment written by make_fixtures.py\n"
            "element camera 1\nproperty float focal\nproperty list uchar int ids\n"
            f"element vertex {len(KNOWN)}\nproperty double x\nproperty uchar red\nproperty float y\n"
            "property list uchar float extra\nproperty int z\n"
            "element face 2\nproperty list uchar int vertex_indices\nproperty uchar flags\nend_header\n").encode()
    body = struct.pack("<fB3i", 525.0, 3, 7, 8, 9)
    for i, (x, y, z) in enumerate(KNOWN):
        # z as int: only whole numbers survive, so this file stores z rounded down towards zero.
        body += struct.pack("<dBf", x, 200 + i, y) + struct.pack("<B", i % 3) + struct.pack("<%df" % (i % 3), *([1.5] * (i % 3)))
        body += struct.pack("<i", int(z))
    body += struct.pack("<B3iB", 3, 0, 1, 2, 0) + struct.pack("<B4iB", 4, 0, 2, 3, 4, 1)
    write("known_binary.ply", head + body)


def grid_square_with_hole(spacing=1.0, size=20, hole=(6, 14)):
    """Square [0, size]^2 on a grid, without the points strictly inside the square hole [6, 14]^2:
    outer area size^2, hole area (14 - 6)^2, boundaries on grid lines."""
    pts = []
    for j in range(size + 1):
        for i in range(size + 1):
            if hole[0] < i < hole[1] and hole[0] < j < hole[1]:
                continue
            pts.append((i * spacing, j * spacing))
    return pts


def grid_files():
    pts = grid_square_with_hole()
    write("grid_hole.xyz", ("# square 20 x 20 with a square hole 8 x 8, grid spacing 1\n" +
                            "".join(f"{x:g} {y:g}\n" for x, y in pts)).encode())
    write("grid_hole.csv", ("x,y,z\r\n" + "".join(f"{x:g}, {y:g}, 3.5\r\n" for x, y in pts)).encode())
    n = len(pts)
    write("grid_hole_ascii.pcd", pcd_header(["x", "y", "z"], [4, 4, 4], ["F", "F", "F"], [1, 1, 1], n, "ascii") +
          "".join(f"{x:g} {y:g} 0\n" for x, y in pts).encode())
    write("grid_hole_binary.pcd", pcd_header(["x", "y"], [8, 8], ["F", "F"], [1, 1], n, "binary") +
          b"".join(struct.pack("<dd", x, y) for x, y in pts))
    soa = b"".join(struct.pack("<f", x) for x, _ in pts) + b"".join(struct.pack("<f", y) for _, y in pts)
    comp = lzf_literal_runs(soa)
    write("grid_hole_compressed.pcd", pcd_header(["x", "y"], [4, 4], ["F", "F"], [1, 1], n, "binary_compressed") +
          struct.pack("<II", len(comp), len(soa)) + comp)
    write("grid_hole_ascii.ply", (f"ply\nformat ascii 1.0\nelement vertex {n}\nproperty float x\nproperty float y\n"
                                  "element face 1\nproperty list uchar int vertex_indices\nend_header\n" +
                                  "".join(f"{x:g} {y:g}\n" for x, y in pts) + "3 0 1 2\n").encode())
    write("grid_hole_binary.ply", (f"ply\nformat binary_little_endian 1.0\nelement vertex {n}\nproperty float x\n"
                                   "property float y\nproperty float z\nend_header\n").encode() +
          b"".join(struct.pack("<fff", x, y, 0.0) for x, y in pts))
    # Tilted copy: the plane through the origin rotated 30 deg about x then 20 deg about z, lifted by
    # (100, 200, 300). In-plane distances are kept, so the loop areas stay 400 and 64.
    a, b = math.radians(30), math.radians(20)

    def rot(x, y):
        x1, y1, z1 = x, y * math.cos(a), y * math.sin(a)
        return (x1 * math.cos(b) - y1 * math.sin(b) + 100, x1 * math.sin(b) + y1 * math.cos(b) + 200, z1 + 300)
    write("grid_hole_tilted.xyz", "".join("%.17g %.17g %.17g\n" % rot(x, y) for x, y in pts).encode())
    # Truncated binary file for the command-line error test: header says n points, data stops halfway.
    full = pcd_header(["x", "y"], [8, 8], ["F", "F"], [1, 1], n, "binary") + b"".join(struct.pack("<dd", x, y) for x, y in pts)
    write("grid_hole_truncated.pcd", full[:len(full) - 16 * (n // 2)])


if __name__ == "__main__":
    known_pcd_binary()
    known_ply_binary()
    grid_files()
