// bench/ld06_bench.cpp — LD06 raster passes (raster/pass.h, particles.h, strokes.h) and the
// implicit-surface build (raster/foliage.h) on the shared dense oak, grouped like the paper's
// Table 2 columns (GeForce 6800, 720 x 720 output, 520 x 520 intermediates):
//   light/shadow/depth  BM_Ld06_LightShadowDepth: light depth + blur + camera depth + blur +
//                       lighting + shadow intensity (paper 8.9-18 ms)
//   intensity maps      BM_Ld06_Particles/N: N particles into three maps (paper 7.6-41.9 ms; the
//                       17,000-particle Fig. 8 tree and the 64,209-particle tree 13d)
//   strokes             BM_Ld06_Strokes: trunk contours, the per-frame part (contour adjacency is
//                       built once per job, as the render job does) (paper 1.4-3.3 ms)
//                       BM_Ld06_StrokesPaperLoad/V: with crown hatching up to V vertices (the
//                       paper's loads: plants 12,687-27,513, trees 30,144-46,544)
//   BM_Ld06_Abstraction: the implicit surface of the oak's 58,560 foliage triangles (preprocessing)
// Each at 720 x 720 with 520 x 520 passes and at 1920 x 1080 with full-size passes; 1 and 2
// threads. Inputs (scene, abstraction, depth map, particles) are built once, outside the timing.
// Run only these: aquarelle_bench --benchmark_filter=BM_Ld06
#include <benchmark/benchmark.h>

#include <cmath>
#include <map>
#include <memory>

#include <glm/gtc/matrix_transform.hpp>

#include "raster/foliage.h"
#include "raster/particles.h"
#include "raster/pass.h"
#include "raster/strokes.h"
#include "scenes/gltf_loader.h"
#include "stylize/stages/gaussian_blur.h"

