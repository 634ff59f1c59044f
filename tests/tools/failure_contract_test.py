"""The failure contract of every program in build/bin (docs/RUNNING.md, "How a program fails"): exit 2 for a bad
command line, config, cell or input file, 1 for "ran and failed", 0 for success, and a failure is exactly one
line on standard error naming the file or the key. One table over every program (HG_PROGRAMS, from CMake, as
tests/tools/help_version_test.py): a program missing from the table fails the test.

Per program: an unknown option; when its --help offers --config, a missing config file and one with an unknown
key; when it offers --cell, a missing cell file; a missing input file where it reads one. A process (it opens
LCM) is given an LCM URL that cannot be opened: a bad configuration must be refused (exit 2) before LCM is
opened (that would be exit 1, "cannot open LCM") or anything else is logged.

Per program also (one table, OUT_OF_RANGE): a value outside its declared range (or not one of its choices) is
refused, exit 2, in one line naming the option and saying why; --help answers exit 0 and lists that option. Every
option is declared once in runtime::Params (type, range, help): the tables keep every program on it.

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
    "hg-bench-station-feed": (["--cloud", MISSING + ".pcd"], [["--cloud", MISSING + ".pcd"]]),
    "hg-calibrate": (["verify", "--session", "{tmp}"], [["verify", "--session", MISSING]]),
    # Its input is a device or a folder that may come (back) later: a missing one is the heartbeat's ERROR state
    # and a retry, not an exit (tests/camera/bridge/process_test.cpp, MissingInputIsAnErrorStateNotACrash).
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


# program -> (arguments with one value out of its declared range or choices, what the one line must name).
# A program of build/bin without an option that has a range says why in NO_RANGE instead.
OUT_OF_RANGE = {
    "hg-bench": (["--runs", "0"], "--runs"),
    "hg-bench-camera": (["--frames", "0"], "--frames"),
    "hg-bench-outline-service": (["--runs", "0"], "--runs"),
    "hg-bench-station-feed": (["--cloud", MISSING + ".pcd", "--distance", "0"], "--distance"),
    "hg-calibrate": (["verify", "--speed", "0"], "--speed"),
    "hg-camera-bridge": (["--ransac-iterations", "0"], "--ransac-iterations"),
    "hg-camera-render": (["--frames", "0"], "--frames"),
    "hg-core-timing": (["--runs", "0", MISSING + ".xyz"], "--runs"),
    "hg-dds-gateway": (["--dds-domain", "231"], "--dds-domain"),
    "hg-fake-genicam": (["--rate", "0"], "--rate"),
    "hg-foxglove": (["--port", "65536"], "--port"),
    "hg-mcap": (["--chunk-size", "1"], "--chunk-size"),
    "hg-station": (["--port", "-1"], "--port"),
    "hg-station-user": (["list", "--role", "king"], "--role"),
    "hg-gen": (["--dropout", "1.5"], "--dropout"),
    "hg-job-recorder": (["--log-level", "loud"], "--log-level"),
    "hg-lcm-dump": (["--timeout", "-1"], "--timeout"),
    "hg-lcm-send": (["sample", "--type", "all", "--rate", "-1"], "--rate"),
    "hg-outline": (["--auto-factor", "0", MISSING + ".xyz"], "--auto-factor"),
    "hg-outline-service": (["--alpha-radius", "-1"], "--alpha-radius"),
    "hg-overview": ([MISSING + ".lcmlog", "--out", "{tmp}/o", "--grind-speed", "0"], "--grind-speed"),
    "hg-path-planner": (["--grind-speed", "0"], "--grind-speed"),
    "hg-plan": ([OUTLINE, "--grind-speed", "0"], "--grind-speed"),
    "hg-plan-bench": (["5"], "VERTICES"),
    "hg-radius-table": (["--seeds", "0"], "--seeds"),
    "hg-robot-bridge": (["--blend-radius", "-1"], "--blend-radius"),
    "hg-robot-export": ([MISSING + ".json", "-o", "{tmp}/x.script", "--blend-radius", "-1"], "--blend-radius"),
}
NO_RANGE = {
    # A C wrapper of a command line that is not its own (OUTFILE COMMAND ARGS...), kept tiny because its own
    # peak RSS is what the child inherits (see rss_wrapper.c); it has no option to declare.
    "hg-bench-rss": "runs a command: no options of its own",
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

    def test_every_program_refuses_a_value_out_of_range_and_helps(self):
        names = programs()
        self.assertGreater(len(names), 15, "HG_PROGRAMS lists the programs (set by CMake)")
        self.assertEqual(sorted(set(names) - set(OUT_OF_RANGE) - set(NO_RANGE)), [],
                         "programs missing from OUT_OF_RANGE (or NO_RANGE, with the reason)")
        for exe in names:
            with tempfile.TemporaryDirectory() as cwd:
                with self.subTest(program=exe, case="--help"):
                    r = self.run_in(cwd, exe, ["--help"])
                    self.assertEqual(r.returncode, 0, "%s --help: exit %d\n%s" % (exe, r.returncode, r.stderr))
                    self.assertEqual(r.stderr, "", exe + " --help wrote to stderr")
                    self.assertIn("usage", r.stdout.lower(), exe + " --help")
                if exe in NO_RANGE:
                    continue
                args, option = OUT_OF_RANGE[exe]
                lcm = BAD_LCM if exe in PROCESSES else []
                with self.subTest(program=exe, case="value out of range"):
                    self.refused(exe, lcm + args, [option], cwd)
                    line = self.run_in(cwd, exe, lcm + [a.replace("{tmp}", cwd) for a in args]).stderr
                    self.assertRegex(line, r"out of range|is not one of", exe)
                with self.subTest(program=exe, case="--help lists the option"):
                    helptext = self.run_in(cwd, exe, ["--help"]).stdout
                    self.assertIn(option, helptext, exe)

    def test_the_planner_arguments_of_hg_overview_are_the_planners(self):
        """hg-overview --planner-args parses the planner's command line with hg-path-planner's declarations: an
        option the planner does not know is refused (it was skipped, a guess), one the planner has is taken."""
        with tempfile.TemporaryDirectory() as cwd:
            base = [MISSING + ".lcmlog", "--out", os.path.join(cwd, "o"), "--planner-args"]
            self.refused("hg-overview", base + ["--no-such-option", "1"], ["--planner-args", "--no-such-option"], cwd)
            self.refused("hg-overview", base + ["--grind-speed", "0"], ["--planner-args", "--grind-speed"], cwd)
            # The planner's own options (--lcm-url, --jobs-dir) are its: taken, and the missing log is what fails.
            self.refused("hg-overview", base + ["--lcm-url", "memq://", "--jobs-dir", cwd], [MISSING + ".lcmlog"], cwd)

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
