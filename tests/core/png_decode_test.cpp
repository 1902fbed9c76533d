// tests/core/png_decode_test.cpp — core/png.h's decode_png gives OpenImageIO's values, bit for bit,
// on every 8-bit grey and RGB PNG of the shared assets and on synthetic files (interlaced, every
// row filter libpng picks, odd sizes); everything else is left to OpenImageIO without the header
// callback being called; a file libpng cannot finish goes to OpenImageIO with the budget intact.
#include "core/png.h"

#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <png.h>

#include "core/input.h"
#include "core/io.h"
#include "core/oiio.h"
#include "tests/core/decoder_support.h"
#include "tests/test_support.h"

namespace aq {
namespace {
namespace fs = std::filesystem;

using test::allocate_into;
using test::expect_same_values;

PixelDest must_not_be_called(void*, const ImageHeader&) {
    ADD_FAILURE() << "decode_png accepted a header it leaves to OpenImageIO";
    throw Error("unexpected header");
}

ImageF decode_with_oiio(const std::vector<unsigned char>& bytes) { return test::decode_with_oiio(bytes, "png"); }

void append_bytes(png_structp p, png_bytep data, std::size_t n) {
    auto* out = static_cast<std::vector<unsigned char>*>(png_get_io_ptr(p));
    out->insert(out->end(), data, data + n);
}
void flush_nothing(png_structp) {}

//! A PNG written by libpng (its adaptive row filters): w x h, colour type `colour`, bit depth
//! `depth`, values value(x, y, k) (bytes; 16-bit samples get v * 257), optionally Adam7 and a tRNS.
template <class F>
std::vector<unsigned char> encode_with_libpng(int w, int h, int colour, int depth, bool interlaced, bool trns, F value) {
    std::vector<unsigned char> out;
    png_structp p = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(p);
    if (setjmp(png_jmpbuf(p))) {
        png_destroy_write_struct(&p, &info);
        ADD_FAILURE() << "libpng could not write the test file";
        return {};
    }
    png_set_write_fn(p, &out, append_bytes, flush_nothing);
    png_set_IHDR(p, info, png_uint_32(w), png_uint_32(h), depth, colour,
                 interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    int samples = 1;
    if (colour == PNG_COLOR_TYPE_RGB) samples = 3;
    if (colour == PNG_COLOR_TYPE_GRAY_ALPHA) samples = 2;
    if (colour == PNG_COLOR_TYPE_RGB_ALPHA) samples = 4;
    if (colour == PNG_COLOR_TYPE_PALETTE) {
        png_color pal[256];
        for (int i = 0; i < 256; ++i) pal[i] = {png_byte(i), png_byte(255 - i), png_byte(i / 2)};
        png_set_PLTE(p, info, pal, 256);
    }
    png_color_16 key{};
    key.gray = 7;
    key.red = 7;
    png_byte palette_alpha[256];
    for (int i = 0; i < 256; ++i) palette_alpha[i] = png_byte(i ^ 0x55);
    if (trns && colour == PNG_COLOR_TYPE_PALETTE) png_set_tRNS(p, info, palette_alpha, 256, nullptr);
    else if (trns) png_set_tRNS(p, info, nullptr, 0, &key);
    png_write_info(p, info);
    const int bytes_per_sample = depth == 16 ? 2 : 1;
    std::vector<unsigned char> img(std::size_t(w) * h * samples * bytes_per_sample);
    std::vector<png_bytep> rows(static_cast<std::size_t>(h));
    for (int y = 0; y < h; ++y) {
        unsigned char* r = img.data() + std::size_t(y) * w * samples * bytes_per_sample;
        rows[std::size_t(y)] = r;
        for (int x = 0; x < w; ++x)
            for (int k = 0; k < samples; ++k) {
                const unsigned char v = value(x, y, k);
                if (depth == 16) {
                    r[(std::size_t(x) * samples + k) * 2] = v;
                    r[(std::size_t(x) * samples + k) * 2 + 1] = v;
                } else {
                    r[std::size_t(x) * samples + k] = v;
                }
            }
    }
    png_write_image(p, rows.data());
    png_write_end(p, nullptr);
    png_destroy_write_struct(&p, &info);
    return out;
}

unsigned char wavy(int x, int y, int k) { return static_cast<unsigned char>((x * 7 + y * 13 + k * 85 + (x * y) % 31) & 0xff); }

}  // namespace

// Every PNG in ../shared/assets (glTF base colour, normal and material maps, the paper, palette
// files of 8 and 1 bits): ours decodes it, with OpenImageIO's values (straight alpha, as the module
// reads it; palettes expanded to RGB).
TEST(PngDecode, RealMapsGiveOpenImageIOsValues) {
    int ours = 0, left = 0;
    for (const auto& e : fs::recursive_directory_iterator(test::shared_dir() + "/assets")) {
        if (!e.is_regular_file() || lower_extension(e.path().string()) != ".png") continue;
        const std::vector<unsigned char> bytes = read_input_file(e.path().string(), kMaxImageFileBytes, "test image");
        ASSERT_GE(bytes.size(), 29u) << e.path();
        const int depth = bytes[24], colour = bytes[25];  // IHDR, the first chunk
        const bool eligible = depth == 8 || colour == PNG_COLOR_TYPE_PALETTE;
        ImageF img;
        const bool decoded = decode_png(bytes.data(), bytes.size(), eligible ? allocate_into : must_not_be_called, &img);
        EXPECT_EQ(decoded, eligible) << e.path();  // no tRNS in these files
        if (decoded) {
            expect_same_values(img, decode_with_oiio(bytes), e.path().string());
            ++ours;
        } else {
            ++left;
        }
    }
    EXPECT_GE(ours, 20) << "fewer maps than the assets hold (23 on 2026-12-06: 5 with alpha, 2 palettes)";
    EXPECT_EQ(left, 0) << "the assets' PNG files are all grey, RGB, with alpha or palettes";
}

// Synthetic grey, RGB, grey+alpha, RGBA and palette files with libpng's adaptive filters (Sub, Up, Average, Paeth), odd sizes,
// one pixel, and Adam7 interlacing.
TEST(PngDecode, SyntheticGreyAndRgbFilesInterlacedOrNotGiveOpenImageIOsValues) {
    for (int colour : {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_RGB, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB_ALPHA,
                       PNG_COLOR_TYPE_PALETTE})
        for (bool interlaced : {false, true})
            for (auto [w, h] : {std::pair{1, 1}, {37, 23}, {8, 61}, {300, 5}}) {
                const std::vector<unsigned char> bytes = encode_with_libpng(w, h, colour, 8, interlaced, false, wavy);
                ImageF img;
                ASSERT_TRUE(decode_png(bytes.data(), bytes.size(), allocate_into, &img));
                const std::string what = "colour " + std::to_string(colour) + (interlaced ? " interlaced " : " ") +
                                         std::to_string(w) + "x" + std::to_string(h);
                expect_same_values(img, decode_with_oiio(bytes), what);
                if (colour != PNG_COLOR_TYPE_PALETTE)
                    EXPECT_EQ(img.at(w - 1, h - 1, 0), float(wavy(w - 1, h - 1, 0)) * (1.0f / 255.0f)) << what;
            }
    // A palette with a tRNS chunk: an alpha channel (4 channels), OpenImageIO's values.
    const std::vector<unsigned char> bytes = encode_with_libpng(37, 23, PNG_COLOR_TYPE_PALETTE, 8, false, true, wavy);
    ImageF img;
    ASSERT_TRUE(decode_png(bytes.data(), bytes.size(), allocate_into, &img));
    EXPECT_EQ(img.channels(), 4);
    expect_same_values(img, decode_with_oiio(bytes), "palette with tRNS");
}

// Palettes, a tRNS key, 16-bit and 1-bit files: not decoded here,
// and the header callback is not called (nothing allocated, no budget spent).
TEST(PngDecode, PalettesTransparencyKeysAndOtherDepthsAreLeftToOpenImageIO) {
    struct Case {
        int colour, depth;
        bool trns;
    };
    for (const Case c : {Case{PNG_COLOR_TYPE_RGB, 8, true},
                         Case{PNG_COLOR_TYPE_GRAY, 8, true}, Case{PNG_COLOR_TYPE_RGB, 16, false},
                         Case{PNG_COLOR_TYPE_GRAY, 16, false}, Case{PNG_COLOR_TYPE_GRAY, 1, false}}) {
        const std::vector<unsigned char> bytes = encode_with_libpng(13, 9, c.colour, c.depth, false, c.trns,
            [&](int x, int y, int k) { return c.depth == 1 ? static_cast<unsigned char>((x + y) % 2) : wavy(x, y, k); });
        ASSERT_FALSE(bytes.empty());
        EXPECT_FALSE(decode_png(bytes.data(), bytes.size(), must_not_be_called, nullptr))
            << "colour " << c.colour << " depth " << c.depth << " tRNS " << c.trns;
        const ImageF through_io = decode_image(bytes.data(), bytes.size(), "t.png");  // OpenImageIO's
        expect_same_values(through_io, decode_with_oiio(bytes), "decode_image of colour " + std::to_string(c.colour));
    }
}

// Damage: ours gives up (false) or gives OpenImageIO's values; decode_image's outcome is always
// OpenImageIO's. A file without IEND, which libpng reports at its end and OpenImageIO reads, is
// decoded by OpenImageIO under a budget that holds exactly one image: the budget ours charged
// before giving up was given back.
TEST(PngDecode, DamagedFilesGetOpenImageIOsOutcomeAndTheBudgetIsChargedOnce) {
    const std::vector<unsigned char> good = encode_with_libpng(41, 17, PNG_COLOR_TYPE_RGB, 8, false, false, wavy);
    const std::size_t need = std::size_t(41) * 17 * 4 * sizeof(float);
    std::vector<unsigned char> no_iend(good.begin(), good.end() - 12);
    DecodeBudget one{need, "one image"};
    const ImageF img = decode_image(no_iend.data(), no_iend.size(), "t.png", &one);
    expect_same_values(img, decode_with_oiio(no_iend), "no IEND");
    EXPECT_EQ(one.bytes_left, 0u);
    for (std::size_t cut : {good.size() / 2, good.size() - 20, std::size_t(40)}) {
        std::vector<unsigned char> bytes(good.begin(), good.begin() + std::ptrdiff_t(cut));
        bytes.back() ^= 0x5a;
        ImageF ours;
        const bool decoded = decode_png(bytes.data(), bytes.size(), allocate_into, &ours);
        ImageF theirs;
        const std::string e = oiio().decode(bytes.data(), bytes.size(), "png", "memory.png", allocate_into, &theirs);
        if (decoded) {
            ASSERT_EQ(e, "") << "cut " << cut;
            expect_same_values(ours, theirs, "cut " + std::to_string(cut));
        }
        bool threw = false;
        try {
            const ImageF via = decode_image(bytes.data(), bytes.size(), "t.png");
            if (e.empty()) expect_same_values(via, theirs, "decode_image, cut " + std::to_string(cut));
        } catch (const Error&) {
            threw = true;
        }
        EXPECT_EQ(threw, !e.empty()) << "cut " << cut << ": " << e;
    }
}

}  // namespace aq
