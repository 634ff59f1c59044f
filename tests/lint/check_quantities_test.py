"""tools/lint/check-quantities.py fails on each kind of second declaration, planted in a tree it makes, and passes
the same tree without it: the lint that keeps one declaration per quantity (issue 26 §1) can fail."""
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
LINT = os.path.join(HERE, "..", "..", "tools", "lint", "check-quantities.py")

# Each line declares a quantity, the kind list or the direction again, outside runtime/quantities.hpp.
PLANTED = [
    'number_param("tool-radius", "", "tool radius, m", 0, 1),',
    'number_param("tilt", "", "tool tilt, rad", -1.6, 1.6),',
    'number_param("safe-height", "0.05", "height", 0, 2),',
    'text_param("base-frame", "robot_base", "frame"),',
    'm.chamfer_angle = 0.5;',
    '{"chamfer-angle", "tool.tilt"},',
    'if (tilt > 80 * M_PI / 180) return false;',
    'double max_tool_radius = 0.2;',
    'if (tilt > 1.3962634015954636) return false;',
    'static const char* kinds[] = {"approach", "lead_in", "grind"};',
    'if (name == "conventional") return 1;',
    'enum class Direction : int8_t { Climb, Conventional };',
]
# Lines that are fine: the table's users, a moved key naming where it lives, the names in a comment.
CLEAN = [
    'runtime::quantity_param(quantity::kStep, "0.002", "job default"),',
    '{"base-frame", "frames.base"},',
    '// the old chamfer_angle is tilt; kinds are "lead_in" and the like',
    'number_param("lead-radius", "0.01", "lead arc radius, m", 0, 1),',
]


def run(root):
    return subprocess.run([sys.executable, LINT, root], capture_output=True, text=True)


def tree(case, lines):
    d = tempfile.mkdtemp()
    case.addCleanup(shutil.rmtree, d)
    os.makedirs(os.path.join(d, "runtime"))
    os.makedirs(os.path.join(d, "planner"))
    with open(os.path.join(d, "runtime", "quantities.hpp"), "w") as f:  # the one home: never flagged
        f.write("\n".join(PLANTED) + "\n")
    with open(os.path.join(d, "planner", "io.cpp"), "w") as f:
        f.write("\n".join(lines) + "\n")
    subprocess.run(["git", "init", "-q", d], check=True)
    subprocess.run(["git", "-C", d, "add", "-A"], check=True)
    return d


class CheckQuantities(unittest.TestCase):
    def test_a_clean_tree_passes(self):
        r = run(tree(self, CLEAN))
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)

    def test_each_second_declaration_fails_naming_the_line(self):
        for line in PLANTED:
            with self.subTest(line=line):
                r = run(tree(self, CLEAN + [line]))
                self.assertEqual(r.returncode, 1, r.stdout + r.stderr)
                self.assertIn("planner/io.cpp:%d:" % (len(CLEAN) + 1), r.stdout)
                self.assertIn("1 second declaration(s)", r.stdout)

    def test_the_real_tree_passes(self):
        r = run(os.path.join(HERE, "..", ".."))
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)


if __name__ == "__main__":
    unittest.main()
