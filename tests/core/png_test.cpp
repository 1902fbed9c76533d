// PNG encoder (core/png.h): files that OpenImageIO (libpng) reads back with the quantised values,
// the sRGB tag and the description, and whose chunks are well formed by an independent check.
#include "core/png.h"

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <OpenImageIO/imageio.h>

#include "core/io.h"
#include "tests/test_support.h"

namespace aq {
namespace {

ImageF pattern(int w, int h, int c, unsigned seed) {
    ImageF img(w, h, c);
    for (std::size_t i = 0; i < img.num_values(); ++i) {
        const unsigned v = (unsigned(i) * 2654435761u + seed * 40503u) >> 7;
        img.data()[i] = float(v % 1200) / 1000.0f - 0.1f;  // some values outside [0, 1]: clamped
    }
    return img;
}

std::vector<unsigned char> file_bytes(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return std::vector<unsigned char>(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

//! CRC-32 of the PNG specification (annex D), bit by bit: independent of the encoder's libdeflate.
std::uint32_t crc32_plain(const unsigned char* p, std::size_t n) {
    std::uint32_t c = 0xffffffffu;
    for (std::size_t i = 0; i < n; ++i) {
        c ^= p[i];
        for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
    }
    return c ^ 0xffffffffu;
}

std::uint32_t be32(const unsigned char* p) {
    return std::uint32_t(p[0]) << 24 | std::uint32_t(p[1]) << 16 | std::uint32_t(p[2]) << 8 | p[3];
}

}  // namespace

// Grey and RGB, odd sizes: OpenImageIO reads back to_unorm8 of each value, the colour space and the
// description, ASCII (tEXt) and not (iTXt, UTF-8).
TEST(Png, OpenImageIOReadsBackTheQuantisedValuesTheSrgbTagAndTheDescription) {
    const std::string dir = test::output_dir();
    const std::string texts[] = {"{\"aquarelle_manifest\":1,\"scene\":\"a b\"}",
                                 "{\"scene\":\"/données/сцена/场景.gltf\"}"};
    for (int c : {1, 3})
        for (const std::string& text : texts) {
            const ImageF img = pattern(37 + c, 11 + 2 * c, c, unsigned(c));
            const std::string path = dir + "/png_" + std::to_string(c) + "_" + std::to_string(text.size()) + ".png";
            write_image(path, img, text);
            auto in = OIIO::ImageInput::open(path);
            ASSERT_TRUE(in) << OIIO::geterror();
            const OIIO::ImageSpec& spec = in->spec();
            EXPECT_EQ(spec.width, img.width());
            EXPECT_EQ(spec.height, img.height());
            ASSERT_EQ(spec.nchannels, c);
            EXPECT_EQ(spec.format, OIIO::TypeDesc::UINT8);
            EXPECT_EQ(spec.get_string_attribute("oiio:ColorSpace"), "sRGB");
            EXPECT_EQ(spec.get_string_attribute("ImageDescription"), text);
            std::vector<unsigned char> px(img.num_values());
            ASSERT_TRUE(in->read_image(0, 0, 0, c, OIIO::TypeDesc::UINT8, px.data())) << in->geterror();
            for (std::size_t i = 0; i < px.size(); ++i)
                ASSERT_EQ(px[i], to_unorm8(img.data()[i])) << "channels " << c << " value " << i;
        }
}

// The file is the specification's: signature, IHDR first with the size, depth 8 and the colour
// type of the channel count, IEND last and empty, every chunk's CRC right (checked with a plain
// CRC-32 here, not the encoder's); the same image gives the same bytes.
TEST(Png, ChunksAreWellFormedAndTheBytesAreDeterministic) {
    const std::string dir = test::output_dir();
    for (int c : {1, 3}) {
        const ImageF img = pattern(64, 33, c, 7u);
        write_image(dir + "/a.png", img, "description");
        write_image(dir + "/b.png", img, "description");
        const std::vector<unsigned char> b = file_bytes(dir + "/a.png");
        EXPECT_EQ(b, file_bytes(dir + "/b.png"));
        const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
        ASSERT_GE(b.size(), 8u + 25u + 12u);
        ASSERT_TRUE(std::equal(sig, sig + 8, b.begin()));
        std::vector<std::string> types;
        std::size_t p = 8;
        while (p + 12 <= b.size()) {
            const std::uint32_t n = be32(&b[p]);
            ASSERT_LE(p + 12 + n, b.size());
            const std::string type(reinterpret_cast<const char*>(&b[p + 4]), 4);
            EXPECT_EQ(be32(&b[p + 8 + n]), crc32_plain(&b[p + 4], 4 + n)) << type;
            if (type == "IHDR") {
                ASSERT_EQ(n, 13u);
                EXPECT_EQ(be32(&b[p + 8]), 64u);
                EXPECT_EQ(be32(&b[p + 12]), 33u);
                EXPECT_EQ(b[p + 16], 8);
                EXPECT_EQ(b[p + 17], c == 1 ? 0 : 2);  // grey, RGB (specification 11.2.2)
            }
            if (type == "IEND") {
                EXPECT_EQ(n, 0u);
            }
            types.push_back(type);
            p += 12 + n;
        }
        EXPECT_EQ(p, b.size());
        ASSERT_FALSE(types.empty());
        EXPECT_EQ(types.front(), "IHDR");
        EXPECT_EQ(types.back(), "IEND");
        EXPECT_EQ(std::count(types.begin(), types.end(), "sRGB"), 1);
    }
}

// Images with alpha hold straight alpha in memory (the G-buffer colour, --style none), as PNG
// stores it: a colour of 0.25 at alpha 0.5 is stored as 0.25 (64) and read back as 0.25, whatever
// the alpha (OpenImageIO's default takes memory as associated and divided colour by alpha, which
// turned every partly covered pixel of a --style none image white; core/oiio_module.cpp).
TEST(Png, ImagesWithAlphaKeepStraightColour) {
    const std::string path = test::output_dir() + "/alpha.png";
    ImageF img(3, 2, 4);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 3; ++x) {
            for (int c = 0; c < 3; ++c) img.at(x, y, c) = 0.25f;
            img.at(x, y, 3) = x == 2 ? 0.0f : 0.5f;
        }
    write_image(path, img);
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(path, &config);
    ASSERT_TRUE(in) << OIIO::geterror();
    ASSERT_EQ(in->spec().nchannels, 4);
    std::vector<unsigned char> stored(img.num_values());
    ASSERT_TRUE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::UINT8, stored.data()));
    for (std::size_t i = 0; i < stored.size(); i += 4) {
        EXPECT_EQ(stored[i], 64) << i;  // 0.25 * 255, as it is
        EXPECT_EQ(stored[i + 3], (i / 4) % 3 == 2 ? 0 : 128) << i;
    }
    const ImageF back = read_image(path);
    for (int x = 0; x < 3; ++x) {
        EXPECT_FLOAT_EQ(back.at(x, 1, 0), 64.0f / 255.0f) << x;  // also where alpha is 0
        EXPECT_FLOAT_EQ(back.at(x, 1, 3), x == 2 ? 0.0f : 128.0f / 255.0f) << x;
    }
}

