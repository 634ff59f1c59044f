#!/usr/bin/env python3
"""Lichtblick's 3-D panel on a real job, live and recorded: screenshots for docs/foxglove.md.

In a network namespace of its own (tests/netns.sh), runs the shipped pipeline (config/pipeline.toml, with
its hg-foxglove on ws://127.0.0.1:8765) under tools/supervisor, sends a job, and while the simulated robot
grinds opens a built Lichtblick web app (APP: the folder its `yarn web:build:dev` or `web:build:prod`
writes, web/.webpack) in headless Chromium, connected to the live server with the layout
config/foxglove-layout.json (`?ds=foxglove-websocket&ds.url=…&layoutUrl=…`, Lichtblick's own URL
parameters). When the job has ended, the recorded bus goes through hg-mcap (as `make run` writes
out/run.mcap) and Lichtblick opens that file (`?ds=remote-file&ds.url=…&time=…`, halfway through the robot's
run) with the same layout. The app, the layout and the MCAP are served on 127.0.0.1:8090 from inside the
namespace. Exit status 1 when Lichtblick raised an alert for a topic it could not read (the raw
LCM_SELF_TEST aside).

Lichtblick is not a Debian or npm package (docs/foxglove.md says how to build it), so this script is not
part of `make test`; the live server's behaviour is tested there with @foxglove/ws-protocol's client.
"""
import argparse
import functools
import http.server
import os
import sys
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
SRC = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(SRC, "tests", "e2e"))
sys.path.insert(0, os.path.join(SRC, "tests", "station"))
sys.path.insert(0, os.path.join(HERE, "bench"))

from hgversion import version  # noqa: E402

LAYOUT = os.path.join(SRC, "config", "foxglove-layout.json")
PORT = 8090  # 8080 is the station's


class AppHandler(http.server.SimpleHTTPRequestHandler):
    """The app's files, the layout at /hullgrind-layout.json and the recording at /run.mcap (byte ranges, as
    Lichtblick reads a remote file)."""
    mcap = None

    def do_HEAD(self):
        self.reply(head=True)

    def do_GET(self):
        self.reply(head=False)

    def reply(self, head):
        path = self.path.split("?")[0]
        files = {"/hullgrind-layout.json": (LAYOUT, "application/json"), "/run.mcap": (self.mcap, "application/octet-stream")}
        if path not in files or not files[path][0]:
            return super().do_HEAD() if head else super().do_GET()
        name, kind = files[path]
        with open(name, "rb") as f:
            body = f.read()
        start, end, status = 0, len(body), 200
        want = self.headers.get("Range", "")
        if want.startswith("bytes="):
            first, _, last = want[6:].partition("-")
            start, end, status = int(first or 0), min(len(body), int(last) + 1 if last else len(body)), 206
        self.send_response(status)
        self.send_header("Content-Type", kind)
        self.send_header("Accept-Ranges", "bytes")
        self.send_header("Content-Length", str(end - start))
        if status == 206:
            self.send_header("Content-Range", "bytes %d-%d/%d" % (start, end - 1, len(body)))
        self.end_headers()
        if not head:
            self.wfile.write(body[start:end])

    def log_message(self, *args):
        pass


