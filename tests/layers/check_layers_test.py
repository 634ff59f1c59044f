"""The layer check on small trees made here (not git work trees: the checker walks them), each with a known
verdict: clean trees pass, each kind of include against the layers fails and is named by file and line."""
import os
import subprocess
import sys
import tempfile
import unittest

CHECKER = os.path.join(os.path.dirname(os.path.abspath(__file__)), "check_layers.py")


def run_on(tree):
    """tree: {path: text}. Returns (exit code, stdout) of the checker over it."""
    with tempfile.TemporaryDirectory() as root:
        for path, text in tree.items():
            os.makedirs(os.path.dirname(os.path.join(root, path)), exist_ok=True)
            with open(os.path.join(root, path), "w") as f:
                f.write(text)
        r = subprocess.run([sys.executable, CHECKER, "--root", root], capture_output=True, text=True)
        return r.returncode, r.stdout


BASE = {
    "runtime/node.hpp": "#pragma once\n",
    "motion/motion.hpp": "#pragma once\n",
    "outline_core/outline.hpp": "#pragma once\n",
    "sim/partgen/shapes.hpp": "#pragma once\n",
    "sim/scene/scene.hpp": '#include "sim/partgen/shapes.hpp"\n',
    "tools/overview/overview.hpp": "#pragma once\n",
    "path_planner/pipeline.hpp": '#include "motion/motion.hpp"\n',
    "robot_bridge/path.hpp": '#include <motion/motion.hpp>\n#include <vector>\n',
}


class CheckLayers(unittest.TestCase):
    def assert_fails(self, added, where, why):
        """BASE plus `added` fails the check, naming `where` (file:line:) and saying `why`."""
        code, out = run_on({**BASE, **added})
        self.assertEqual(code, 1, out)
        self.assertIn(where, out)
        self.assertIn(why, out)
        return out

    def test_includes_that_point_down_pass(self):
        tree = dict(BASE)
        tree["camera_bridge/sources.cpp"] = ('#include "runtime/node.hpp"\n#include "sim/scene/scene.hpp"\n'
                                             '#include "outline_core/outline.hpp"\n#include <opencv2/core.hpp>\n')
        tree["tools/hg_plan/main.cpp"] = '#include "path_planner/pipeline.hpp"\n#include "tools/overview/overview.hpp"\n'
        tree["tests/x/any_test.cpp"] = '#include "tools/overview/overview.hpp"\n#include "robot_bridge/path.hpp"\n'
        code, out = run_on(tree)
        self.assertEqual(code, 0, out)
        self.assertIn("0 include(s)", out)

    def test_a_process_including_tools_fails(self):
        self.assert_fails({"job_recorder/recorder.cpp": '// the outline writer\n#include "tools/overview/overview.hpp"\n'},
                          "job_recorder/recorder.cpp:2:", "a higher layer")

    def test_a_process_including_another_process_fails(self):
        self.assert_fails({"outline_service/bench.cpp": '#include <vector>\n#include "path_planner/pipeline.hpp"\n'},
                          "outline_service/bench.cpp:2:", "another process folder, path_planner")

    def test_a_lower_layer_including_a_higher_one_fails(self):
        for src, include in [("outline_core/alpha.cpp", '#include "sim/partgen/shapes.hpp"'),  # spelled from the root
                             ("sim/scene/scene.cpp", "#include <robot_bridge/path.hpp>"),   # angle brackets
                             ("motion/motion.cpp", '#include "../outline_core/outline.hpp"')]:  # relative
            self.assert_fails({src: include + "\n"}, src + ":1:", "a higher layer")

    def test_a_product_file_including_tests_fails(self):
        self.assert_fails({"tests/common/helper.hpp": "#pragma once\n",
                           "robot_bridge/bridge.cpp": '#include "tests/common/helper.hpp"\n'},
                          "robot_bridge/bridge.cpp:1:", "includes tests/")

    def test_a_folder_in_no_layer_is_named(self):
        self.assert_fails({"newthing/a.cpp": '#include "runtime/node.hpp"\n'}, "newthing/a.cpp:1:",
                          "newthing is in no layer")

    def test_a_folder_in_no_layer_fails_even_without_includes_of_the_tree(self):
        self.assert_fails({"newthing/a.cpp": "#include <vector>\n", "newthing/b.hpp": "#pragma once\n"},
                          "newthing/:", "source files in no layer")

    def test_a_quoted_include_that_names_no_file_fails(self):
        # An include root the checker does not know would otherwise hide the include from the check.
        out = self.assert_fails({"robot_bridge/bridge.cpp": '#include "somewhere/unknown.hpp"\n#include <unknown_system_header>\n'},
                                "robot_bridge/bridge.cpp:1:", "names no file of the tree")
        self.assertNotIn("bridge.cpp:2:", out)

    def test_an_include_spelled_from_another_include_root_fails(self):
        # sim/partgen/shapes.hpp is "sim/partgen/shapes.hpp" everywhere (or "shapes.hpp" beside it), never
        # "partgen/shapes.hpp" through an include directory of its own.
        self.assert_fails({"tools/hg_gen/hg_gen.cpp": '#include "partgen/shapes.hpp"\n'}, "tools/hg_gen/hg_gen.cpp:1:",
                          "names no file of the tree")


if __name__ == "__main__":
    unittest.main()