// Compression::None (--compression none): the same pixels, stored uncompressed — grey and RGB PNG
// (our encoder: deflate's stored blocks, so the file holds every row byte), PNG with alpha
// (OpenImageIO, zlib level 0) and EXR (OpenImageIO, no compression, as its header says); the fast
// files of the same compressible image are far smaller.
TEST(Png, CompressionNoneStoresTheSamePixelsUncompressed) {
    const std::string dir = test::output_dir();
    for (const char* ext : {".png", ".exr"})
        for (int c : {1, 3, 4}) {
            SCOPED_TRACE(std::string(ext) + " channels " + std::to_string(c));
            ImageF img(96, 40, c);
            for (int y = 0; y < 40; ++y)
                for (int x = 0; x < 96; ++x)
                    for (int k = 0; k < c; ++k) img.at(x, y, k) = k == 3 ? 1.0f : float((x / 8 + y / 8 + k) % 4) / 3.0f;
            const std::string fast = dir + "/fast_" + std::to_string(c) + ext;
            const std::string none = dir + "/none_" + std::to_string(c) + ext;
            write_image(fast, img, "d", Compression::Fast);
            write_image(none, img, "d", Compression::None);
            const ImageF a = read_image(fast), b = read_image(none);
            ASSERT_EQ(a.num_values(), b.num_values());
            EXPECT_TRUE(std::equal(a.data(), a.data() + a.num_values(), b.data()));
            const std::size_t raw = std::string(ext) == ".png" ? std::size_t(40) * (96 * std::size_t(c) + 1)
                                                                : img.num_values() * sizeof(float);  // float EXR
            EXPECT_GT(file_bytes(none).size(), raw);
            EXPECT_LT(file_bytes(fast).size() * 2, file_bytes(none).size());
            if (std::string(ext) == ".exr") {
                auto in = OIIO::ImageInput::open(none);
                ASSERT_TRUE(in) << OIIO::geterror();
                EXPECT_EQ(in->spec().get_string_attribute("compression"), "none");
            }
        }
}