def serve(app_dir):
    handler = functools.partial(AppHandler, directory=app_dir)
    server = http.server.ThreadingHTTPServer(("127.0.0.1", PORT), handler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    return server


def app_url(source):
    """Lichtblick's URL for a data source ("ds=…&ds.url=…&…") with the layout."""
    return "http://127.0.0.1:%d/?%s&layoutUrl=http://127.0.0.1:%d/hullgrind-layout.json" % (PORT, source, PORT)


LIVE = "ds=foxglove-websocket&ds.url=ws://127.0.0.1:8765"


def recording_source(p):
    """hg-mcap on the run's bus, and Lichtblick's remote-file source halfway through the robot's run."""
    import datetime
    import e2e_pipeline as E
    from pipeline_latency import read_log
    mcap = os.path.join(p.dir, "run.mcap")
    out = E.run([E.bin_path("hg-mcap"), p.log, "-o", mcap, "--cell", os.path.join(SRC, "config", "cell-sim.yaml")], 120)
    if out.returncode != 0:
        raise RuntimeError("hg-mcap: " + out.stderr)
    times = [t for ch, t, _ in read_log(p.log, ("HG_GRIND_PATH", "HG_JOB_STATUS"))]
    path_t = [t for ch, t, _ in read_log(p.log, ("HG_GRIND_PATH",))][-1]
    mid = path_t + (max(times) - path_t) // 2
    when = datetime.datetime.fromtimestamp(mid / 1e6, datetime.timezone.utc).isoformat().replace("+00:00", "Z")
    AppHandler.mcap = mcap
    return "ds=remote-file&ds.url=http://127.0.0.1:%d/run.mcap&time=%s" % (PORT, when)


def picture(driver, url, out, settle):
    """Opens url, waits, shows the 3-D panel wide and saves the screenshot; returns the unreadable topics."""
    driver.get(url)
    time.sleep(settle)  # Lichtblick connects or reads, subscribes and draws
    close_left_sidebar(driver)
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    driver.save_screenshot(out)
    print("wrote", out)
    return [a for a in player_alerts(driver) if a not in RAW_CHANNELS]


# Channels of no hullgrind type, sent raw (encoding lcm): no viewer decodes them, by design.
RAW_CHANNELS = {"LCM_SELF_TEST"}


def player_alerts(driver):
    """The topics Lichtblick raised an alert for ("schema:TOPIC": a schema or message it could not read)."""
    alerts = []
    for entry in driver.get_log("browser"):
        text = entry.get("message", "")
        if "Player alert" in text and '"schema:' in text:
            alerts.append(text.split('"schema:', 1)[1].split('"', 1)[0])
    return sorted(set(alerts))


def close_left_sidebar(driver):
    """The panel-settings sidebar takes a fifth of the window; Lichtblick's "[" key toggles it (and the app
    remembers it closed for the next page)."""
    from selenium.webdriver.common.action_chains import ActionChains
    if "Select a panel to edit its settings" in driver.page_source:
        ActionChains(driver).send_keys("[").perform()
        time.sleep(1)


def shoot(args):
    import e2e_pipeline as E
    from station_browser_test import browser
    server = serve(os.path.abspath(args.app))
    p = E.Pipeline("lichtblick", extra_args={"planner": ["--small-hole", "skip"], "foxglove": []})
    driver = None
    try:
        p.start()
        time.sleep(6)  # the probes before the first job
        p.send("lichtblick-1", extra=["--grind-speed", "0.004"])
        p.wait_status("lichtblick-1", lambda s: s["state"] == "RUNNING", 180, "the robot to run")
        driver = browser()
        driver.set_window_size(args.width, args.height)
        unreadable = picture(driver, app_url(LIVE), args.out, args.settle)  # the robot moves on meanwhile
        p.wait_final("lichtblick-1", 600)
        p.stop()
        unreadable += picture(driver, app_url(recording_source(p)), args.recording_out, args.settle)
        if unreadable:
            print("Lichtblick could not read:", ", ".join(sorted(set(unreadable))))
            return 1
        return 0
    finally:
        if driver:
            driver.quit()
        server.shutdown()
        p.stop()
        p.cleanup(failed=False)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], epilog=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--version", action="version", version="lichtblick-screenshot.py " + version())
    ap.add_argument("--app", required=True, help="the built Lichtblick web app (its web/.webpack folder)")
    ap.add_argument("--out", default=os.path.join(SRC, "docs", "foxglove", "lichtblick-live.png"),
                    help="the screenshot [docs/foxglove/lichtblick-live.png]")
    ap.add_argument("--recording-out", default=os.path.join(SRC, "docs", "foxglove", "lichtblick-recording.png"),
                    help="the screenshot of the recording [docs/foxglove/lichtblick-recording.png]")
    ap.add_argument("--width", type=int, default=1600, help="window width [1600]")
    ap.add_argument("--height", type=int, default=1000, help="window height [1000]")
    ap.add_argument("--settle", type=float, default=20, help="seconds between opening the app and the picture [20]")
    args = ap.parse_args()
    if not os.path.isfile(os.path.join(args.app, "index.html")):
        ap.error("--app %s: no index.html (build Lichtblick's web app first, docs/foxglove.md)" % args.app)
    if os.environ.get("HG_IN_NETNS") != "1":
        os.execv(os.path.join(SRC, "tests", "netns.sh"),
                 [os.path.join(SRC, "tests", "netns.sh"), "--own-pids", "/usr/bin/python3", os.path.abspath(__file__)]
                 + sys.argv[1:])
    sys.exit(shoot(args))


if __name__ == "__main__":
    main()
