// bench/style_run_bench.cpp — a style run on an existing G-buffer from C++ (issue 50 item 6): what
// aquarelle.Style.run(gb) does in Python (app::run_style_on: the G-buffer lent to an unfused run,
// every intermediate and the final image kept). scripts/python_overhead.py times the same run from
// Python in the same minutes and gives the ratio (docs/performance.md "Python").
//
//   style/run_on_gbuffer/<scene>/<style>/1280x720: 2 threads, wall time; the G-buffer and the
//     style's job are made once, outside the timed loop (as a Python loop over one G-buffer).
#include <string>

#include <benchmark/benchmark.h>

#include "app/render_job.h"

namespace {

struct Case {
    std::string name, scene, style;
};

void bm_run_on_gbuffer(benchmark::State& st, Case c) {
    aq::app::RenderOptions o;
    o.scene = c.scene;
    o.style = c.style;
    o.style_given = true;
    o.width = 1280;
    o.height = 720;
    o.threads = 2;
    o.quiet = true;
    o.live = true;
    o.keep_intermediates = true;
    const aq::app::RenderJob job = aq::app::prepare_render(o, aq::app::Reporter{});
    aq::Targets gbuffer = aq::app::render_gbuffer(job, 0);
    for (auto _ : st) {
        aq::Targets out = aq::app::run_style_on(job, gbuffer, 0);
        benchmark::DoNotOptimize(out.get("final").data());
    }
}

const int registered = [] {
    const Case cases[] = {
        {"waterbottle/wc18", std::string(AQ_SHARED_DIR) + "/assets/gltf/WaterBottle/glTF/WaterBottle.gltf", "wc18"},
    };
    for (const Case& c : cases)
        benchmark::RegisterBenchmark(("style/run_on_gbuffer/" + c.name + "/1280x720").c_str(), bm_run_on_gbuffer, c)
            ->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0);
    return 0;
}();

}  // namespace
