// bench/serve_bench.cpp — the server-side part of `aquarelle serve`'s latency (issue 49 item 4):
// app::render_live, what the render thread does for a page's message, PNG encoding included.
//
//   serve/param/<scene>/<style>/1280x720: a parameter value changes every iteration (two values
//     alternate): the live image continues the last one from the first step that reads it
//   serve/camera/<scene>/<style>/1280x720: the view turns every iteration: G-buffer and every step
//   serve/camera_preview/...: the same with the preview JPEG the page asks for while dragging
//   serve/scene_edit/<scene>/<style>/1280x720: a value of the scene file's art direction changes
//     every iteration (a light's direction, a layer's colour)
// The browser's part (WebSocket, decoding, display) is measured by scripts/serve_latency.py in
// headless Chromium; docs/performance.md "Live view" gives both. 2 threads, wall time.
#include <string>

#include <benchmark/benchmark.h>

#include "app/serve.h"

namespace {

struct Case {
    std::string name, scene, style, param;
    double a, b;
};

aq::app::RenderOptions options(const Case& c) {
    aq::app::RenderOptions o;
    o.scene = c.scene;
    o.style = c.style;
    o.style_given = true;
    o.width = 1280;
    o.height = 720;
    o.threads = 2;
    o.quiet = true;
    o.out = "live.png";
    return o;
}

void bm_param(benchmark::State& st, Case c) {
    aq::app::LiveState live;
    int i = 0;
    (void)aq::app::render_live(options(c), "view", "final", false, live);  // the page's first image: not timed
    for (auto _ : st) {
        aq::app::RenderOptions o = options(c);
        o.sets = {c.param + "=" + std::to_string(i++ % 2 ? c.a : c.b)};
        const aq::app::LiveImage img = aq::app::render_live(o, "view", "final", false, live);
        if (img.first_step == 0) st.SkipWithError("the live image did not continue the previous one");
        benchmark::DoNotOptimize(img.bytes.data());
    }
}

void bm_camera(benchmark::State& st, Case c, bool preview) {
    aq::app::LiveState live;
    int i = 0;
    (void)aq::app::render_live(options(c), "view", "final", false, live);  // loads the scene: not timed
    for (auto _ : st) {
        aq::app::RenderOptions o = options(c);
        o.view_yaw = double(++i % 60);
        const aq::app::LiveImage img = aq::app::render_live(o, "view " + std::to_string(i), "final", false, live, preview);
        benchmark::DoNotOptimize(img.bytes.data());
    }
}

//! An edit of the scene file's art direction, a new value every iteration (as while typing or
//! picking a colour): the scene file read again with the edit, the model from memory, a new frame.
void bm_scene_edit(benchmark::State& st, Case c) {
    aq::app::LiveState live;
    int i = 0;
    (void)aq::app::render_live(options(c), "view", "final", false, live);  // loads the scene: not timed
    for (auto _ : st) {
        aq::app::RenderOptions o = options(c);
        const double v = c.a + (c.b - c.a) * double(++i % 97) / 97.0;
        o.scene_edits = {{c.param, "[" + std::to_string(v) + "," + std::to_string(v) + "," + std::to_string(v) + "]"}};
        const aq::app::LiveImage img = aq::app::render_live(o, "edit " + o.scene_edits[0].value, "final", false, live);
        benchmark::DoNotOptimize(img.bytes.data());
    }
}

const int registered = [] {
    const std::string shared = std::string(AQ_SHARED_DIR) + "/assets/";
    const Case cases[] = {
        {"waterbottle/wc18", shared + "gltf/WaterBottle/glTF/WaterBottle.gltf", "wc18", "edge_darken.intensity", 1.0, 2.0},
        {"oak_scene/ld06", std::string(AQ_SOURCE_DIR) + "/scenes/data/oak.json", "ld06", "wash.kappa", 0.3, 0.6},
    };
    for (const Case& c : cases) {
        benchmark::RegisterBenchmark(("serve/param/" + c.name + "/1280x720").c_str(), bm_param, c)
            ->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0);
        benchmark::RegisterBenchmark(("serve/camera/" + c.name + "/1280x720").c_str(), bm_camera, c, false)
            ->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0);
        benchmark::RegisterBenchmark(("serve/camera_preview/" + c.name + "/1280x720").c_str(), bm_camera, c, true)
            ->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0);
    }
    const Case edits[] = {
        {"waterbottle_scene/wc18", std::string(AQ_SOURCE_DIR) + "/scenes/data/waterbottle.json", "wc18", "/lights/0/direction", 0.3, 0.6},
        {"oak_scene/ld06", std::string(AQ_SOURCE_DIR) + "/scenes/data/oak.json", "ld06", "/layers/1/color", 0.3, 0.6},
    };
    for (const Case& c : edits)
        benchmark::RegisterBenchmark(("serve/scene_edit/" + c.name + "/1280x720").c_str(), bm_scene_edit, c)
            ->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0);
    return 0;
}();

}  // namespace
