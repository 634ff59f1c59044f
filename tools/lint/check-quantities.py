#!/usr/bin/env python3
"""One name and one range per quantity (issue 26 §1): fails on a second declaration outside runtime/quantities.hpp.

The job quantities (tool_radius, tilt, grind_speed, travel_speed, step, safe_height), the waypoint kinds and the
travel directions are declared once, in runtime/quantities.hpp, and every reader uses that table. This check
scans the product sources (every tracked C++, IDL, Python and shell file outside tests/ and docs/) and names
each line that declares one again:
  - a job quantity as a parameter with its own range: number_param("tool-radius", ...) and the like
    (runtime::quantity_param takes the range from the table);
  - the tilt's old names (chamfer-angle, chamfer_angle: a chamfer is a cut corner, not the tool's tilt) and
    the planner's base-frame, except where that moved key is declared ({"base-frame", "frames.base"}: refused
    naming where it lives now);
  - a limit of a quantity written as a literal: 80 * M_PI / 180, 1.396..., a max_tool_radius or
    max_chamfer_angle field;
  - the waypoint kind list ("lead_in" as a string) or the direction names ("conventional") as text;
  - a Direction enum.
Usage: check-quantities.py [ROOT] (default: the repository holding this script). Exit 1 naming each line.
--help, --version answer.
"""
import os
import re
import subprocess
import sys

HOME = "runtime/quantities.hpp"
KEYS = "tool-radius|tilt|grind-speed|travel-speed|step|safe-height"
RULES = [
    (re.compile(r'number_param\(\s*"(' + KEYS + r')"'), "a job quantity declared with its own range: use "
     "runtime::quantity_param (" + HOME + ")"),
    (re.compile(r'"(chamfer-angle|chamfer_angle)"|"base-frame"(?!\s*,\s*"frames\.base")'),
     "an old name: the tilt is `tilt`, the base frame the cell's frames.base"),
    (re.compile(r'\bchamfer_angle\b'), "an old name: the tilt is `tilt`"),
    (re.compile(r'80\s*\*\s*M_PI|1\.39626|1\.0472|\bmax_tool_radius\b|\bmax_chamfer_angle\b'),
     "a quantity's limit written again: the range is " + HOME + "'s"),
    (re.compile(r'"(lead_in|lead_out)"'), "the waypoint kind names written again: waypoint::kind_name"),
    (re.compile(r'"conventional"'), "the direction names written again: job::direction_names"),
    (re.compile(r'\benum\s+(class\s+)?Direction\b'), "Direction declared again: job::Direction"),
]
# Known second declarations, each with why it is still there (the lead removes an entry when its file moves).
ALLOWED = {}
EXTENSIONS = (".cpp", ".hpp", ".h", ".c", ".idl", ".py", ".sh")


def product_files(root):
    out = subprocess.run(["git", "-C", root, "ls-files"], check=True, capture_output=True, text=True).stdout
    for path in out.split("\n"):
        if not path or path.startswith(("tests/", "docs/", "third_party/")) or path == HOME:
            continue
        if path == "tools/lint/check-quantities.py" or path in ALLOWED:
            continue
        if path.endswith(EXTENSIONS) or path.startswith("tools/hg-"):
            yield path


def comment_free(line):
    """The line without a // or # comment (a rule on text in a comment would only forbid explaining)."""
    for mark in ("//", " #"):
        at = line.find(mark)
        if at >= 0 and line[:at].count('"') % 2 == 0:
            line = line[:at]
    return line


def findings(root):
    for path in product_files(root):
        full = os.path.join(root, path)
        if not os.path.isfile(full):
            continue
        with open(full, encoding="utf-8", errors="replace") as f:
            for number, line in enumerate(f, 1):
                code = comment_free(line)
                for rule, why in RULES:
                    if rule.search(code):
                        yield "%s:%d: %s: %s" % (path, number, why, line.strip())


def main(argv):
    if len(argv) > 1 and argv[1] == "--help":
        print(__doc__.strip())
        return 0
    repo = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    if len(argv) > 1 and argv[1] == "--version":
        with open(os.path.join(repo, "CMakeLists.txt")) as f:  # the one place the version is written
            version = re.search(r"project\(hullgrind VERSION ([0-9.]+)", f.read()).group(1)
        print("check-quantities.py " + version)
        return 0
    root = argv[1] if len(argv) > 1 else repo
    bad = list(findings(root))
    for b in bad:
        print(b)
    if bad:
        print("%d second declaration(s) of a quantity; declare it once in %s" % (len(bad), HOME))
        return 1
    print("every quantity declared once (%s)" % HOME)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
