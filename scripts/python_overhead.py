#!/usr/bin/python3
"""A style run on an existing G-buffer from Python against the same run from C++ (issue 50 item 6;
docs/performance.md "Python"), in the same minutes, alternating.

Usage: PYTHONPATH=build/python /usr/bin/python3 scripts/python_overhead.py [BENCH] [--rounds N]
  BENCH: the aquarelle_bench binary (default build/bench/aquarelle_bench). Each round runs the
  Google Benchmark style/run_on_gbuffer/waterbottle/wc18/1280x720 (app::run_style_on, 2 threads),
  then times aquarelle.Style("wc18").run(gb) on the same scene, size and threads in a loop (median
  of 15 after 3 warm-up runs). Prints each round and the median ratio Python / C++.
"""
import argparse, json, os, statistics, subprocess, time

import aquarelle as aq

ap = argparse.ArgumentParser()
ap.add_argument("bench", nargs="?", default="build/bench/aquarelle_bench")
ap.add_argument("--rounds", type=int, default=3)
a = ap.parse_args()
shared = os.environ.get("AQ_SHARED", os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared"))
scene = aq.load_scene(os.path.join(shared, "assets/gltf/WaterBottle/glTF/WaterBottle.gltf"))
gb = aq.rasterize(scene, 1280, 720, threads=2, style="wc18")
style = aq.style("wc18")
ratios = []
for r in range(a.rounds):
    out = subprocess.run([a.bench, "--benchmark_filter=^style/run_on_gbuffer/waterbottle/wc18/", "--benchmark_format=json"],
                         capture_output=True, text=True, check=True)
    cpp = json.loads(out.stdout)["benchmarks"][0]["real_time"]
    for _ in range(3):
        style.run(gb)
    ts = []
    for _ in range(15):
        t0 = time.perf_counter()
        style.run(gb)
        ts.append((time.perf_counter() - t0) * 1000)
    py = statistics.median(ts)
    ratios.append(py / cpp)
    print("round %d: C++ %.1f ms, Python %.1f ms (median of 15), ratio %.3f" % (r + 1, cpp, py, py / cpp), flush=True)
print("median ratio Python / C++: %.3f over %d rounds" % (statistics.median(ratios), a.rounds))
