#!/usr/bin/python3
"""Latency of `aquarelle serve` as a browser sees it (docs/performance.md "Live view").

Usage: scripts/serve_latency.py AQUARELLE SCENE PARAM LO HI [--style S] [--size WxH] [--changes N]
Starts the server, opens the page in headless Chromium, and
  - makes N changes of PARAM (values from LO to HI), each after the previous image is on screen,
    and reports the median and 95th percentile of change -> image decoded (the page's
    performance.now(), window.aq.latencies);
  - drags the camera for 5 s (a request per mouse move, as a user's drag) with preview JPEGs, as
    the page does, then 5 s with a PNG for every move, and reports images shown per second.
"""
import argparse, shutil, statistics, subprocess, sys, tempfile, time
from selenium import webdriver
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.support.ui import WebDriverWait

ap = argparse.ArgumentParser()
ap.add_argument("exe"); ap.add_argument("scene"); ap.add_argument("param"); ap.add_argument("lo", type=float); ap.add_argument("hi", type=float)
ap.add_argument("--style", default=""); ap.add_argument("--size", default="1280x720"); ap.add_argument("--changes", type=int, default=30)
ap.add_argument("--drags", type=int, default=1, help="rounds of the two 5 s drags (preview JPEG, PNG)")
a = ap.parse_args()
w, h = a.size.split("x")
out_dir = tempfile.mkdtemp(prefix="aq-serve-latency.")  # Save is not used; its own folder anyway
cmd = [a.exe, "serve", a.scene, "--width", w, "--height", h, "--quiet", "--out-dir", out_dir] + (["--style", a.style] if a.style else [])
srv = subprocess.Popen(cmd, stdout=subprocess.PIPE, text=True)
url = srv.stdout.readline().strip()
o = webdriver.ChromeOptions(); o.binary_location = "/usr/bin/chromium"
for f in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--window-size=1800,1000"): o.add_argument(f)
d = webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=o)
try:
    d.get(url)
    WebDriverWait(d, 60).until(lambda d: d.execute_script("return !!window.aq && window.aq.schema !== null && document.getElementById('view').naturalWidth > 0"))
    d.execute_script("window.aq.latencies = [];")
    for i in range(a.changes):
        v = a.lo + (a.hi - a.lo) * i / max(1, a.changes - 1)
        seq = d.execute_script("return window.aq.seq")
        d.execute_script("window.aq.state.params[arguments[0]] = arguments[1]; window.aq.render();", a.param, v)
        WebDriverWait(d, 60).until(lambda d: d.execute_script("return window.aq.shownSeq > arguments[0] || window.aq.lastError !== ''", seq))
        err = d.execute_script("return window.aq.lastError")
        if err: sys.exit("error: " + err)
    lat = sorted(d.execute_script("return window.aq.latencies"))
    p95 = lat[min(len(lat) - 1, int(round(0.95 * (len(lat) - 1))))]
    print("%s %s %s: parameter change -> image on screen: median %.0f ms, p95 %.0f ms, min %.0f, max %.0f (%d changes)"
          % (a.scene.split("/")[-1], a.style or "(scene's style)", a.size, statistics.median(lat), p95, lat[0], lat[-1], len(lat)))
    # Camera drag: a mouse move every 16 ms for 5 s; count the images shown. As the page drags
    # (preview JPEGs while moving: aq.renderMoving), and with the still PNG for every move, in turn.
    def drag(call):
        shown0 = d.execute_script("return window.aq.latencies.length")
        t0 = time.time(); k = 0
        while time.time() - t0 < 5.0:
            k += 1
            d.execute_script("window.aq.state.view = [arguments[0], 10, 1]; window.aq." + call + "();", (k * 2) % 360)
            time.sleep(0.016)
        time.sleep(0.5)
        return (d.execute_script("return window.aq.latencies.length") - shown0) / 5.0, k
    for r in range(a.drags):
        for call, what in (("renderMoving", "preview JPEG"), ("render", "PNG")):
            rate, k = drag(call)
            print("camera drag (%s): %.1f images/s shown (%d requests in 5 s, the server renders the newest)" % (what, rate, k))
finally:
    d.quit(); srv.terminate(); srv.wait(); shutil.rmtree(out_dir, ignore_errors=True)
