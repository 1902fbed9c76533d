// bench/raster_bench.cpp — G-buffer render (raster::render_gbuffer) of real models.
//
// Models: Suzanne (3.9k triangles), the Stanford dragon at 202k and 871k triangles, at 1920x1080
// and 640x360 with 1 and 2 threads, default RenderSettings (tremor and bleeding displacement on,
// no back-face culling, ssaa 1). Each model is loaded once (static), never per iteration.
// Counters: triangles/s (submitted triangles) and pixels/s (output pixels).
//
// Variants:
//   BM_RasterFrame — render_gbuffer_into() with the previous frame's targets: the steady state of
//                    an animation (no allocation of the 108 B/px G-buffer per frame; the tiles
//                    that show only background in both frames are not written again);
//   BM_RasterFrameAnimated — BM_RasterFrame with the frame number advancing every iteration (the
//                    hand tremor moves every vertex, as in an animation of a still model);
//   BM_RasterFrameRewrite — BM_RasterFrame with the targets' content declared unknown before each
//                    frame (their stamps cleared, as any write into them does): every pixel is
//                    written, what a frame costs without the previous frame's background;
//   BM_RasterCold  — render_gbuffer(): allocates and zero-fills fresh targets every call (the
//                    page faults of ~224 MB at 1080p are part of the time);
//   BM_RasterFrameCull — BM_RasterFrame with cull_backfaces (dragons only, 1080p);
//   BM_RasterFrameNoAA — BM_RasterFrame with antialias None: one sample per pixel, without the
//                    coverage pass along the silhouettes (what the default's antialiasing costs);
//   BM_RasterFrameTargets — BM_RasterFrame writing a subset of the targets (set 0: all ten, 108
//                    B/px; 1: what WC18 reads, colour + four controls + depth, 84 B/px; 2: colour +
//                    depth, 20 B/px): what the G-buffer's bytes cost, for issue 13's compact formats.
// Run only these: aquarelle_bench --benchmark_filter=BM_Raster
#include <benchmark/benchmark.h>

#include <cmath>
#include <map>
#include <string>

#include "raster/raster.h"
#include "scenes/gltf_loader.h"

