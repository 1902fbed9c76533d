// fuzz/fuzz_image.cpp — bytes -> the image readers: aq::scene::decode_image_bytes (papers),
// aq::scene::decode_texture and finish_texture (glTF, control and intensity textures: 8-bit PNG
// and JPEG straight to codes) and aq::read_image on a file (papers, `compare` inputs).
//
// The readers choose OpenImageIO's decoder from the magic bytes where they know them and else
// from the file name's extension, which a user controls. So that every decoder is reachable, the
// fuzzer names its input after the format its first bytes announce (a wider table than the
// loader's), falling back to .tga, the common format without a magic number.
// Each read draws from the fuzzers' decode budget (fuzz_common.h kDecodeBytes).
#include <cstdint>
#include <cstring>
#include <string>

#include "core/io.h"
#include "fuzz/fuzz_common.h"
#include "scenes/gltf_loader.h"

namespace {

std::string extension_for(const std::uint8_t* b, std::size_t n) {
    struct Magic {
        const char* bytes;
        std::size_t len;
        const char* ext;
    };
    static const Magic kMagic[] = {
        {"\x89PNG", 4, ".png"},         {"\xff\xd8\xff", 3, ".jpg"},  {"\x76\x2f\x31\x01", 4, ".exr"},
        {"DDS ", 4, ".dds"},            {"BM", 2, ".bmp"},            {"GIF8", 4, ".gif"},
        {"II*\0", 4, ".tif"},           {"MM\0*", 4, ".tif"},         {"#?", 2, ".hdr"},
        {"PF", 2, ".pfm"},              {"Pf", 2, ".pfm"},            {"P1", 2, ".pbm"},
        {"P2", 2, ".pgm"},              {"P3", 2, ".ppm"},            {"P4", 2, ".pbm"},
        {"P5", 2, ".pgm"},              {"P6", 2, ".ppm"},            {"8BPS", 4, ".psd"},
        {"\x01\xda", 2, ".sgi"},        {"\0\0\x01\0", 4, ".ico"},    {"RIFF", 4, ".webp"},
        {"SDPX", 4, ".dpx"},            {"XPDS", 4, ".dpx"},          {"\x80\x2a\x5f\xd7", 4, ".cin"},
        {"FOR4", 4, ".iff"},            {"SIMPLE", 6, ".fits"},       {"\x53\x80\xf6\x34", 4, ".pic"},
        {"\0\0\0\x0cjP  ", 8, ".jp2"},  {"\xff\x4f\xff\x51", 4, ".j2k"}, {"gimp xcf", 8, ".xcf"},
    };
    for (const Magic& m : kMagic)
        if (n >= m.len && std::memcmp(b, m.bytes, m.len) == 0) return m.ext;
    return ".tga";
}

aq::DecodeBudget fuzz_budget() { return aq::DecodeBudget{aq::fuzz::kDecodeBytes, "the fuzzer's images (64 MiB)"}; }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string ext = extension_for(data, size);
    aq::fuzz::expect_only_aq_errors("decode_image_bytes",
                                    [&] {
        aq::DecodeBudget budget = fuzz_budget();
        (void)aq::scene::decode_image_bytes(data, size, "fuzz-input" + ext, &budget);
    });
    // The texture path: 8-bit PNG and JPEG straight to RGBA codes (core/png.h, core/jpeg.h), then
    // the mip levels.
    aq::fuzz::expect_only_aq_errors("decode_texture", [&] {
        aq::DecodeBudget budget = fuzz_budget();
        aq::scene::Texture t = aq::scene::decode_texture("fuzz-input" + ext, data, size, &budget,
                                                         {aq::scene::TexelMap::Kind::Srgb});
        aq::scene::finish_texture(t);
    });
    const std::string path = aq::fuzz::write_temp("in" + ext, data, size);
    aq::fuzz::expect_only_aq_errors("read_image", [&] {
        aq::DecodeBudget budget = fuzz_budget();
        (void)aq::read_image(path, &budget);
    });
    return 0;
}