// The deflate encoders' extremes at a size of several deflate blocks: uniformly random bytes
// (incompressible: neither encoder makes the file more than ~0.1 % larger than the raw rows, and
// zlib_bound leaves room for that) and one flat colour (the file a tiny fraction of them); every
// value read back exact.
TEST(Png, IncompressibleAndFlatImagesRoundTripWithinTheirBounds) {
    const std::string dir = test::output_dir();
    const int w = 800, h = 300;
    const std::size_t raw = std::size_t(h) * (3 * std::size_t(w) + 1);
    ImageF noise(w, h, 3), flat(w, h, 3);
    std::uint32_t state = 12345u;
    for (std::size_t i = 0; i < noise.num_values(); ++i) {
        state = state * 1664525u + 1013904223u;  // Numerical Recipes' LCG; the top byte is uniform
        noise.data()[i] = float(state >> 24) / 255.0f;
        flat.data()[i] = 0.5f;
    }
    for (Compression comp : {Compression::Fast, Compression::None}) {
        SCOPED_TRACE(compression_name(comp));
        const std::string np = dir + "/noise_" + compression_name(comp) + ".png";
        const std::string fp = dir + "/flat_" + compression_name(comp) + ".png";
        write_image(np, noise, "", comp);
        write_image(fp, flat, "", comp);
        const ImageF a = read_image(np), b = read_image(fp);
        ASSERT_EQ(a.num_values(), noise.num_values());
        for (std::size_t i = 0; i < a.num_values(); ++i)
            ASSERT_EQ(to_unorm8(a.data()[i]), to_unorm8(noise.data()[i])) << i;
        ASSERT_EQ(b.num_values(), flat.num_values());
        for (std::size_t i = 0; i < b.num_values(); ++i) ASSERT_EQ(to_unorm8(b.data()[i]), to_unorm8(0.5f)) << i;
        EXPECT_LE(file_bytes(np).size(), raw + raw / 1000 + 200);
        EXPECT_GT(file_bytes(np).size(), raw * 99 / 100);
        if (comp == Compression::Fast) {
            EXPECT_LT(file_bytes(fp).size() * 50, raw);
        }
    }
}

// An RGBA image written with drop_alpha: the bytes of writing its RGB copy, for PNG (encoded
// straight from the RGBA values, both compression settings) and for EXR (through the copy); the
// alpha values (out of range, NaN) play no part. A 3-channel image with drop_alpha is refused.
TEST(Png, DropAlphaWritesTheBytesOfTheRgbCopy) {
    const std::string dir = test::output_dir();
    ImageF rgba = pattern(53, 17, 4, 7u);
    for (std::size_t i = 3; i < rgba.num_values(); i += 8) rgba.data()[i] = std::numeric_limits<float>::quiet_NaN();
    ImageF rgb(rgba.width(), rgba.height(), 3);
    for (std::size_t i = 0; i < std::size_t(rgba.width()) * std::size_t(rgba.height()); ++i)
        for (int c = 0; c < 3; ++c) rgb.data()[3 * i + std::size_t(c)] = rgba.data()[4 * i + std::size_t(c)];
    for (const char* ext : {".png", ".exr"})
        for (Compression comp : {Compression::Fast, Compression::None}) {
            const std::string a = dir + "/rgb" + ext, b = dir + "/dropped" + ext;
            const std::string sha_a = write_image(a, rgb, "d", comp);
            const std::string sha_b = write_image(b, rgba, "d", comp, true);
            EXPECT_EQ(sha_a, sha_b) << ext;
            EXPECT_EQ(file_bytes(a), file_bytes(b)) << ext;
        }
    EXPECT_THROW(write_image(dir + "/bad.png", rgb, "", Compression::Fast, true), Error);
}

// A description the text chunk cannot hold is an error naming the file, not a cut manifest.
TEST(Png, ADescriptionWithANulByteIsRefused) {
    const std::string path = test::output_dir() + "/nul.png";
    try {
        write_image(path, pattern(4, 4, 3, 1u), std::string("a\0b", 3));
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("nul.png"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("NUL"), std::string::npos) << e.what();
    }
}

}  // namespace aq
