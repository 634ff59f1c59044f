"""hg-foxglove --client-publish against @foxglove/ws-protocol's client (tests/foxglove/publish_check.js): an
anonymous client, a wrong password and a viewer of the station's users file cannot publish; an operator
can publish HG_JOB_REQUEST and nothing else. What reaches the bus is read on LCM (hg-lcm-dump): exactly one
request of the test's job, from the operator (actor "operator NAME", whatever the client wrote). The users
file is made with hg-station-user, the station's own tool. Runs in its own network namespace."""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SRC = os.environ.get("HG_SOURCE_DIR", os.path.join(HERE, "..", ".."))
BIN = os.environ.get("HG_BIN_DIR", os.path.join(SRC, "build", "bin"))
NPM = os.environ.get("HG_NPM_DIR", os.path.join(SRC, "build", "npm"))
PORT = 8765


def add_user(users, name, role, password):
    subprocess.run([os.path.join(BIN, "hg-station-user"), "add", name, "--role", role, "--password-stdin",
                    "--file", users], input=password + "\n", text=True, check=True, capture_output=True)


class FoxglovePublish(unittest.TestCase):
    def test_only_an_operator_publishes_a_job_request(self):
        tmp = tempfile.mkdtemp(prefix="hg-fox-publish-")
        self.addCleanup(shutil.rmtree, tmp, True)
        users = os.path.join(tmp, "users")
        add_user(users, "op1", "operator", "op-secret-1")
        add_user(users, "view1", "viewer", "view-secret-1")
        dump = subprocess.Popen([os.path.join(BIN, "hg-lcm-dump"), "--channels", "^HG_JOB_REQUEST$", "--type",
                                 "job_request_t", "--count", "2", "--timeout", "25"], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
        fox = subprocess.Popen([os.path.join(BIN, "hg-foxglove"), "--port", str(PORT), "--client-publish",
                                "--users-file", users], stderr=subprocess.PIPE, text=True)
        try:
            for line in fox.stderr:
                if "serving the bus" in line:
                    break
            result_file = os.path.join(tmp, "result.json")
            chk = subprocess.run(["node", os.path.join(HERE, "publish_check.js"), "127.0.0.1:%d" % PORT,
                                  "op1:op-secret-1", "view1:view-secret-1", "fox-pub-1", result_file],
                                 env=dict(os.environ, NODE_PATH=os.path.join(NPM, "node_modules")),
                                 capture_output=True, text=True, timeout=60)
            self.assertEqual(chk.returncode, 0, chk.stdout + chk.stderr)
            time.sleep(1)
        finally:
            fox.terminate()
            fox.wait(10)
        out, _ = dump.communicate(timeout=40)  # until its timeout: a second request would end it early
        self.assertEqual(dump.returncode, 3, "hg-lcm-dump did not time out: more than one request? " + out)
        with open(result_file) as f:
            r = json.load(f)
        self.check_clients(r)
        got = [json.loads(line)["msg"] for line in out.splitlines() if line.startswith("{")]
        self.assertEqual(len(got), 1, out)
        self.assertEqual((got[0]["job_id"], got[0]["action"], got[0]["actor"]), ("fox-pub-1", 6, "operator op1"))

    def check_clients(self, r):
        for name in ("anonymous", "viewer"):
            c = r[name]
            self.assertIn("clientPublish", c["capabilities"], name)
            self.assertTrue(any(s["level"] == 2 and "operator" in s["message"] for s in c["statuses"]), (name, c))
            self.assertEqual(c["closed"]["code"], 1008, (name, c))
            self.assertTrue(c["closed"]["reason"], name)
        self.assertEqual(r["wrong_password"]["status"], 401, r["wrong_password"])
        op = r["operator"]
        self.assertIsNone(op["closed"], op)
        texts = [s["message"] for s in op["statuses"] if s["level"] == 2]
        self.assertTrue(any("HG_ROBOT_MOVE" in t for t in texts), texts)
        self.assertTrue(any("not a JSON object" in t for t in texts), texts)
        self.assertTrue(any("no_such_field" in t for t in texts), texts)
        self.assertEqual(len(texts), 3, texts)


if __name__ == "__main__":
    unittest.main()
