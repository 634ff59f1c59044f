"""Every program built into build/bin and every script of the tree answers --help and --version: exit 0, something on
standard output (--version: the project's version, read here from CMakeLists.txt), and no file created —
neither in the working directory, nor in $TMPDIR, nor in the source tree. build/bin holds the user programs only
(test binaries go to build/tests). Runs in its own network namespace (tests/netns.sh) in case a program opened a
socket it should not."""
import os
import re
import subprocess
import tempfile
import unittest

SRC = os.environ.get("HG_SOURCE_DIR", os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..")))
BIN = os.environ.get("HG_BIN_DIR", os.path.join(SRC, "build", "bin"))


def project_version():
    with open(os.path.join(SRC, "CMakeLists.txt")) as f:
        return re.search(r"^project\(hullgrind VERSION ([0-9.]+)", f.read(), re.M).group(1)


def declared_programs():
    """The user programs: every executable target outside tests/ (HG_PROGRAMS, from CMake)."""
    return sorted(n for n in os.environ.get("HG_PROGRAMS", "").split(",") if n)


def programs():
    """Every program in build/bin (test binaries go to build/tests)."""
    return [os.path.join(BIN, n) for n in declared_programs()]


def bin_listing():
    """The executable files in build/bin, whatever made them."""
    return sorted(n for n in os.listdir(BIN) if os.path.isfile(os.path.join(BIN, n)) and
                  os.access(os.path.join(BIN, n), os.X_OK))


def is_script(path):
    with open(path, "rb") as f:
        return os.access(path, os.X_OK) and f.read(2) == b"#!"


def scripts():
    """Every executable script of the tree (tools/, tests/netns.sh, data/samples/regenerate.sh, .ci/run, ...):
    the tracked files with a #! line (`git ls-files`); without git, those under tools/ and tests/."""
    try:
        listed = subprocess.run(["git", "-C", SRC, "ls-files", "-z"], check=True, capture_output=True).stdout
        paths = [os.path.join(SRC, p) for p in listed.decode().split("\0") if p]
    except (subprocess.CalledProcessError, FileNotFoundError):
        paths = [os.path.join(d, n) for top in ("tools", "tests") for d, _, names in os.walk(os.path.join(SRC, top))
                 for n in names]
    return sorted(p for p in paths if os.path.isfile(p) and is_script(p))


def tree_snapshot(root):
    """What a program or script could leave in the source tree: the top-level entries (out/, build-fuzz/, ...)
    and everything under tools/, docs/ and data/ (__pycache__, a screenshot, a sample), with modification
    times. Other test folders are left out: tests running at the same time write there."""
    snap = {os.path.join(root, name): 0 for name in os.listdir(root)}
    for top in ("tools", "docs", "data"):
        for folder, dirs, files in os.walk(os.path.join(root, top)):
            for name in dirs + files:
                path = os.path.join(folder, name)
                try:
                    snap[path] = os.lstat(path).st_mtime_ns
                except FileNotFoundError:
                    pass
    return snap


class HelpAndVersion(unittest.TestCase):
    def test_every_program_and_script(self):
        targets = programs() + scripts()
        self.assertGreater(len(programs()), 15, "HG_PROGRAMS lists the programs (set by CMake)")
        for exe in programs():
            self.assertTrue(os.access(exe, os.X_OK), exe + " is not built")
        # build/bin holds the user programs and nothing else: no test binary, no program CMake no longer makes.
        self.assertEqual(sorted(set(bin_listing()) - set(declared_programs())), [],
                         "executables in build/bin that are no user program (test binaries belong in build/tests)")
        self.assertGreater(len(scripts()), 8)
        version = project_version()
        before = tree_snapshot(SRC)
        for exe in targets:
            for arg in ("--help", "--version"):
                with self.subTest(program=os.path.relpath(exe, SRC), arg=arg), tempfile.TemporaryDirectory() as cwd:
                    tmp = os.path.join(cwd, "tmp")
                    os.mkdir(tmp)
                    env = dict(os.environ, TMPDIR=tmp, HOME=cwd)
                    r = subprocess.run([exe, arg], cwd=cwd, env=env, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                       stderr=subprocess.PIPE, text=True, errors="replace", timeout=60)
                    self.assertEqual(r.returncode, 0, r.stderr[-2000:])
                    self.assertTrue(r.stdout.strip(), "nothing on standard output")
                    if arg == "--version":
                        self.assertIn(version, r.stdout)
                        self.assertLess(len(r.stdout.splitlines()), 3, r.stdout)
                    self.assertEqual(os.listdir(tmp), [], "files left in $TMPDIR")
                    self.assertEqual(sorted(os.listdir(cwd)), ["tmp"], "files left in the working directory")
        after = tree_snapshot(SRC)
        self.assertEqual(sorted(set(after) - set(before)), [], "files created in the source tree")
        changed = [p for p in before if p in after and after[p] != before[p] and not os.path.isdir(p)]
        self.assertEqual(changed, [], "files changed in the source tree")


if __name__ == "__main__":
    unittest.main()
