// bench/scene_bench.cpp — loading real textured glTF models (scene::load_gltf), what a render of
// such a model pays before its first triangle: parsing, decoding the texture files, the sRGB decode
// of base colours and the 8-bit texel codes (scene::TextureCodes).
//   scene/load/<model>      the whole load_gltf call
//   scene/texture_codes/<n> texture_codes + texture_codes_finish of an n x n RGBA 8-bit texture
//   scene/noise_field/{plain,eight}/<n>  one noise control rule (WC18's default pigment turbulence:
//                           2 octaves, bounds-relative) over n vertices: noise_field per vertex,
//                           and noise_field_n (8 per vector); one thread. A bare model's default
//                           control evaluates three such rules (the dragon: 437,645 vertices).
// Run only these: aquarelle_bench --benchmark_filter=scene/
#include <benchmark/benchmark.h>

#include <cstdint>
#include <string>

#include <cmath>
#include <vector>

#include "scenes/gltf_loader.h"
#include "scenes/noise.h"
#include "scenes/scene.h"

namespace {

void bm_load(benchmark::State& st, const std::string& path) {
    aq::scene::Scene warm = aq::scene::load_gltf(path);  // loads the image module once, untimed
    benchmark::DoNotOptimize(warm);
    for (auto _ : st) {
        aq::scene::Scene s = aq::scene::load_gltf(path);
        benchmark::DoNotOptimize(s);
    }
}

void bm_texture_codes(benchmark::State& st) {
    const int n = int(st.range(0));
    aq::ImageF img(n, n, 4);
    for (std::size_t i = 0; i < img.num_values(); ++i) img.data()[i] = float((i * 2654435761u >> 7) % 256u) / 255.0f;
    for (auto _ : st) {
        aq::scene::TextureCodes c = aq::scene::texture_codes(img);
        aq::scene::texture_codes_finish(c, img);
        benchmark::DoNotOptimize(c);
    }
    st.SetItemsProcessed(std::int64_t(st.iterations()) * n * n);
}

//! n positions on a sphere of radius 50 (object units of a scanned model), spiral order.
std::vector<glm::vec3> sphere_points(int n) {
    std::vector<glm::vec3> p(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
        const float z = 1.0f - 2.0f * (float(i) + 0.5f) / float(n), r = std::sqrt(1.0f - z * z), a = 2.3999632f * float(i);
        p[std::size_t(i)] = 50.0f * glm::vec3(r * std::cos(a), r * std::sin(a), z);
    }
    return p;
}

void bm_noise_field(benchmark::State& st, bool eight) {
    const std::vector<glm::vec3> p = sphere_points(int(st.range(0)));
    aq::scene::NoiseField f;  // stylize/presets/wc18.json default_control[0]
    f.frequency = 4.0f;
    f.amplitude = 0.25f;
    f.seed = 101;
    f.octaves = 2;
    const float inv_diag = 1.0f / (100.0f * std::sqrt(3.0f));
    std::vector<float> out(p.size());
    for (auto _ : st) {
        if (eight) {
            aq::scene::noise_field_n(f, p.data(), p.size(), inv_diag, out.data());
        } else {
            for (std::size_t i = 0; i < p.size(); ++i) out[i] = aq::scene::noise_field(f, p[i] * inv_diag);
        }
        benchmark::DoNotOptimize(out.data());
        benchmark::ClobberMemory();
    }
    st.SetItemsProcessed(std::int64_t(st.iterations()) * st.range(0));
}

const int registered = [] {
    for (const auto& [name, rel] : {std::pair{"suzanne", "gltf/Suzanne/glTF/Suzanne.gltf"},
                                    std::pair{"waterbottle", "gltf/WaterBottle/glTF/WaterBottle.gltf"}})
        benchmark::RegisterBenchmark((std::string("scene/load/") + name).c_str(), bm_load,
                                     std::string(AQ_SHARED_DIR) + "/assets/" + rel)
            ->Unit(benchmark::kMillisecond)->UseRealTime();
    benchmark::RegisterBenchmark("scene/texture_codes", bm_texture_codes)->Arg(1024)->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark("scene/noise_field/plain", bm_noise_field, false)->Arg(437645)->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark("scene/noise_field/eight", bm_noise_field, true)->Arg(437645)->Unit(benchmark::kMillisecond);
    return 0;
}();

}  // namespace
