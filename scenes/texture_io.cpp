// scenes/texture_io.cpp — images into textures: encoded bytes or a file decoded by OpenImageIO,
// kept as 8-bit codes with per-lane tables where the file is 8-bit, else as RGBA float values
// (declared in scenes/gltf_loader.h; docs/scenes.md "Textures").
#include <cstddef>
#include <string>
#include <vector>

#include "core/input.h"
#include "core/io.h"
#include "core/unorm8.h"
#include "scenes/gltf_loader.h"

namespace aq::scene {

namespace {
ImageF to_rgba(const float* src, int w, int h, int c) {
    ImageF img(w, h, 4, kUninitialized);  // every value written below (one pass over fresh memory)
    float* d = img.data();
    const std::size_t np = std::size_t(w) * std::size_t(h);
    for (std::size_t i = 0; i < np; ++i) {
        const float* s = src + i * std::size_t(c);
        if (c == 1 || c == 2) {
            d[4 * i] = d[4 * i + 1] = d[4 * i + 2] = s[0];
            d[4 * i + 3] = c == 2 ? s[1] : 1.0f;
        } else {
            d[4 * i] = s[0];
            d[4 * i + 1] = s[1];
            d[4 * i + 2] = s[2];
            d[4 * i + 3] = c == 4 ? s[3] : 1.0f;
        }
    }
    return img;
}

}  // namespace

ImageF decode_image_bytes(const unsigned char* bytes, std::size_t size, const std::string& name,
                          DecodeBudget* budget) {
    ImageF img = decode_image(bytes, size, name, budget);
    if (img.channels() == 4) return img;  // already RGBA: no copy
    return to_rgba(img.data(), img.width(), img.height(), img.channels());
}

Texture decode_texture(const std::string& name, const unsigned char* bytes, std::size_t size, DecodeBudget* budget,
                       const TexelMap& map) {
    Texture t;
    t.name = name;
    DecodedImage d = decode_image_or_codes(bytes, size, name, budget);
    if (!d.codes.empty()) {
        // An 8-bit file: its codes as decoded, each lane's table the mapped value of every code.
        t.codes.width = d.codes.width;
        t.codes.height = d.codes.height;
        t.codes.codes = std::move(d.codes.codes);
        const float* unorm8 = unorm8_floats();
        for (int lane = 0; lane < 4; ++lane)
            for (int k = 0; k < 256; ++k) t.codes.lut[std::size_t(lane)][std::size_t(k)] = map(unorm8[k], lane);
        return t;
    }
    // Any other file: RGBA float, mapped value by value; kept as codes where its values turn out
    // to be 8-bit (8-bit formats that OpenImageIO decodes).
    t.image = d.values.channels() == 4 ? std::move(d.values)
                                       : to_rgba(d.values.data(), d.values.width(), d.values.height(), d.values.channels());
    TextureCodes codes = texture_codes(t.image);
    float* v = t.image.data();
    for (std::size_t i = 0, n = t.image.num_values(); i < n; ++i) v[i] = map(v[i], int(i % 4));
    texture_codes_finish(codes, t.image);
    if (!codes.empty()) {
        t.codes = std::move(codes);
        t.image = ImageF();
    }
    return t;
}

Texture read_texture(const std::string& path, DecodeBudget* budget, const TexelMap& map) {
    const std::vector<unsigned char> bytes = read_input_file(path, kMaxImageFileBytes, "image");
    return decode_texture(path, bytes.data(), bytes.size(), budget, map);
}

}  // namespace aq::scene
