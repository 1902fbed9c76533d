// bench/stylize_bench.cpp — Google Benchmark for the stylization library: one benchmark per
// registered stage variant (found by iterating builtin_registry(), so every group's stages are
// covered) at 1920x1080 and 640x360, reference and fast traversal, 1 and 2 threads, items =
// output pixels; and every preset pipeline end to end (fast, 1 and 2 threads); the overlaps' RYB
// inverse one and four colours per call (stylize/ryb/inverse/{scalar,lanes}).
// Inputs are the one synthetic G-buffer of tests, benchmarks and reference (tests/synthetic_gbuffer.h:
// three spheres over a slanted ground plane, painted control over the signed range on the objects
// and none on the background; intermediates get a smooth-plus-edges pattern).
// Results: docs/performance.md "Stylization".
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "bench/bench_inputs.h"
#include "stylize/paper.h"
#include "stylize/pipeline.h"
#include "stylize/ryb.h"
#include "stylize/stage.h"
#include "tests/synthetic_gbuffer.h"

namespace aq::stylize {
namespace {

struct Size {
    int w, h;
    const char* name;
};
constexpr Size kSizes[] = {{1920, 1080, "1920x1080"}, {640, 360, "640x360"}};

//! Inputs for one variant at one size, built once and kept for every run of that benchmark.
struct StageInputs {
    std::vector<ImageF> in;
    ImageF paper;
    Globals g;
};

const StageInputs& inputs_for(const StageVariant& v, const Size& s) {
    static std::map<std::string, std::unique_ptr<StageInputs>> cache;
    const std::string key = v.key() + "@" + s.name;
    auto& slot = cache[key];
    if (!slot) {
        slot = std::make_unique<StageInputs>();
        std::uint32_t seed = 3;
        for (const Port& p : v.inputs) slot->in.push_back(test::synthetic_target(p.default_target, p.channels, s.w, s.h, seed++));
        slot->paper = bench::stage_paper(s.w, s.h);
        slot->g.paper = &slot->paper;
    }
    return *slot;
}

void bm_stage(benchmark::State& st, const StageVariant* v, Size s, Exec ex) {
    const StageInputs& data = inputs_for(*v, s);
    const ParamValues pv = Registry::resolve_params(*v, {}, "bench");
    std::vector<ImageF> outs(v->outputs.size());
    StageIO io;
    io.globals = &data.g;
    for (auto& i : data.in) io.in.push_back(&i);
    for (auto& o : outs) io.out.push_back(&o);
    for (auto _ : st) {
        v->run(io, pv, ex);
        benchmark::DoNotOptimize(outs.front().data());
    }
    st.SetItemsProcessed(st.iterations() * std::int64_t(s.w) * s.h);
    st.counters["threads"] = ex.traversal == Traversal::Reference ? 1 : ex.threads;
}

//! The schedules of a frame loop (the same bytes in each):
//!   Steps      every step writes its own output image (what `--targets` needs: every
//!              intermediate kept) (pipeline/STYLE/SIZE/fast/threads:N, the series of issue 13 item 4)
//!   RowGroups  Steps with the compiled pipeline's row groups run band by band ("/row_groups")
//!   Cli        what `aquarelle render` runs without --targets (app/render_job.cpp): fused pairs
//!              (stage.h Fusion) and steps in place on dead intermediates ("/cli")
//!   CliRowGroups Cli with the row groups the in-place steps leave ("/cli_row_groups": what
//!              `aquarelle render --row-groups` runs)
enum class Schedule { Steps, RowGroups, Cli, CliRowGroups };

void bm_pipeline(benchmark::State& st, std::string preset, Size s, int threads, Schedule schedule) {
    Pipeline p = load_pipeline(preset);
    Targets t = test::synthetic_gbuffer(s.w, s.h);
    RunOptions o;
    o.exec = Exec::fast(threads);
    o.row_groups = schedule == Schedule::RowGroups || schedule == Schedule::CliRowGroups;
    o.fuse = o.in_place = schedule == Schedule::Cli || schedule == Schedule::CliRowGroups;
    o.reuse_outputs = true;  // a frame loop: outputs of the previous frame are reused
    for (int k = 0; k < bench::kWarmUpFrames; ++k) run_pipeline(p, t, o);  // also prepares and keeps "paper"
    for (auto _ : st) {
        run_pipeline(p, t, o);
        benchmark::DoNotOptimize(t.get(p.output).data());
    }
    st.SetItemsProcessed(st.iterations() * std::int64_t(s.w) * s.h);
    st.counters["threads"] = threads;
}

//! Where a frame goes: the pipeline with a progress callback timing each step, reported as
//! counters "NN_stage" in ms per frame: CPU time of the calling thread between step starts (with
//! threads:1 that is all of the step's work, and it is far less disturbed by other load on the
//! machine than wall time). `reuse` ("/reuse")
//! = the frame-loop path (RunOptions::reuse_outputs); off ("/fresh") = fresh targets every run;
//! `cli` ("/cli", with reuse) = also fused pairs and steps in place, as `aquarelle render`
//! runs an animation without --targets (a fused pair's time is its consumer's).
void bm_profile(benchmark::State& st, std::string preset, Size s, int threads, bool reuse, bool cli = false) {
    struct Clock {  // CPU time of the calling thread
        using time_point = std::chrono::duration<double, std::milli>;
        static time_point now() {
            timespec ts{};
            clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
            return time_point(double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6);
        }
    };
    Pipeline p = load_pipeline(preset);
    const Targets g = test::synthetic_gbuffer(s.w, s.h);
    Targets t = g;
    RunOptions o;
    o.exec = Exec::fast(threads);
    o.reuse_outputs = reuse;
    o.fuse = o.in_place = cli;  // bm_pipeline's Schedule::Cli
    o.row_groups = false;  // step by step (also the default): a row group's steps would share one time
    std::vector<std::string> names;
    std::vector<double> ms;
    Clock::time_point last;
    int current = -1;
    o.progress = [&](int i, int, const std::string& step) {
        const Clock::time_point now = Clock::now();
        if (current >= 0) ms[std::size_t(current)] += (now - last).count();
        if (names.size() <= std::size_t(i)) {
            names.resize(std::size_t(i) + 1);
            ms.resize(std::size_t(i) + 1);
        }
        names[std::size_t(i)] = step.substr(0, step.find(' '));
        current = i;
        last = now;
    };
    auto frame = [&] {
        if (!reuse) t = g;  // the CLI path: only the G-buffer exists before the run
        current = -1;
        run_pipeline(p, t, o);
        ms[std::size_t(current)] += (Clock::now() - last).count();
    };
    for (int k = 0; k < bench::kWarmUpFrames; ++k) frame();
    std::fill(ms.begin(), ms.end(), 0.0);
    for (auto _ : st) {
        frame();
        benchmark::DoNotOptimize(t.get(p.output).data());
    }
    for (std::size_t i = 0; i < names.size(); ++i) {
        char key[64];
        std::snprintf(key, sizeof key, "%02zu_%s", i, names[i].c_str());
        st.counters[key] = ms[i] / double(st.iterations());
    }
    st.SetItemsProcessed(st.iterations() * std::int64_t(s.w) * s.h);
}

const bool kRegistered = [] {
    for (const StageVariant* v : builtin_registry().all())
        for (const Size& s : kSizes) {
            const std::string base = "stage/" + v->key() + "/" + s.name;
            benchmark::RegisterBenchmark((base + "/reference").c_str(), bm_stage, v, s, Exec::reference())
                ->Unit(benchmark::kMillisecond)
                ->UseRealTime();
            for (int threads : {1, 2})
                benchmark::RegisterBenchmark((base + "/fast/threads:" + std::to_string(threads)).c_str(), bm_stage, v,
                                             s, Exec::fast(threads))
                    ->Unit(benchmark::kMillisecond)
                    ->UseRealTime();
        }
    // Image pipelines only: presets with raster passes (ld06) need a scene, bench/ld06_frame_bench.cpp.
    std::vector<std::string> image_presets;
    for (const std::string& preset : preset_names())
        if (!compile_pipeline(load_pipeline(preset)).has_passes) image_presets.push_back(preset);
    for (const std::string& preset : image_presets)
        for (const Size& s : kSizes)
            for (int threads : {1, 2})
                for (Schedule schedule : {Schedule::RowGroups, Schedule::Steps, Schedule::Cli, Schedule::CliRowGroups})
                    benchmark::RegisterBenchmark(("pipeline/" + preset + "/" + s.name + "/fast/threads:" +
                                                  std::to_string(threads) +
                                                  (schedule == Schedule::RowGroups ? "/row_groups"
                                                   : schedule == Schedule::Cli     ? "/cli"
                                                   : schedule == Schedule::CliRowGroups ? "/cli_row_groups"
                                                                                   : ""))
                                                     .c_str(),
                                                 bm_pipeline, preset, s, threads, schedule)
                        ->Unit(benchmark::kMillisecond)
                        ->UseRealTime();
    for (const std::string& preset : image_presets)
        for (const Size& s : kSizes)
            for (int threads : {1, 2})
                for (int mode : {0, 1, 2})  // fresh, reuse, cli (reuse + fused pairs + in place)
                    benchmark::RegisterBenchmark(("profile/" + preset + "/" + s.name + "/fast/threads:" +
                                                  std::to_string(threads) +
                                                  (mode == 0 ? "/fresh" : mode == 1 ? "/reuse" : "/cli"))
                                                     .c_str(),
                                                 bm_profile, preset, s, threads, mode != 0, mode == 2)
                        ->Unit(benchmark::kMillisecond)
                        ->UseRealTime();
    return true;
}();

// The overlaps' RGB -> RYB inverse (stylize/ryb.h) over 4096 colours of the cube's image, some
// darkened (as painted pixels are): one conversion per call, and all of them in one call (rgb_to_ryb_many: four lanes).
void bm_ryb_inverse(benchmark::State& st, bool lanes) {
    std::vector<glm::vec3> in(4096), out(in.size());
    for (std::size_t i = 0; i < in.size(); ++i) {
        auto u = [&](unsigned k) { return float(((i * 4 + k) * 2654435761u) >> 8 & 0xffffff) / float(1 << 24); };
        in[i] = ryb_to_rgb({u(0), u(1), u(2)}) * (i % 2 ? 1.0f : 0.3f + 0.7f * u(3));
    }
    for (auto _ : st) {
        if (lanes) {
            rgb_to_ryb_many(in.data(), out.data(), in.size());
        } else {
            for (std::size_t i = 0; i < in.size(); ++i) out[i] = rgb_to_ryb(in[i]);
        }
        benchmark::DoNotOptimize(out.data());
        benchmark::ClobberMemory();
    }
    st.SetItemsProcessed(std::int64_t(st.iterations()) * std::int64_t(in.size()));
}

const bool ryb_registered = [] {
    benchmark::RegisterBenchmark("stylize/ryb/inverse/scalar", bm_ryb_inverse, false)->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark("stylize/ryb/inverse/lanes", bm_ryb_inverse, true)->Unit(benchmark::kMicrosecond);
    return true;
}();

}  // namespace
}  // namespace aq::stylize

namespace aq::bench {

const ImageF& stage_paper(int w, int h) {
    static std::map<std::pair<int, int>, ImageF> cache;  // benchmarks are registered and run on one thread
    auto it = cache.find({w, h});
    if (it == cache.end()) {
        const stylize::Pipeline wc18 = stylize::load_pipeline("wc18");
        it = cache.emplace(std::pair{w, h}, wc18.has_paper ? stylize::prepare_paper(wc18.paper, w, h)
                                                           : stylize::flat_paper(w, h)).first;
    }
    return it->second;
}

}  // namespace aq::bench
