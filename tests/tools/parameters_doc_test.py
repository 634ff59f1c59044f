"""docs/PARAMETERS.md is what the programs say: each section is the program's own `--help-markdown` (the
parameters as declared once in the code: name, type, default, range, help). After changing a parameter:
    HG_WRITE_DOC=1 HG_BIN_DIR=build/bin python3 tests/tools/parameters_doc_test.py
rewrites the page."""
import difflib
import os
import subprocess
import unittest

SRC = os.environ.get("HG_SOURCE_DIR", os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..")))
BIN = os.environ.get("HG_BIN_DIR", os.path.join(SRC, "build", "bin"))
DOC = os.path.join(SRC, "docs", "PARAMETERS.md")
PROGRAMS = ["hg-camera-bridge", "hg-outline-service", "hg-path-planner", "hg-robot-bridge", "hg-dds-gateway",
            "hg-job-recorder", "hg-foxglove", "hg-station", "hg-station-user", "hg-plan", "hg-outline", "hg-robot-export",
            "hg-gen", "hg-calibrate", "hg-mcap", "hg-overview", "hg-lcm-dump", "hg-lcm-send", "hg-camera-render",
            "hg-fake-genicam", "hg-bench", "hg-bench-camera", "hg-bench-outline-service", "hg-bench-station-feed",
            "hg-plan-bench", "hg-core-timing", "hg-radius-table"]
# The programs without options of their own (not runtime::Params): the page names them and says why. Every user
# program (HG_PROGRAMS, from CMake) is in one list or the other.
OWN_OPTIONS = ["hg-bench-rss"]
HEADER = """# Parameters

Every parameter of the processes and of the tools built on the same parameter handling, as each program
declares it (`PROGRAM --help-markdown` prints its table; `PROGRAM --help` says the same in words). Keys are
kebab-case, the same on the command line (`--grind-speed 0.02`, lists as `0.5,0,1.2`) and in a `--config`
YAML file (`grind-speed: 0.02`, lists as `[0.5, 0, 1.2]`, booleans `true`/`false`); the command line wins
over the file, the file over the default. Generated: `tests/tools/parameters_doc_test.py` checks that this
page matches the programs.

Not on this page: %s, which runs the command line it is given (`OUTFILE COMMAND ARGS...`, for hg-bench's
memory figures) and has no options of its own.
""" % ", ".join("`%s`" % n for n in OWN_OPTIONS)


def generated():
    env = {k: v for k, v in os.environ.items() if k != "LCM_DEFAULT_URL"}  # the default shown is then fixed
    parts = [HEADER]
    for name in PROGRAMS:
        table = subprocess.run([os.path.join(BIN, name), "--help-markdown"], env=env, stdout=subprocess.PIPE,
                               text=True, check=True, timeout=60).stdout
        parts.append("\n## %s\n\n%s" % (name, table))
    return "".join(parts)


class ParametersDoc(unittest.TestCase):
    def test_every_program_is_on_the_page_or_named_as_having_no_options(self):
        declared = set(n for n in os.environ.get("HG_PROGRAMS", "").split(",") if n)
        self.assertGreater(len(declared), 15, "HG_PROGRAMS lists the programs (set by CMake)")
        self.assertEqual(sorted(declared - set(PROGRAMS) - set(OWN_OPTIONS)), [],
                         "programs neither in PARAMETERS.md nor named as parsing their own options")
        self.assertEqual(sorted(set(PROGRAMS) & set(OWN_OPTIONS)), [])

    def test_doc_matches_the_programs(self):
        text = generated()
        for name in PROGRAMS:
            self.assertIn("\n## %s\n\n| key | type | default | range | what |" % name, text)
        if os.environ.get("HG_WRITE_DOC"):
            with open(DOC, "w") as f:
                f.write(text)
        with open(DOC) as f:
            doc = f.read()
        diff = "".join(difflib.unified_diff(doc.splitlines(True), text.splitlines(True), "docs/PARAMETERS.md", "programs"))
        self.assertEqual(doc, text, "docs/PARAMETERS.md differs from --help-markdown:\n" + diff)


if __name__ == "__main__":
    unittest.main()