namespace {

const char* const kModels[] = {
    AQ_SHARED_DIR "/assets/gltf/Suzanne/glTF/Suzanne.gltf",
    AQ_SHARED_DIR "/assets/meshes/stanford_dragon/dragon_202k.glb",
    AQ_SHARED_DIR "/assets/meshes/stanford_dragon/dragon_871k.glb",
};
const char* const kModelNames[] = {"suzanne", "dragon202k", "dragon871k"};

const aq::scene::Scene& model(int i) {
    static std::map<int, aq::scene::Scene> cache;
    auto it = cache.find(i);
    if (it == cache.end()) it = cache.emplace(i, aq::scene::load_gltf(kModels[i])).first;
    return it->second;
}

// Frames the world bounds from the front-right, like the CLI's automatic camera.
aq::scene::Camera framing_camera(const aq::scene::Scene& s, float aspect) {
    const aq::scene::Bounds b = s.world_bounds();
    const glm::vec3 c = 0.5f * (b.min + b.max);
    const float r = 0.5f * glm::length(b.max - b.min);
    const float fov = 0.7f;
    const float d = r / std::sin(0.5f * std::min(fov, fov * aspect)) * 1.05f;
    const glm::vec3 eye = c + glm::normalize(glm::vec3(0.35f, 0.3f, 1.0f)) * d;
    aq::scene::Camera cam;
    const glm::vec3 f = glm::normalize(c - eye), sd = glm::normalize(glm::cross(f, glm::vec3(0, 1, 0)));
    const glm::vec3 u = glm::cross(sd, f);
    cam.view = glm::mat4(1.0f);
    cam.view[0][0] = sd.x; cam.view[1][0] = sd.y; cam.view[2][0] = sd.z;
    cam.view[0][1] = u.x;  cam.view[1][1] = u.y;  cam.view[2][1] = u.z;
    cam.view[0][2] = -f.x; cam.view[1][2] = -f.y; cam.view[2][2] = -f.z;
    cam.view[3][0] = -glm::dot(sd, eye);
    cam.view[3][1] = -glm::dot(u, eye);
    cam.view[3][2] = glm::dot(f, eye);
    cam.yfov = fov;
    cam.znear = d * 0.05f;
    cam.zfar = d * 3.0f;
    return cam;
}

// The target sets of BM_RasterFrameTargets (bits over target::kGBufferLayout).
std::uint32_t target_set(int i) {
    using namespace aq::target;
    const std::uint32_t color_depth = gbuffer_bit(kColor) | gbuffer_bit(kDepthLinear);
    if (i == 1)
        return color_depth | gbuffer_bit(kCtrlPigment) | gbuffer_bit(kCtrlSubstrate) | gbuffer_bit(kCtrlEdge) |
               gbuffer_bit(kCtrlAbstraction);
    return i == 2 ? color_depth : kAllGBufferTargets;
}

void run(benchmark::State& state, bool reuse, bool cull = false, int targets = 0, bool rewrite = false,
         bool animate = false, bool coverage = true) {
    const int mi = int(state.range(0));
    const int w = int(state.range(1)), h = int(state.range(2)), threads = int(state.range(3));
    const aq::scene::Scene& s = model(mi);
    const aq::scene::Camera cam = framing_camera(s, float(w) / float(h));
    aq::raster::RenderSettings st;
    st.width = w;
    st.height = h;
    st.exec = aq::Exec::fast(threads);
    st.frame = 1;
    st.cull_backfaces = cull;
    st.targets = target_set(targets);
    if (!coverage) st.antialias = aq::raster::RenderSettings::Antialias::None;
    aq::Targets out;
    if (reuse) aq::raster::render_gbuffer_into(out, s, cam, st);  // first frame: allocation
    for (auto _ : state) {
        if (animate) ++st.frame;
        if (reuse) {
            if (rewrite)
                for (const std::string& n : out.names()) out.get_mut(n).set_stamp(0);
            aq::raster::render_gbuffer_into(out, s, cam, st);
        } else {
            aq::Targets t = aq::raster::render_gbuffer(s, cam, st);
            benchmark::DoNotOptimize(t);
        }
    }
    const double tris = double(s.triangle_count());
    state.SetItemsProcessed(std::int64_t(state.iterations() * tris));
    state.counters["triangles/s"] = benchmark::Counter(double(state.iterations()) * tris, benchmark::Counter::kIsRate);
    state.counters["pixels/s"] = benchmark::Counter(double(state.iterations()) * w * h, benchmark::Counter::kIsRate);
    state.counters["threads"] = threads;
    state.SetLabel(kModelNames[mi]);
}

void BM_RasterFrame(benchmark::State& state) { run(state, true); }
void BM_RasterCold(benchmark::State& state) { run(state, false); }
void BM_RasterFrameCull(benchmark::State& state) { run(state, true, true); }
void BM_RasterFrameTargets(benchmark::State& state) { run(state, true, false, int(state.range(4))); }
void BM_RasterFrameRewrite(benchmark::State& state) { run(state, true, false, 0, true); }
void BM_RasterFrameAnimated(benchmark::State& state) { run(state, true, false, 0, false, true); }
void BM_RasterFrameNoAA(benchmark::State& state) { run(state, true, false, 0, false, false, false); }

void args(benchmark::internal::Benchmark* b) {
    b->ArgNames({"model", "w", "h", "threads"});
    for (int m = 0; m < 3; ++m)
        for (auto [w, h] : {std::pair{1920, 1080}, std::pair{640, 360}})
            for (int t : {1, 2}) b->Args({m, w, h, t});
    b->Unit(benchmark::kMillisecond)->UseRealTime();
}

}  // namespace

BENCHMARK(BM_RasterFrame)->Apply(args);
BENCHMARK(BM_RasterCold)->Apply(args);
BENCHMARK(BM_RasterFrameNoAA)->Apply(args);
// Same as BM_RasterFrame with back-face culling (closed meshes: the same visible surfaces, about
// half the triangles set up and rasterized).
BENCHMARK(BM_RasterFrameCull)
    ->ArgNames({"model", "w", "h", "threads"})
    ->Args({1, 1920, 1080, 2})
    ->Args({2, 1920, 1080, 1})
    ->Args({2, 1920, 1080, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_RasterFrameAnimated)
    ->ArgNames({"model", "w", "h", "threads"})
    ->ArgsProduct({{0, 2}, {1920}, {1080}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_RasterFrameRewrite)
    ->ArgNames({"model", "w", "h", "threads"})
    ->ArgsProduct({{0, 2}, {1920}, {1080}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_RasterFrameTargets)
    ->ArgNames({"model", "w", "h", "threads", "set"})
    ->ArgsProduct({{0, 2}, {1920}, {1080}, {1, 2}, {0, 1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
