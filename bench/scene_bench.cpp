// bench/scene_bench.cpp — loading real textured glTF models (scene::load_gltf), what a render of
// such a model pays before its first triangle: parsing, decoding the texture files, the sRGB decode
// of base colours and the 8-bit texel codes (scene::TextureCodes).
//   scene/load/<model>      the whole load_gltf call
//   scene/texture_codes/<n> texture_codes + texture_codes_finish of an n x n RGBA 8-bit texture
// Run only these: aquarelle_bench --benchmark_filter=scene/
#include <benchmark/benchmark.h>

#include <cstdint>
#include <string>

#include "scenes/gltf_loader.h"
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

const int registered = [] {
    for (const auto& [name, rel] : {std::pair{"suzanne", "gltf/Suzanne/glTF/Suzanne.gltf"},
                                    std::pair{"waterbottle", "gltf/WaterBottle/glTF/WaterBottle.gltf"}})
        benchmark::RegisterBenchmark((std::string("scene/load/") + name).c_str(), bm_load,
                                     std::string(AQ_SHARED_DIR) + "/assets/" + rel)
            ->Unit(benchmark::kMillisecond)->UseRealTime();
    benchmark::RegisterBenchmark("scene/texture_codes", bm_texture_codes)->Arg(1024)->Unit(benchmark::kMillisecond);
    return 0;
}();

}  // namespace
