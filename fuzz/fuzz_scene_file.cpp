// fuzz/fuzz_scene_file.cpp — bytes -> aq::scene::load_scene on <temp>/scene.json.
// Beside it lie the files the seeds name (fuzz/README.md): model.gltf (a textured, vertex-coloured
// quad with two materials), tex.png (a control texture) and paper.png, so the fuzzer reaches the
// glTF loading, control rules, material overrides and camera framing, not just the JSON checks.
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "core/io.h"
#include "fuzz/fuzz_common.h"
#include "scenes/scene_file.h"

namespace {

// A quad (two triangles) with NORMAL, TEXCOORD_0 and COLOR_0, materials "paint" and "1", one
// embedded 2x2 PNG texture. Written by hand for the fuzzer (no third-party asset).
const char kModel[] = R"({
 "asset": {"version": "2.0"},
 "scene": 0, "scenes": [{"nodes": [0, 1]}],
 "nodes": [{"mesh": 0, "name": "quad"}, {"mesh": 0, "translation": [2, 0, 0], "scale": [1, 2, 1]}],
 "meshes": [{"name": "quad", "primitives": [
   {"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2, "COLOR_0": 3}, "indices": 4, "material": 0},
   {"attributes": {"POSITION": 0}, "mode": 5, "material": 1}]}],
 "materials": [{"name": "paint", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.3, 0.2, 1],
                "baseColorTexture": {"index": 0}}, "extras": {"watercolor": {"dilute": 0.5}}},
               {"name": "second", "doubleSided": true}],
 "textures": [{"source": 0}],
 "images": [{"uri": "tex.png"}],
 "accessors": [
   {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
   {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
   {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
   {"bufferView": 3, "componentType": 5121, "normalized": true, "count": 4, "type": "VEC4"},
   {"bufferView": 4, "componentType": 5123, "count": 6, "type": "SCALAR"}],
 "bufferViews": [
   {"buffer": 0, "byteOffset": 0, "byteLength": 48},
   {"buffer": 0, "byteOffset": 48, "byteLength": 48},
   {"buffer": 0, "byteOffset": 96, "byteLength": 32},
   {"buffer": 0, "byteOffset": 128, "byteLength": 16},
   {"buffer": 0, "byteOffset": 144, "byteLength": 12}],
 "buffers": [{"uri": "model.bin", "byteLength": 156}]
})";

void write_model() {
    unsigned char b[156] = {};
    const float pos[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    const float nrm[12] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    const float uv[8] = {0, 0, 1, 0, 1, 1, 0, 1};
    const unsigned char col[16] = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 128, 128, 128, 128};
    const std::uint16_t idx[6] = {0, 1, 2, 0, 2, 3};
    std::memcpy(b, pos, 48);
    std::memcpy(b + 48, nrm, 48);
    std::memcpy(b + 96, uv, 32);
    std::memcpy(b + 128, col, 16);
    std::memcpy(b + 144, idx, 12);
    aq::fuzz::write_temp("model.bin", b, sizeof b);
    aq::fuzz::write_temp("model.gltf", reinterpret_cast<const std::uint8_t*>(kModel), std::strlen(kModel));
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    aq::ImageF tex(4, 4, 4, 0.25f);
    tex.at(1, 1, 0) = 1.0f;
    aq::write_image(aq::fuzz::temp_dir() + "/tex.png", tex);
    aq::write_image(aq::fuzz::temp_dir() + "/paper.png", aq::ImageF(8, 8, 3, 0.5f));
    write_model();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string path = aq::fuzz::write_temp("scene.json", data, size);
    aq::fuzz::expect_only_aq_errors("load_scene", [&] {
        aq::scene::LoadOptions options;
        options.texture_budget_bytes = aq::fuzz::kDecodeBytes;
        (void)aq::scene::load_scene(path, options);
    });
    // The art direction's values (render --scene-set): listed, then the first and last edited
    // with a value of another kind and with the file's own value.
    aq::fuzz::expect_only_aq_errors("scene_knobs", [&] {
        const std::vector<aq::scene::SceneKnob> knobs = aq::scene::scene_knobs(path);
        if (knobs.empty()) return;
        aq::scene::LoadOptions options;
        options.texture_budget_bytes = aq::fuzz::kDecodeBytes;
        for (const aq::scene::SceneKnob* k : {&knobs.front(), &knobs.back()})
            for (const std::string& v : {k->value, std::string("[1e308, -1, 0]"), std::string("true")}) {
                options.edits = {{k->pointer, v}};
                try {
                    (void)aq::scene::load_scene(path, options);
                } catch (const aq::Error&) {
                }
            }
    });
    return 0;
}
