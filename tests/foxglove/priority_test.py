"""hg-foxglove's conversion runs at idle scheduling priority and its WebSocket server's thread at a nice value
above the cell's (docs/foxglove.md, "What is dropped, when"), read from outside: the scheduling policy and
nice value of each of its threads in /proc/PID/task/TID/stat (field 41, `policy`: SCHED_OTHER 0, SCHED_IDLE 5
in linux/sched.h; field 19, `nice`), the thread named by its comm. By default the conversion thread, and only
it, is SCHED_IDLE, and the server's thread, and only it, has nice 10 (--server-nice); with
--conversion-priority normal --server-nice 0 every thread is SCHED_OTHER at nice 0; started at nice 19 (the
supervisor's nice, the shipped pipelines'), every thread stays at 19. Each time a
viewer (@foxglove/ws-protocol's client, priority_check.js) on this otherwise idle process still receives and
decodes the messages sent on LCM with hg-lcm-send: the last one kept for a late subscriber and one sent
while it is subscribed. No timing is asserted. Runs in its own network namespace."""
import json
import os
import subprocess
import threading
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SRC = os.environ.get("HG_SOURCE_DIR", os.path.join(HERE, "..", ".."))
BIN = os.environ.get("HG_BIN_DIR", os.path.join(SRC, "build", "bin"))
NPM = os.environ.get("HG_NPM_DIR", os.path.join(SRC, "build", "npm"))
PORT = 8765
SCHED_OTHER, SCHED_IDLE = 0, 5


def thread_policies(pid, field=41):
    """{tid: (comm, policy)} of a process's threads (field=19: (comm, nice))."""
    out = {}
    task = "/proc/%d/task" % pid
    for tid in os.listdir(task):
        with open(os.path.join(task, tid, "stat")) as f:
            stat = f.read()
        comm = stat[stat.index("(") + 1:stat.rindex(")")]
        fields = stat[stat.rindex(")") + 2:].split()  # from field 3, state
        out[int(tid)] = (comm, int(fields[field - 3]))
    return out


def send_query(job_id):
    subprocess.run([os.path.join(BIN, "hg-lcm-send"), "query", "--job-id", job_id], check=True,
                   capture_output=True, timeout=20)


class FoxglovePriority(unittest.TestCase):
    def serve(self, extra, prefix=()):
        fox = subprocess.Popen(list(prefix) + [os.path.join(BIN, "hg-foxglove"), "--port", str(PORT)] + extra,
                               stderr=subprocess.PIPE, text=True)
        self.addCleanup(lambda: (fox.terminate(), fox.wait(10)))
        for line in fox.stderr:
            if "serving the bus" in line:
                return fox
        self.fail("hg-foxglove did not start")

    def viewer_receives(self, tag):
        """A query on LCM before the viewer subscribes (kept as the channel's last message), another while it
        is subscribed: both must arrive and decode."""
        first, second = tag + "-before", tag + "-while-subscribed"
        env = dict(os.environ, NODE_PATH=os.path.join(NPM, "node_modules"))
        chk = subprocess.Popen(["node", os.path.join(HERE, "priority_check.js"), "ws://127.0.0.1:%d" % PORT,
                                "HG_JOB_REQUEST", "30", first, second], stdout=subprocess.PIPE, text=True, env=env)
        ready = threading.Event()
        # hg-foxglove subscribes to LCM just after it says it serves: the first query is sent until it came.
        repeat = threading.Thread(target=lambda: [send_query(first) for _ in range(25) if not ready.wait(1)])
        repeat.start()
        try:
            line = chk.stdout.readline().strip()
            ready.set()
            repeat.join()
            self.assertEqual(line, "ready")
            send_query(second)
            out, _ = chk.communicate(timeout=40)
        finally:
            if chk.poll() is None:
                chk.kill()
                chk.wait()
        self.assertEqual(chk.returncode, 0, out)
        got = json.loads(out.strip().splitlines()[-1])
        self.assertEqual([m["job_id"] for m in got], [first, second])
        self.assertEqual([m["action"] for m in got], [6, 6])  # job_request_t.QUERY, what hg-lcm-send query sends

    def test_conversion_idle_by_default(self):
        fox = self.serve([])
        self.viewer_receives("idle")
        threads = thread_policies(fox.pid)
        idle = {tid: comm for tid, (comm, policy) in threads.items() if policy == SCHED_IDLE}
        self.assertEqual(sorted(idle.values()), ["hg-fox-convert"], threads)
        for tid, (comm, policy) in threads.items():
            if tid not in idle:
                self.assertEqual(policy, SCHED_OTHER, threads)
        self.assertEqual(threads[fox.pid][1], SCHED_OTHER, "the main thread (LCM, heartbeat)")
        self.assertGreaterEqual(len(threads), 3, "main, conversion and server threads: %s" % threads)
        nice = thread_policies(fox.pid, 19)
        self.assertEqual(sorted((comm, n) for comm, n in nice.values() if n != 0), [("hg-fox-server", 10)], nice)

    def test_a_process_started_at_nice_19_keeps_every_thread_there(self):
        """The supervisor's nice = 19 (the shipped pipelines'): --server-nice 10 must not raise the server's
        thread above the rest of the process."""
        fox = self.serve([], prefix=["nice", "-n", "19"])
        self.viewer_receives("nice19")
        self.assertEqual({n for _, n in thread_policies(fox.pid, 19).values()}, {19})
        idle = [comm for comm, policy in thread_policies(fox.pid).values() if policy == SCHED_IDLE]
        self.assertEqual(idle, ["hg-fox-convert"])

    def test_conversion_normal_when_asked(self):
        fox = self.serve(["--conversion-priority", "normal", "--server-nice", "0"])
        self.viewer_receives("normal")
        threads = thread_policies(fox.pid)
        self.assertIn("hg-fox-convert", [comm for comm, _ in threads.values()], threads)
        self.assertIn("hg-fox-server", [comm for comm, _ in threads.values()], threads)
        self.assertEqual({policy for _, policy in threads.values()}, {SCHED_OTHER}, threads)
        self.assertEqual({n for _, n in thread_policies(fox.pid, 19).values()}, {0})


if __name__ == "__main__":
    unittest.main()
