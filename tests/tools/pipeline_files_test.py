"""One cell per pipeline: every process of config/pipeline*.toml whose program reads a cell file (its --help
lists --cell) is given the pipeline's cell, `--cell ${CELL:-cell-sim.yaml}` (tools/run.sh --cell replaces
it). A process left on its program's default cell would judge scans, frames or limits by another cell than
the planner's and robot bridge's. Runs in its own network namespace (tests/netns.sh), as the other tests
that start every program."""

import glob
import os
import subprocess
import sys
import tomllib
import unittest

SRC = os.environ.get("HG_SOURCE_DIR", os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
BIN = os.environ.get("HG_BIN_DIR", os.path.join(SRC, "build", "bin"))
CELL = "${CELL:-cell-sim.yaml}"


def program(command):
    """The hullgrind program a process runs: the first hg-NAME of its command (the camera runs behind the
    virtual OpenNI2 device's wrapper)."""
    for arg in command:
        name = os.path.basename(arg)
        if name.startswith("hg-"):
            return name
    return None


def reads_cell(name):
    out = subprocess.run([os.path.join(BIN, name), "--help"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                         text=True, timeout=30)
    return any(line.split()[:1] == ["--cell"] for line in out.stdout.splitlines())


class PipelineFiles(unittest.TestCase):
    def test_every_cell_reader_gets_the_pipelines_cell(self):
        files = sorted(glob.glob(os.path.join(SRC, "config", "pipeline*.toml")))
        self.assertGreaterEqual(len(files), 2, files)
        readers = 0
        for path in files:
            with open(path, "rb") as f:
                processes = tomllib.load(f)["process"]
            for p in processes:
                name = program(p["command"])
                if not name or not os.path.exists(os.path.join(BIN, name)) or not reads_cell(name):
                    continue
                readers += 1
                cmd = p["command"]
                with self.subTest(file=os.path.basename(path), process=p["name"]):
                    self.assertIn("--cell", cmd, "%s: %s reads a cell file but is given none" % (path, name))
                    self.assertEqual(cmd[cmd.index("--cell") + 1], CELL, path)
        # The outline service, planner, robot bridge, Foxglove server and station in each file.
        self.assertGreaterEqual(readers, 2 * 5)

    def test_every_output_is_under_the_output_folder(self):
        # One pipeline per output folder: nothing of a run is written beside another run's (no ../out/).
        for path in sorted(glob.glob(os.path.join(SRC, "config", "pipeline*.toml"))):
            with open(path, "rb") as f:
                doc = tomllib.load(f)
            args = [a for p in doc["process"] for a in p["command"]] + [str(v) for v in doc["supervisor"].values()]
            with self.subTest(file=os.path.basename(path)):
                self.assertEqual([a for a in args if "../out" in a], [])

    def test_reads_cell_tells_readers_from_others(self):
        # The probe itself: the planner reads one, the job recorder does not.
        self.assertTrue(reads_cell("hg-path-planner"))
        self.assertFalse(reads_cell("hg-job-recorder"))


if __name__ == "__main__":
    sys.exit(unittest.main())
