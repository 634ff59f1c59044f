"""tools/lint/check-channels.py fails on each way of naming a channel outside the one table
(runtime/channels.hpp), planted in a tree it makes, and passes the same tree without it: the lint that keeps
the bus in one table can fail."""
import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
LINT = os.path.join(HERE, "..", "..", "tools", "lint", "check-channels.py")

TABLE = '''#pragma once
namespace hg::channels {
inline constexpr const char* kOutline = "HG_OUTLINE";
inline constexpr const char* kJobStatus =
    "HG_JOB_STATUS";
struct Channel { const char* name; const char* type; const char* publishers; const char* subscribers; const char* what; };
inline constexpr Channel kTable[] = {
    {kOutline, "outline_t", "outline_service", "path_planner, "
     "station", "outer loops"},
    {kJobStatus, "job_status_t", "path_planner", "station", "the job's state"},
};
}
'''
CLEAN = {
    "path_planner/path_planner.cpp": ('#include "runtime/channels.hpp"\n'
                                      "void f(Node& node_) {\n  node_.subscribe<hullgrind::outline_t>(\n"
                                      "      channels::kOutline, handler);\n  node_.publish(channels::kJobStatus, s);\n}\n"
                                      '// help text naming "on HG_OUTLINE" is prose\nconst char* h = "reads HG_OUTLINE";\n'),
    "station/station.cpp": "void g(Node& node) { namespace ch = channels; node.subscribe<T>(ch::kOutline, h); }\n",
    "tests/x/x_test.cpp": 'publish("HG_OUTLINE", m);\n',  # tests are readers of their own
}
# Each planted file breaks the rule once.
PLANTED = [
    ("tools/overview/run_log.cpp", 'if (e->channel == "HG_OUTLINE") ok = true;\n', 'channel name "HG_OUTLINE"'),
    ("outline_service/o.cpp", 'node_.publish("HG_NEW_THING", m);\n', "names its channel by a literal"),
    ("outline_service/o.cpp", "node_.publish(channels::kJobStatus, m);\n", "does not name it among the publishers"),
    ("robot_bridge/b.cpp", "node.subscribe<job_status_t>(channels::kJobStatus, h);\n",
     "does not name it among the subscribers"),
    ("robot_bridge/b.cpp", "node.subscribe<T>(channels::kNoSuch, h);\n", "has no row"),
]


def run(files):
    with tempfile.TemporaryDirectory() as root:
        for path, text in {"runtime/channels.hpp": TABLE, **files}.items():
            os.makedirs(os.path.dirname(os.path.join(root, path)), exist_ok=True)
            with open(os.path.join(root, path), "w") as f:
                f.write(text)
        return subprocess.run([sys.executable, LINT, root], capture_output=True, text=True)


class CheckChannels(unittest.TestCase):
    def test_the_clean_tree_passes(self):
        r = run(CLEAN)
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertIn("0 finding(s)", r.stdout)

    def test_each_planted_line_fails_naming_its_file(self):
        for path, text, why in PLANTED:
            with self.subTest(path=path, text=text):
                r = run({**CLEAN, path: text})
                self.assertEqual(r.returncode, 1, r.stdout)
                self.assertIn(path + ":1:", r.stdout)
                self.assertIn(why, r.stdout)

    def test_a_constant_without_a_row_fails(self):
        r = run({"runtime/channels.hpp": TABLE.replace("inline constexpr Channel",
                                                       'inline constexpr const char* kLog = "HG_LOG";\n'
                                                       "inline constexpr Channel")})
        self.assertEqual(r.returncode, 1, r.stdout)
        self.assertIn("kLog (HG_LOG) has no row", r.stdout)


if __name__ == "__main__":
    unittest.main()
