#!/usr/bin/env python3
"""Lichtblick's 3-D panel on a real job: a screenshot for docs/foxglove.md.

In a network namespace of its own (tests/netns.sh), runs the shipped pipeline (config/pipeline.toml, with
its hg-foxglove on ws://127.0.0.1:8765) under tools/supervisor, sends a job, and while the simulated robot
grinds opens a built Lichtblick web app (APP: the folder its `yarn web:build:dev` or `web:build:prod`
writes, web/.webpack) in headless Chromium, connected to the live server with the layout
config/foxglove-layout.json (`?ds=foxglove-websocket&ds.url=…&layoutUrl=…`, Lichtblick's own URL
parameters). The app and the layout are served on 127.0.0.1:8090 from inside the namespace.

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

from hgversion import version  # noqa: E402

LAYOUT = os.path.join(SRC, "config", "foxglove-layout.json")
PORT = 8090  # 8080 is the station's


class AppHandler(http.server.SimpleHTTPRequestHandler):
    """The app's files, and the layout at /hullgrind-layout.json."""

    def do_GET(self):
        if self.path.split("?")[0] == "/hullgrind-layout.json":
            with open(LAYOUT, "rb") as f:
                body = f.read()
            self.send_response(200)
            self.send_header("Content-Type", "application/json")
            self.send_header("Content-Length", str(len(body)))
            self.end_headers()
            self.wfile.write(body)
            return
        super().do_GET()

    def log_message(self, *args):
        pass


def serve(app_dir):
    handler = functools.partial(AppHandler, directory=app_dir)
    server = http.server.ThreadingHTTPServer(("127.0.0.1", PORT), handler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    return server


def app_url():
    ws = "ws://127.0.0.1:8765"
    return ("http://127.0.0.1:%d/?ds=foxglove-websocket&ds.url=%s&layoutUrl=http://127.0.0.1:%d/hullgrind-layout.json"
            % (PORT, ws, PORT))


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
    """The panel-settings sidebar takes a fifth of the window; Lichtblick's "[" key toggles it."""
    from selenium.webdriver.common.action_chains import ActionChains
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
        driver.get(app_url())
        time.sleep(args.settle)  # Lichtblick connects, subscribes and draws; the robot moves on meanwhile
        close_left_sidebar(driver)
        os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
        driver.save_screenshot(args.out)
        print("wrote", args.out)
        unreadable = [a for a in player_alerts(driver) if a not in RAW_CHANNELS]
        if unreadable:
            print("Lichtblick could not read:", ", ".join(unreadable))
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
