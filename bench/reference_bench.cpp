// bench/reference_bench.cpp — the GPU-equivalent reference (GLSL twins through OpenGL; llvmpipe on
// our machines) timed beside the C++ stages of bench/stylize_bench.cpp in the same binary, so every
// ratio comes from one run. Names pair with the C++ ones by prefix:
//   gl/stage/<stage>/<variant>/<size>      vs  stage/<stage>/<variant>/<size>/fast/threads:2
//   gl/pipeline/<preset>/<size>            vs  pipeline/<preset>/<size>/fast/threads:2
// Each iteration runs every pass of the twin and reads the stage's outputs back (glReadPixels,
// GL_FLOAT), which waits for the GPU/llvmpipe to finish; the inputs are uploaded once, outside the
// timed loop (a G-buffer already lives on the GPU in a real renderer). One untimed warm-up run per
// benchmark absorbs program compilation and LLVM JIT (~110 ms per shader), so the result does not
// depend on Mesa's shader cache (MESA_SHADER_CACHE_DISABLE is not needed and not set).
// llvmpipe uses LP_NUM_THREADS rasterizer threads (default: all cores, 2 here).
// Inputs are exactly those of the paired C++ benchmarks (tests/synthetic_gbuffer.h: the same
// per-port synthetic targets and seeds, bench/bench_inputs.h stage_paper for single stages; the
// preset's paper for pipelines), so both sides process the same data. Results: docs/performance.md
// "## C++ vs GLSL on llvmpipe".
#ifdef AQ_HAVE_REFERENCE

#include <map>
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "bench/bench_inputs.h"
#include "reference/gl_context.h"
#include "reference/gl_runner.h"
#include "reference/stage_twin.h"
#include "stylize/paper.h"
#include "stylize/pipeline.h"
#include "tests/synthetic_gbuffer.h"

namespace aq::ref {
namespace {

struct Size {
    int w, h;
    const char* name;
};
constexpr Size kSizes[] = {{1920, 1080, "1920x1080"}, {640, 360, "640x360"}};

bool gl_ready(benchmark::State& st) {
    std::string why;
    if (GlContext::shared(&why)) return true;
    st.SkipWithError(("no OpenGL context: " + why).c_str());
    return false;
}

void bm_gl_stage(benchmark::State& st, const stylize::StageVariant* v, Size s) {
    if (!gl_ready(st)) return;
    std::vector<Texture> up;
    std::vector<const Texture*> ins;
    up.reserve(v->inputs.size());
    std::uint32_t seed = 3;  // as bench/stylize_bench.cpp inputs_for()
    for (auto& p : v->inputs) {
        up.push_back(Texture::upload(test::synthetic_target(p.default_target, p.channels, s.w, s.h, seed++)));
        ins.push_back(&up.back());
    }
    const Texture paper = Texture::upload(bench::stage_paper(s.w, s.h));  // as stylize_bench.cpp inputs_for()
    const auto params = stylize::Registry::resolve_params(*v, {}, "bench");
    const StageTwin twin(*v);
    const glm::vec3 substrate(1.0f);  // stylize::Globals default
    {  // warm-up: compile + JIT every pass
        auto outs = twin.run(ins, params, substrate, &paper);
        for (auto& o : outs) benchmark::DoNotOptimize(read_texture(o).data());
    }
    for (auto _ : st) {
        auto outs = twin.run(ins, params, substrate, &paper);
        for (auto& o : outs) benchmark::DoNotOptimize(read_texture(o).data());
    }
    st.SetItemsProcessed(st.iterations() * std::int64_t(s.w) * s.h);
    st.counters["passes"] = twin.num_passes();
}

void bm_gl_pipeline(benchmark::State& st, std::string preset, Size s) {
    if (!gl_ready(st)) return;
    stylize::Pipeline p = stylize::load_pipeline(preset);
    std::map<std::string, Texture> gbuffer;
    const Targets g = test::synthetic_gbuffer(s.w, s.h);  // as bench/stylize_bench.cpp bm_pipeline
    for (auto& [name, img] : g.all()) gbuffer.emplace(name, Texture::upload(img));
    const Texture paper =
        Texture::upload(p.has_paper ? stylize::prepare_paper(p.paper, s.w, s.h) : stylize::flat_paper(s.w, s.h));
    std::vector<stylize::ResolvedStep> steps;
    std::vector<std::unique_ptr<StageTwin>> twins;
    for (std::size_t i = 0; i < p.steps.size(); ++i) {
        steps.push_back(stylize::resolve_step(p, i));
        twins.push_back(std::make_unique<StageTwin>(*steps.back().variant));
    }
    auto run_once = [&] {
        std::map<std::string, Texture> produced;
        auto find = [&](const std::string& n) -> const Texture* {
            if (auto it = produced.find(n); it != produced.end()) return &it->second;
            if (auto it = gbuffer.find(n); it != gbuffer.end()) return &it->second;
            return nullptr;
        };
        for (std::size_t i = 0; i < steps.size(); ++i) {
            std::vector<const Texture*> ins;
            for (auto& n : steps[i].inputs) ins.push_back(n.empty() ? nullptr : find(n));
            auto outs = twins[i]->run(ins, steps[i].params, p.substrate_color, &paper);
            for (std::size_t k = 0; k < outs.size(); ++k) produced[steps[i].outputs[k]] = std::move(outs[k]);
        }
        benchmark::DoNotOptimize(read_texture(*find(p.output)).data());
    };
    run_once();  // warm-up: compile + JIT every pass of every step
    for (auto _ : st) run_once();
    st.SetItemsProcessed(st.iterations() * std::int64_t(s.w) * s.h);
}

const bool kRegistered = [] {
    for (const stylize::StageVariant* v : stylize::builtin_registry().all())
        for (const Size& s : kSizes)
            benchmark::RegisterBenchmark(("gl/stage/" + v->key() + "/" + s.name).c_str(), bm_gl_stage, v, s)
                ->Unit(benchmark::kMillisecond)
                ->UseRealTime();
    for (const std::string& preset : stylize::preset_names())
        if (!stylize::compile_pipeline(stylize::load_pipeline(preset)).has_passes)  // ld06: needs a scene
        for (const Size& s : kSizes)
            benchmark::RegisterBenchmark(("gl/pipeline/" + preset + "/" + s.name).c_str(), bm_gl_pipeline, preset, s)
                ->Unit(benchmark::kMillisecond)
                ->UseRealTime();
    return true;
}();

}  // namespace
}  // namespace aq::ref

#endif  // AQ_HAVE_REFERENCE
