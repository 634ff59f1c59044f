#!/usr/bin/env python3
"""Every camera profile of the renderer can be chosen wherever a profile is chosen: hg-camera-render renders
each at its sensor's resolution, and hg-fake-genicam offers each. The resolutions are the data sheets'
(docs/scene.md): PM806-class 1280x960, LSR-L-class 2048x1536, Zivid 2+ M130 2448x2048."""
import os
import re
import subprocess
import tempfile
import unittest

SRC = os.environ.get("HG_SOURCE_DIR", os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..")))
BIN = os.environ.get("HG_BIN_DIR", os.path.join(SRC, "build", "bin"))
SENSORS = {"pm806": (1280, 960), "lsr-l": (2048, 1536), "m130": (2448, 2048)}


def offered_profiles(program):
    out = subprocess.run([os.path.join(BIN, program), "--help"], capture_output=True, text=True, check=True).stdout
    match = re.search(r"--profile \S+\s+camera profile \{([^}]*)\}", out)
    if not match:
        raise AssertionError(f"{program} --help names no profile choices:\n{out}")
    return set(match.group(1).split("|"))


class CameraProfiles(unittest.TestCase):
    def test_the_renderer_renders_every_profile_at_its_sensor_size(self):
        for profile, (width, height) in SENSORS.items():
            with self.subTest(profile=profile), tempfile.TemporaryDirectory() as out:
                subprocess.run([os.path.join(BIN, "hg-camera-render"), "--out", out, "--profile", profile,
                                "--scene", "plate-hole-slot"], capture_output=True, text=True, check=True)
                text = open(os.path.join(out, "intrinsics.yaml")).read()
                self.assertIn(f"width: {width}\n", text)
                self.assertIn(f"height: {height}\n", text)

    def test_every_program_with_a_profile_offers_every_profile(self):
        for program in ("hg-camera-render", "hg-fake-genicam"):
            with self.subTest(program=program):
                self.assertEqual(offered_profiles(program), set(SENSORS))


if __name__ == "__main__":
    unittest.main()
