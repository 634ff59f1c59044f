#!/usr/bin/env python3
"""Checks that the include graph points down the layers (README.md, "Layers").

Every #include of a file of this tree, from a file outside tests/, must name a file of the same or a lower
layer; a process folder must not include another process folder. Exit 0 when clean, 1 with one line per
offending include (file:line: what and why), 2 on bad usage.

    check_layers.py [--root DIR]   # DIR: the source tree (default: this file's ../..)

In a git work tree the files are `git ls-files`; elsewhere every file below DIR (the self-test uses that).
"""
import argparse
import os
import re
import subprocess
import sys

# Bottom to top. Folders of one layer may include each other, except the processes (see PROCESSES).
LAYERS = [
    ("ground", ["lcmtypes", "runtime", "jobs", "path_file", "camera_types", "polygon", "motion", "cell"]),
    ("outline core", ["outline_core"]),
    ("outline io", ["outline_io"]),
    ("simulation", ["sim"]),
    ("processes", ["camera_bridge", "outline_service", "path_planner", "robot_bridge", "dds_gateway",
                   "job_recorder", "station"]),
    ("calibration", ["calibration"]),
    ("tools", ["tools", "foxglove"]),
]
PROCESSES = set(LAYERS[4][1])
EXEMPT = {"tests"}  # tests may include anything
# One include convention: a file of the tree is included by its path from the tree's root
# ("sim/partgen/shapes.hpp", "camera_bridge/segment.hpp") or, within its own folder, by its name. There are
# no other include roots: an include spelled from a folder's own include directory names no file here.
INCLUDE_ROOTS = []
# Generated headers: include prefix -> the folder that generates them.
GENERATED = {"hullgrind/": "lcmtypes", "hullgrind.h": "dds_gateway", "hg_lcm_registry.inc": "tools",
             "camera_sources.inc": "camera_bridge"}
SOURCE_EXT = (".c", ".cc", ".cpp", ".cxx", ".h", ".hh", ".hpp", ".hxx", ".inc", ".ipp")
INCLUDE_RE = re.compile(r'^\s*#\s*include\s*([<"])([^">]+)[">]')

LAYER_OF = {folder: (i, name) for i, (name, folders) in enumerate(LAYERS) for folder in folders}


def list_files(root):
    try:
        out = subprocess.run(["git", "-C", root, "ls-files", "-z"], check=True, capture_output=True).stdout
        return [f for f in out.decode().split("\0") if f]
    except (subprocess.CalledProcessError, FileNotFoundError):
        files = []
        for d, _, names in os.walk(root):
            files += [os.path.relpath(os.path.join(d, n), root) for n in names]
        return files


def top_folder(path):
    return path.split("/", 1)[0] if "/" in path else ""


def resolve(root, files, including, target):
    """The tree path `target` names when included from `including`, or None (system or unknown)."""
    for prefix, folder in GENERATED.items():
        if target.startswith(prefix):
            return folder + "/" + target
    here = os.path.dirname(including)
    for base in [here, ""] + INCLUDE_ROOTS:
        candidate = os.path.normpath(os.path.join(base, target)).replace(os.sep, "/")
        if candidate in files:
            return candidate
    return None


def violation(src, dst):
    """Why src may not include dst, or None when it may."""
    a, b = top_folder(src), top_folder(dst)
    if a in EXEMPT or a == b:
        return None
    if a not in LAYER_OF:
        return f"{a or src} is in no layer (add it to LAYERS in tests/layers/check_layers.py)"
    if b not in LAYER_OF:
        return f"{a} includes tests/ (only tests may)" if b in EXEMPT else f"{b} is in no layer"
    (la, na), (lb, nb) = LAYER_OF[a], LAYER_OF[b]
    if a in PROCESSES and b in PROCESSES:
        return f"process folder {a} includes another process folder, {b}"
    if lb > la:
        return f"{a} ({na}) includes {b} ({nb}), a higher layer"
    return None


def check(root):
    files = [f.replace(os.sep, "/") for f in list_files(root)]
    known = set(files)
    problems = []
    # Every folder with source files has a layer, even one that includes nothing of the tree yet.
    unlayered = sorted({top_folder(f) for f in files if f.endswith(SOURCE_EXT)} - set(LAYER_OF) - EXEMPT)
    for folder in unlayered:
        problems.append(f"{folder or '(the top folder)'}/: source files in no layer (add the folder to LAYERS in "
                        "tests/layers/check_layers.py)")
    for f in sorted(files):
        if not f.endswith(SOURCE_EXT) or top_folder(f) in EXEMPT:
            continue
        try:
            with open(os.path.join(root, f), encoding="utf-8", errors="replace") as fh:
                lines = fh.readlines()
        except OSError as e:
            problems.append(f"{f}: cannot read ({e.strerror})")
            continue
        for n, line in enumerate(lines, 1):
            m = INCLUDE_RE.match(line)
            if not m:
                continue
            quoted, target = m.group(1) == '"', m.group(2)
            dst = resolve(root, known, f, target)
            if dst is None and quoted:  # a quoted include is ours: unresolved means an include root is missing
                problems.append(f"{f}:{n}: #include \"{target}\" names no file of the tree (spell it from the tree's root, or add its "
                                "generated prefix to tests/layers/check_layers.py)")
                continue
            why = dst and violation(f, dst)
            if why:
                spelled = f'"{target}"' if quoted else f"<{target}>"
                problems.append(f"{f}:{n}: #include {spelled} ({dst}): {why}")
    return problems


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--root", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
    args = ap.parse_args()
    root = os.path.abspath(args.root)
    if not os.path.isdir(root):
        print(f"check_layers: --root {root} is not a folder", file=sys.stderr)
        return 2
    problems = check(root)
    for p in problems:
        print(p)
    print(f"check_layers: {len(problems)} include(s) against the layers in {root}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
