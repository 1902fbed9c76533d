// bench/ld06_frame_bench.cpp — the whole LD06 frame (issue 12 "Speed"): the ld06 preset as the CLI
// configures it (app::prepare_render: layer colours, foliage abstraction once per job), one frame =
// every pass and stage at 720 x 720 with 520 x 520 intermediates, on the shared dense oak
// (16,993 particles) and bush, 1 and 2 threads. Counters split the frame into the paper's Table 2
// columns (GeForce 6800; tree 13d: 9.8 / 41.9 / 7.1 / 3.3 ms, 16.1 fps):
//   lsd_ms     light/shadow/depth: depth, light depth, their blurs, shadow, lighting
//   imaps_ms   intensity maps: layer IDs and their split, particles
//   wc_ms      watercolor: layer_wash, color_ramp, glaze, shadow_layer, substrate_light
//   strokes_ms strokes: the strokes pass and stroke_ink
// The G-buffer is not rendered (ld06 reads none); file encoding is not included (BM_Cli_* measure
// whole CLI runs). Run: aquarelle_bench --benchmark_filter=BM_Ld06Frame (AQ_BENCH_STEPS=1: a
// counter per step as well; AQ_NO_IN_PLACE=1: in-place steps off, to compare)
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "app/render_job.h"
#include "bench/bench_inputs.h"
#include "raster/pass.h"

namespace {

using namespace aq;

const char* column_of(const stylize::CompiledStep& s) {
    const std::string& st = s.variant->stage;
    if (st == "particles" || st == "layer_id" || st == "id_layers" || st == "intensity" || st == "intensity_texture")
        return "imaps_ms";
    if (st == "strokes" || st == "stroke_ink") return "strokes_ms";
    if (s.pass || st == "gaussian_blur") return "lsd_ms";
    return "wc_ms";
}

void BM_Ld06Frame(benchmark::State& st, const std::string& model, int threads) {
    app::RenderOptions o;
    o.scene = std::string(AQ_SHARED_DIR) + "/assets/plants/ez-tree/" + model;
    o.style = "ld06";
    o.style_given = true;
    o.width = o.height = 720;
    o.threads = threads;
    o.quiet = true;
    app::RenderJob job = app::prepare_render(o, app::Reporter{});
    const raster::AbstractedScene& a = *job.pass_scenes[0];
    raster::PassScene ps = raster::make_pass_scene(a.scene, job.desc.camera, 720, 720);
    ps.layers = &job.pass_layers[0];
    ps.contours = &job.pass_contours[0];
    if (a.abstracted) {
        ps.foliage_surface = &a.surface;
        ps.plant_height = a.height;
    }
    Targets t;
    std::vector<std::string> warnings;
    std::vector<double> ms;
    stylize::RunOptions ro;
    ro.exec = Exec::fast(threads);
    ro.scene = &ps;
    ro.warnings = &warnings;
    ro.step_ms = &ms;
    ro.reuse_outputs = true;  // as an animation's frames
    ro.fuse = true;           // as the render job without --targets
    ro.in_place = std::getenv("AQ_NO_IN_PLACE") == nullptr;
    for (int k = 0; k < bench::kWarmUpFrames; ++k) stylize::run_pipeline(job.compiled[0], t, ro);  // buffers, paper
    std::map<std::string, double> sum, step;
    const bool per_step = std::getenv("AQ_BENCH_STEPS") != nullptr;  // also one counter per step
    for (auto _ : st) {
        raster::PassFrameCache frames;  // per frame, as the render job
        ps.frames = &frames;
        stylize::run_pipeline(job.compiled[0], t, ro);
        ps.frames = nullptr;
        for (std::size_t i = 0; i < ms.size(); ++i) {
            sum[column_of(job.compiled[0].steps[i])] += ms[i];
            if (per_step) step[std::to_string(100 + i).substr(1) + "_" + job.compiled[0].steps[i].label.substr(0, job.compiled[0].steps[i].label.find(' '))] += ms[i];
        }
    }
    for (auto& [k, v] : sum) st.counters[k] = v / double(st.iterations());
    for (auto& [k, v] : step) st.counters[k] = v / double(st.iterations());
}

const bool kRegistered = [] {
    for (const char* model : {"ez_oak_large_dense.glb", "ez_bush2.glb"})
        for (int threads : {1, 2})
            benchmark::RegisterBenchmark(("BM_Ld06Frame/" + std::string(model) + "/threads:" + std::to_string(threads)).c_str(),
                                         BM_Ld06Frame, std::string(model), threads)
                ->Unit(benchmark::kMillisecond)
                ->UseRealTime();
    return true;
}();

}  // namespace
