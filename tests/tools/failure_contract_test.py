"""The failure contract of every program in build/bin (docs/RUNNING.md, "How a program fails"): exit 2 for a bad
command line, config, cell or input file, 1 for "ran and failed", 0 for success, and a failure is exactly one
line on standard error naming the file or the key. One table over every program (HG_PROGRAMS, from CMake, as
tests/tools/help_version_test.py): a program missing from the table fails the test.

Per program: an unknown option; when its --help offers --config, a missing config file and one with an unknown
key; when it offers --cell, a missing cell file; a missing input file where it reads one. A process (it opens
LCM) is given an LCM URL that cannot be opened: a bad configuration must be refused (exit 2) before LCM is
opened (that would be exit 1, "cannot open LCM") or anything else is logged.

Default files (config/cell.yaml, config/path_planner.yaml) resolve from any working directory: next to the
executable (build/bin/../../config) or in HG_CONFIG_DIR. Runs in its own network namespace (tests/netns.sh)."""
import os
import re
import subprocess
import tempfile
import unittest

SRC = os.environ.get("HG_SOURCE_DIR", os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..")))
BIN = os.environ.get("HG_BIN_DIR", os.path.join(SRC, "build", "bin"))
MISSING = "/nonexistent/hg-missing"
OUTLINE = os.path.join(SRC, "tests", "data", "e2e", "plate-hole-slot-pm806-outline.json")
BAD_LCM = ["--lcm-url", "nosuchprovider://nowhere"]

# Processes: they open LCM. Their input arrives on the bus (no input file).
PROCESSES = {"hg-camera-bridge", "hg-outline-service", "hg-path-planner", "hg-robot-bridge", "hg-dds-gateway",
             "hg-job-recorder", "hg-foxglove", "hg-station"}
# program -> (arguments the program needs besides the file under test, [missing-input cases]).
# "{}" in an argument list is the file under test (config or cell); a missing-input case is an argument list
# naming MISSING.
TABLE = {
    "hg-bench": (["--only", "none"], []),
    "hg-bench-camera": ([], []),
    "hg-bench-outline-service": ([], []),
    "hg-bench-rss": ([], []),
    "hg-calibrate": (["verify", "--session", "{tmp}"], [["verify", "--session", MISSING]]),
    # Its input is a device or a folder that may come (back) later: a missing one is the heartbeat's ERROR state
    # and a retry, not an exit (tests/camera_bridge/process_test.cpp, MissingInputIsAnErrorStateNotACrash).
    "hg-camera-bridge": ([], []),
    "hg-camera-render": ([], []),
    "hg-core-timing": ([], [[MISSING + ".xyz"]]),
    "hg-dds-gateway": ([], [["--dds-security-identity-ca", MISSING + ".pem"]]),
    "hg-fake-genicam": ([], [["--xml", MISSING + ".xml"]]),
    "hg-foxglove": ([], []),
    "hg-mcap": ([MISSING + ".lcmlog", "-o", "{tmp}/x.mcap"], [[MISSING + ".lcmlog", "-o", "{tmp}/x.mcap"]]),
    # A missing users file is the heartbeat's DEGRADED state until one is made (docs/station.md), not an exit.
    "hg-station": (["--users-file", "{tmp}/users"], []),
    # `list` of a users file not made yet lists nobody (exit 0): the file is made by the first `add`.
    "hg-station-user": (["list", "--file", "{tmp}/users"], []),
    "hg-gen": ([], []),
    "hg-job-recorder": ([], []),
    "hg-lcm-dump": ([], []),
    "hg-lcm-send": ([], []),
    "hg-outline": ([MISSING + ".xyz"], [[MISSING + ".xyz"], [MISSING + ".ply"]]),
    "hg-outline-service": ([], []),
    "hg-overview": ([MISSING + ".lcmlog", "--out", "{tmp}/o"], [[MISSING + ".lcmlog", "--out", "{tmp}/o"]]),
    "hg-path-planner": ([], []),
    "hg-plan": ([OUTLINE], [[MISSING + ".json"]]),
    "hg-plan-bench": ([], []),
    "hg-radius-table": ([], []),
    "hg-robot-bridge": ([], []),
    "hg-robot-export": ([MISSING + ".json", "-o", "{tmp}/x.script"], [[MISSING + ".json", "-o", "{tmp}/x.script"]]),
}


def programs():
    return sorted(n for n in os.environ.get("HG_PROGRAMS", "").split(",") if n)


class FailureContract(unittest.TestCase):
    def run_in(self, cwd, exe, args, env=None):
        r = subprocess.run([os.path.join(BIN, exe)] + args, cwd=cwd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                           stderr=subprocess.PIPE, text=True, errors="replace", timeout=60,
                           env=dict(os.environ, **(env or {})))
        return r

    def refused(self, exe, args, names, cwd):
        """Exit 2, exactly one line on stderr, naming each of `names`, nothing else logged."""
        args = [a.replace("{tmp}", cwd) for a in args]
        r = self.run_in(cwd, exe, args)
        lines = r.stderr.splitlines()
        self.assertEqual(r.returncode, 2, "%s %s: exit %d, stderr:\n%s" % (exe, args, r.returncode, r.stderr))
        self.assertEqual(len(lines), 1, "%s %s: not one line:\n%s" % (exe, args, r.stderr))
        for n in names:
            self.assertIn(n, lines[0], "%s %s" % (exe, args))
        self.assertNotIn(" INFO ", lines[0])

    def test_every_program_follows_the_contract(self):
        names = programs()
        self.assertGreater(len(names), 15, "HG_PROGRAMS lists the programs (set by CMake)")
        self.assertEqual(sorted(set(names) - set(TABLE)), [], "programs missing from this test's table")
        for exe in names:
            base, missing_inputs = TABLE[exe]
            lcm = BAD_LCM if exe in PROCESSES else []
            with tempfile.TemporaryDirectory() as cwd:
                helptext = self.run_in(cwd, exe, ["--help"]).stdout
                with self.subTest(program=exe, case="unknown option"):
                    self.refused(exe, ["--no-such-option"], ["--no-such-option"], cwd)
                if re.search(r"^\s*--config\b", helptext, re.M):
                    bad = os.path.join(cwd, "bad.yaml")
                    with open(bad, "w") as f:
                        f.write("no-such-key: 1\n")
                    with self.subTest(program=exe, case="missing config file"):
                        self.refused(exe, lcm + ["--config", MISSING + ".yaml"] + base, [MISSING + ".yaml"], cwd)
                    with self.subTest(program=exe, case="config file with an unknown key"):
                        self.refused(exe, lcm + ["--config", bad] + base, [bad, "no-such-key"], cwd)
                if re.search(r"^\s*(\| `)?--cell\b", helptext, re.M):
                    with self.subTest(program=exe, case="missing cell file"):
                        self.refused(exe, lcm + ["--cell", MISSING + ".yaml"] + base, [MISSING + ".yaml"], cwd)
                for case in missing_inputs:
                    with self.subTest(program=exe, case="missing input file", args=case):
                        self.refused(exe, lcm + case, [MISSING], cwd)

    def test_default_files_resolve_from_any_working_directory(self):
        with tempfile.TemporaryDirectory() as cwd:
            r = self.run_in(cwd, "hg-plan", ["--check-config"])
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertIn(os.path.realpath(os.path.join(SRC, "config", "cell.yaml")), r.stderr)
            # The outline of the e2e fixture, planned and exported from a folder outside the tree.
            r = self.run_in(cwd, "hg-plan", [OUTLINE, "--outline-frame", "camera", "-o", "path.json"])
            self.assertNotIn("cannot open", r.stderr)
            self.assertNotEqual(r.returncode, 2, r.stderr)
            r = self.run_in(cwd, "hg-robot-export", [MISSING + ".json", "-o", "job.script"])
            self.assertEqual(r.returncode, 2, r.stderr)
            self.assertIn(MISSING + ".json", r.stderr)  # the path file, not the default cell, is missing
            r = self.run_in(cwd, "hg-overview", [MISSING + ".lcmlog", "--out", "o"])
            self.assertIn(MISSING + ".lcmlog", r.stderr)  # not config/path_planner.yaml
            # HG_CONFIG_DIR wins: its cell file (with another tool) is the one read.
            os.mkdir(os.path.join(cwd, "cfg"))
            with open(os.path.join(SRC, "config", "cell.yaml")) as f:
                text = f.read()
            with open(os.path.join(cwd, "cfg", "cell.yaml"), "w") as f:
                f.write(text.replace("\n  radius:", "\n  radius: -1\n  old-radius:", 1))
            r = self.run_in(cwd, "hg-plan", ["--check-config"], env={"HG_CONFIG_DIR": os.path.join(cwd, "cfg")})
            self.assertEqual(r.returncode, 2, r.stderr)
            self.assertIn(os.path.join(cwd, "cfg", "cell.yaml"), r.stderr)
            self.assertEqual(len(r.stderr.splitlines()), 1, r.stderr)


if __name__ == "__main__":
    unittest.main()
