#!/usr/bin/env python3
"""lint_channels: the bus is the one table of runtime/channels.hpp.

- No channel name of the table ("HG_PLATE_CLOUD") is written as a string literal in the C++ code outside
  runtime/channels.hpp (tests excepted: they are readers of their own), and no publish() or subscribe() names
  its channel by a literal: the code says channels::kPlateCloud.
- Every publish(channels::kX ...) and subscribe(channels::kX ...) of a process or tool folder below is in the
  row of that channel: its name (PARTICIPANTS) among the row's publishers, or subscribers.

    check-channels.py [ROOT]      # ROOT: the source tree (default: this file's ../..)

Exit 0 when clean, 1 with one line per finding (file:line: what), 2 on bad usage. In a git work tree the files
are `git ls-files`; elsewhere every file below ROOT (the self-test uses that).
"""
import os
import re
import subprocess
import sys

TABLE = "runtime/channels.hpp"
EXEMPT = ("tests/",)
CPP = (".cpp", ".hpp", ".h", ".cc", ".inc")
# Folder -> the name its row spells (substring of the publishers / subscribers text). hg-lcm-send and the
# benchmarks (tools/lcm_tools, tools/bench) publish on any channel they are told: not checked.
PARTICIPANTS = {
    "camera_bridge/": "camera_bridge",
    "outline_service/": "outline_service",
    "path_planner/": "path_planner",
    "robot_bridge/": "robot_bridge",
    "dds_gateway/": "dds_gateway",
    "job_recorder/": "job_recorder",
    "station/": "station",
    "foxglove/": "hg-foxglove",
    "tools/calibrate/": "hg-calibrate",
    "runtime/": "every process",
}
CONSTANT_RE = re.compile(r'inline\s+constexpr\s+const\s+char\s*\*\s*(k\w+)\s*=\s*"([^"]+)"')
# {kName, "type", "publishers...", "subscribers...", "what..."}: adjacent literals are one string, as in C++.
ROW_RE = re.compile(r'\{\s*(k\w+)\s*,\s*((?:"(?:[^"\\]|\\.)*"\s*)+),\s*((?:"(?:[^"\\]|\\.)*"\s*)+),\s*'
                    r'((?:"(?:[^"\\]|\\.)*"\s*)+),')
LITERAL_RE = re.compile(r'"((?:[^"\\\n]|\\.)*)"')
CALL_RE = re.compile(r'\b(publish|subscribe)\s*(?:<[^;{}()]*?>)?\s*\(\s*(?:hg::)?(?:channels|ch)::(k\w+)')
LITERAL_CALL_RE = re.compile(r'\b(publish|subscribe)\s*(?:<[^;{}()]*?>)?\s*\(\s*"')


def joined(literals):
    return "".join(m.group(1) for m in LITERAL_RE.finditer(literals))


def read_table(root):
    with open(os.path.join(root, TABLE), encoding="utf-8") as f:
        text = f.read()
    names = dict(CONSTANT_RE.findall(text))
    rows = {}
    for m in ROW_RE.finditer(text):
        rows[m.group(1)] = {"publish": joined(m.group(3)), "subscribe": joined(m.group(4))}
    return names, rows


def list_files(root):
    try:
        out = subprocess.run(["git", "-C", root, "ls-files", "-z"], check=True, capture_output=True).stdout
        return [f for f in out.decode().split("\0") if f]
    except (subprocess.CalledProcessError, FileNotFoundError):
        return [os.path.relpath(os.path.join(d, n), root) for d, _, ns in os.walk(root) for n in ns]


def participant(path):
    return next((name for folder, name in PARTICIPANTS.items() if path.startswith(folder)), None)


def check_file(path, text, names, rows):
    problems = []
    channel_names = set(names.values())
    for n, line in enumerate(text.splitlines(), 1):
        for m in LITERAL_RE.finditer(line):
            if m.group(1) in channel_names:
                problems.append(f"{path}:{n}: channel name \"{m.group(1)}\" as a literal: use its constant "
                                f"from {TABLE}")
    for m in LITERAL_CALL_RE.finditer(text):
        problems.append(f"{path}:{text.count(chr(10), 0, m.start()) + 1}: {m.group(1)}() names its channel by a "
                        f"literal: use a constant of {TABLE}")
    who = participant(path)
    for m in CALL_RE.finditer(text):
        verb, const = m.group(1), m.group(2)
        line = text.count("\n", 0, m.start()) + 1
        if const not in rows:
            problems.append(f"{path}:{line}: channels::{const} has no row in {TABLE}")
        elif who and who not in rows[const][verb]:
            role = "publishers" if verb == "publish" else "subscribers"
            problems.append(f"{path}:{line}: {who} {verb}es {names.get(const, const)}, but the channel's row in "
                            f"{TABLE} does not name it among the {role}")
    return problems


def check(root):
    names, rows = read_table(root)
    problems = [f"{TABLE}: {k} ({v}) has no row in kTable" for k, v in names.items() if k not in rows]
    for f in sorted(list_files(root)):
        if not f.endswith(CPP) or f == TABLE or f.startswith(EXEMPT):
            continue
        try:
            with open(os.path.join(root, f), encoding="utf-8", errors="replace") as fh:
                text = fh.read()
        except OSError as e:
            problems.append(f"{f}: cannot read ({e.strerror})")
            continue
        problems += check_file(f, text, names, rows)
    return problems


def main(argv):
    if len(argv) > 2 or (len(argv) == 2 and argv[1] in ("-h", "--help")):
        print(__doc__.strip())
        return 0 if len(argv) == 2 else 2
    if len(argv) == 2 and argv[1] == "--version":
        sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
        import hgversion
        print("check-channels.py " + hgversion.version())
        return 0
    root = os.path.abspath(argv[1] if len(argv) == 2 else os.path.join(os.path.dirname(__file__), "..", ".."))
    if not os.path.isfile(os.path.join(root, TABLE)):
        print(f"check-channels: {root} holds no {TABLE}", file=sys.stderr)
        return 2
    problems = check(root)
    for p in problems:
        print(p)
    print(f"check-channels: {len(problems)} finding(s) in {root}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