namespace {

using namespace aq;
using namespace aq::raster;

const scene::Scene& oak() {
    static const scene::Scene s = scene::load_gltf(AQ_SHARED_DIR "/assets/plants/ez-tree/ez_oak_large_dense.glb");
    return s;
}

const AbstractedScene& abstracted() {
    static const std::shared_ptr<const AbstractedScene> a = abstract_foliage(oak(), FoliageParams{}, Exec::fast(2));
    return *a;
}

scene::Camera camera(float aspect) {
    const scene::Bounds b = abstracted().scene.world_bounds();
    const glm::vec3 c = 0.5f * (b.min + b.max);
    const float r = 0.5f * glm::length(b.max - b.min);
    const float fov = 0.7f;
    const float d = r / std::sin(0.5f * std::min(fov, fov * aspect)) * 1.05f;
    scene::Camera cam;
    cam.view = glm::lookAt(c + glm::normalize(glm::vec3(0.35f, 0.3f, 1.0f)) * d, c, glm::vec3(0, 1, 0));
    cam.yfov = fov;
    cam.znear = d - r * 1.1f;
    cam.zfar = d + r * 1.1f;
    return cam;
}

// 0: 720 x 720 output with 520 x 520 passes (the paper's setting); 1: 1920 x 1080, full size.
struct Setting {
    int w, h;
    float scale;
    const char* name;
};
constexpr Setting kSettings[] = {{720, 720, 520.0f / 720.0f, "720_520"}, {1920, 1080, 1.0f, "1080p"}};

PassScene pass_scene(int setting) {
    const Setting& s = kSettings[setting];
    PassScene ps = make_pass_scene(abstracted().scene, camera(float(s.w) / float(s.h)), s.w, s.h);
    ps.foliage_surface = &abstracted().surface;
    ps.plant_height = abstracted().height;
    return ps;
}

const ImageF& blurred_depth(int setting) {
    static std::map<int, ImageF> cache;
    auto it = cache.find(setting);
    if (it != cache.end()) return it->second;
    TrianglePass p;
    p.value = PassValue::Depth;
    p.scale = kSettings[setting].scale;
    ImageF d, b;
    render_triangle_pass(d, pass_scene(setting), p, Exec::fast(2));
    stylize::gaussian_blur(b, d, {}, Exec::fast(2));
    return cache.emplace(setting, std::move(b)).first->second;
}

void label(benchmark::State& st, int setting, int threads) {
    st.SetLabel(std::string(kSettings[setting].name) + " threads=" + std::to_string(threads));
}

void BM_Ld06_LightShadowDepth(benchmark::State& st) {
    const int setting = int(st.range(0)), threads = int(st.range(1));
    const PassScene ps = pass_scene(setting);
    const Exec ex = Exec::fast(threads);
    const float sc = kSettings[setting].scale;
    ImageF light, light_blur, depth, depth_blur, lighting, shadow;
    for (auto _ : st) {
        TrianglePass p;
        p.value = PassValue::Depth;
        p.view = PassView::Light;
        p.scale = sc;
        render_triangle_pass(light, ps, p, ex);
        stylize::gaussian_blur(light_blur, light, {}, ex);
        p.view = PassView::Camera;
        render_triangle_pass(depth, ps, p, ex);
        stylize::gaussian_blur(depth_blur, depth, {}, ex);
        p.value = PassValue::Lighting;
        render_triangle_pass(lighting, ps, p, ex);
        p.value = PassValue::Shadow;
        p.shadow_map = &light_blur;
        render_triangle_pass(shadow, ps, p, ex);
        benchmark::DoNotOptimize(shadow.data());
    }
    label(st, setting, threads);
}

void BM_Ld06_Particles(benchmark::State& st) {
    const int setting = int(st.range(0)), threads = int(st.range(1)), count = int(st.range(2));
    const PassScene ps = pass_scene(setting);
    ParticleParams p;
    p.scale = kSettings[setting].scale;
    p.depth_map = &blurred_depth(setting);
    p.quantity = float(count) / (p.height * p.height);  // eq. 8 solved for the wanted count
    const std::vector<Particle> qs = place_particles(abstracted().surface, abstracted().height, ps.light_dir, p);
    ImageF a, b, c;
    for (auto _ : st) {
        render_particles(a, b, c, ps, qs, p, Exec::fast(threads));
        benchmark::DoNotOptimize(a.data());
    }
    st.counters["particles"] = double(qs.size());
    label(st, setting, threads);
}

void BM_Ld06_Strokes(benchmark::State& st) {
    const int setting = int(st.range(0)), threads = int(st.range(1));
    PassScene ps = pass_scene(setting);
    // The view-independent contour data is built once per render job (raster::ContourCache).
    static const ContourCache contours = build_contour_cache(abstracted().scene);
    ps.contours = &contours;
    StrokeParams p;
    p.scale = kSettings[setting].scale;
    p.depth_map = &blurred_depth(setting);
    std::size_t vertices = 0;
    ImageF out;
    for (auto _ : st) {
        const std::vector<Stroke> s = contour_strokes(ps, Exec::fast(threads));  // facing and chaining: part of every frame
        vertices = 0;
        for (const Stroke& k : s) vertices += k.points.size();
        render_strokes(out, ps, s, p, Exec::fast(threads));
        benchmark::DoNotOptimize(out.data());
    }
    st.counters["stroke_vertices"] = double(vertices);
    label(st, setting, threads);
}

// Hatching strokes over the crown (3 vertices, about 1.5 % of the tree height, along a tangent of
// the implicit surface, its normals; every second one lit-side faded) so that, with the trunk
// contours, `vertices` stroke vertices are drawn: the paper's Table 2 stroke loads (12,687 -
// 46,544 vertices) rather than our trunk contours alone.
std::vector<Stroke> crown_hatching(std::size_t vertices, std::size_t contour_vertices) {
    const ImplicitSurface& s = abstracted().surface;
    const std::size_t n = vertices > contour_vertices ? (vertices - contour_vertices) / 3 : 0;
    const float len = 0.0075f * abstracted().height;
    std::vector<Stroke> out;
    for (std::size_t k = 0; k < n && !s.positions.empty(); ++k) {
        const std::size_t i = k * s.positions.size() / n;  // spread over the surface in its order (as leaf strokes come, leaf by leaf)
        const glm::vec3 p = s.positions[i], nrm = s.normals[i];
        glm::vec3 t = glm::cross(nrm, glm::vec3(0.3f, 1.0f, 0.2f));
        t = glm::length(t) > 0.0f ? glm::normalize(t) : glm::vec3(1, 0, 0);
        out.push_back(Stroke{{p - len * t, p, p + len * t}, {nrm, nrm, nrm}, k % 2 == 1});
    }
    return out;
}

// The strokes column at the paper's stroke loads: hatching (above) then the trunk contours, as the
// strokes pass orders them, 720 x 720, 1 and 2 threads.
void BM_Ld06_StrokesPaperLoad(benchmark::State& st) {
    const int vertices = int(st.range(0)), threads = int(st.range(1));
    PassScene ps = pass_scene(0);
    static const ContourCache contours = build_contour_cache(abstracted().scene);
    ps.contours = &contours;
    StrokeParams p;
    p.scale = kSettings[0].scale;
    p.depth_map = &blurred_depth(0);
    std::size_t contour_vertices = 0;
    for (const Stroke& k : contour_strokes(ps)) contour_vertices += k.points.size();
    const std::vector<Stroke> hatching = crown_hatching(std::size_t(vertices), contour_vertices);
    std::size_t drawn = 0;
    ImageF out;
    for (auto _ : st) {
        const std::vector<Stroke> c = contour_strokes(ps, Exec::fast(threads));
        const std::vector<Stroke>* lists[2] = {&hatching, &c};  // as the strokes pass draws them
        drawn = 0;
        for (const auto* l : lists)
            for (const Stroke& k : *l) drawn += k.points.size();
        render_strokes(out, ps, lists, p, Exec::fast(threads));
        benchmark::DoNotOptimize(out.data());
    }
    st.counters["stroke_vertices"] = double(drawn);
    label(st, 0, threads);
}

void BM_Ld06_Abstraction(benchmark::State& st) {
    const int threads = int(st.range(0));
    std::size_t tris = 0;
    for (auto _ : st) {
        const auto a = abstract_foliage(oak(), FoliageParams{}, Exec::fast(threads));
        tris = a->surface.indices.size() / 3;
    }
    st.counters["triangles"] = double(tris);
    st.SetLabel("threads=" + std::to_string(threads));
}

}  // namespace

BENCHMARK(BM_Ld06_LightShadowDepth)->ArgsProduct({{0, 1}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Ld06_Particles)->ArgsProduct({{0, 1}, {1, 2}, {17000, 64209}})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Ld06_Strokes)->ArgsProduct({{0, 1}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Ld06_StrokesPaperLoad)->ArgsProduct({{12687, 27513, 46544}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Ld06_Abstraction)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
