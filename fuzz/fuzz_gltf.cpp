// fuzz/fuzz_gltf.cpp — bytes -> aq::scene::load_gltf (.gltf JSON or .glb, chosen by the magic).
// The input is written to <temp>/in.gltf; beside it lie buffer.bin and tex.png, so seeds whose
// URIs name those files also exercise external buffers and images (fuzz/README.md).
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "core/io.h"
#include "fuzz/fuzz_common.h"
#include "scenes/gltf_loader.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    // buffer.bin: 3 float VEC3 positions of a triangle, then indices 0 1 2 (u16), padded, then a
    // byte ramp, so external-buffer seeds have real data to point at.
    std::vector<std::uint8_t> buf(256);
    const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const std::uint16_t idx[4] = {0, 1, 2, 0};
    std::memcpy(buf.data(), pos, sizeof pos);
    std::memcpy(buf.data() + 36, idx, sizeof idx);
    for (std::size_t i = 44; i < buf.size(); ++i) buf[i] = std::uint8_t(i * 37);
    aq::fuzz::write_temp("buffer.bin", buf.data(), buf.size());
    aq::ImageF tex(4, 4, 4, 0.5f);
    aq::write_image(aq::fuzz::temp_dir() + "/tex.png", tex);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string path = aq::fuzz::write_temp("in.gltf", data, size);
    aq::fuzz::expect_only_aq_errors("load_gltf", [&] {
        std::vector<std::string> warnings;
        aq::scene::LoadOptions options;
        options.texture_budget_bytes = aq::fuzz::kDecodeBytes;
        const aq::scene::Scene s = aq::scene::load_gltf(path, &warnings, options);
        (void)s.world_bounds();
    });
    return 0;
}
