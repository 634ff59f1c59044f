"""hg-foxglove converts a big message (a plate cloud of 4 MB or more on HG_PLATE_CLOUD) at most once per
--cloud-period, and sends its own JSON at most once per --raw-cloud-period, while its 3-D topic
/hg/plate/points carries every cloud it converts (docs/foxglove.md, "What is dropped, when"). A free-running camera (hg-bench-station-feed --rate 5) publishes
a 764 k-point cloud (over 6 MB); a viewer (@foxglove/ws-protocol's client, count_check.js) counts what it
receives per topic in 6 s. The conversion runs at normal priority here, so that what is counted is the
rule, not the load of the machine the test runs on. Runs in its own network namespace."""
import json
import os
import subprocess
import tempfile
import time
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SRC = os.environ.get("HG_SOURCE_DIR", os.path.join(HERE, "..", ".."))
BIN = os.environ.get("HG_BIN_DIR", os.path.join(SRC, "build", "bin"))
NPM = os.environ.get("HG_NPM_DIR", os.path.join(SRC, "build", "npm"))
PORT = 8765
SECONDS = 6


class FoxgloveRawPeriod(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.cloud = os.path.join(cls.tmp.name, "cloud.pcd")
        subprocess.run([os.path.join(BIN, "hg-gen"), "--preset", "high-1", "--format", "pcd", "-o", cls.cloud],
                       check=True, capture_output=True, timeout=120)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def start(self, argv):
        p = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        self.running.append(p)
        return p

    def setUp(self):
        self.running = []
        self.addCleanup(self.stop_all)

    def stop_all(self):
        """Each count has a server of its own on the port: the one before is gone first."""
        for p in self.running:
            p.terminate()
            p.wait(10)
            p.stderr.close()
        self.running = []

    def counts(self, raw_period, cloud_period):
        fox = self.start([os.path.join(BIN, "hg-foxglove"), "--port", str(PORT), "--conversion-priority", "normal",
                          "--raw-cloud-period", str(raw_period), "--cloud-period", str(cloud_period)])
        for line in fox.stderr:
            if "serving the bus" in line:
                break
        self.start([os.path.join(BIN, "hg-bench-station-feed"), "--cloud", self.cloud, "--rate", "5"])
        time.sleep(1)  # the first clouds advertise the topics
        env = dict(os.environ, NODE_PATH=os.path.join(NPM, "node_modules"))
        out = subprocess.run(["node", os.path.join(HERE, "count_check.js"), "ws://127.0.0.1:%d" % PORT, str(SECONDS)],
                             capture_output=True, text=True, env=env, timeout=60)
        self.assertEqual(out.returncode, 0, out.stderr)
        got = json.loads(out.stdout.strip().splitlines()[-1])
        self.stop_all()
        return got.get("HG_PLATE_CLOUD", 0), got.get("/hg/plate/points", 0)

    def test_a_clouds_json_once_per_period_its_points_once_per_cloud_period(self):
        raw, points = self.counts(3600, 1)
        self.assertLessEqual(raw, 1, "one cloud's JSON in an hour, at most the one kept from before")
        self.assertGreaterEqual(points, 3, "the 3-D topic keeps coming")
        self.assertLessEqual(points, SECONDS + 2, "a cloud a second of the camera's five")
        raw_all, points_all = self.counts(0, 0)
        self.assertGreaterEqual(raw_all, 3, "periods 0: every cloud's JSON the conversion gets to")
        self.assertGreater(points_all, SECONDS + 2, "periods 0: every cloud the conversion gets to")


if __name__ == "__main__":
    unittest.main()
