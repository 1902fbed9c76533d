// tests/core/jpeg_test.cpp — core/jpeg.h's decoder gives OpenImageIO's values, bit for bit, on
// the real papers and on grey, progressive, damaged and synthetic files; CMYK is left to
// OpenImageIO.
#include "core/jpeg.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <jpeglib.h>

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

//! OpenImageIO's JPEG reader on the same bytes (through the module, as core/io.cpp used to).
ImageF decode_with_oiio(const std::vector<unsigned char>& bytes) { return test::decode_with_oiio(bytes, "jpeg"); }

//! Ours, asserting that ours (not the OpenImageIO fallback) decoded it.
ImageF decode_with_ours(const std::vector<unsigned char>& bytes) {
    ImageF img;
    EXPECT_TRUE(decode_jpeg(bytes.data(), bytes.size(), "test", allocate_into, &img));
    return img;
}

//! A JPEG written by libjpeg: w x h, `components` of `in_space`, values from `value(x, y, c)`.
template <class F>
std::vector<unsigned char> encode_jpeg(int w, int h, int components, J_COLOR_SPACE in_space, bool progressive,
                                       F value) {
    jpeg_compress_struct c{};
    jpeg_error_mgr err;
    c.err = jpeg_std_error(&err);
    jpeg_create_compress(&c);
    unsigned char* mem = nullptr;
    unsigned long size = 0;
    jpeg_mem_dest(&c, &mem, &size);
    c.image_width = JDIMENSION(w);
    c.image_height = JDIMENSION(h);
    c.input_components = components;
    c.in_color_space = in_space;
    jpeg_set_defaults(&c);
    jpeg_set_quality(&c, 90, TRUE);
    if (progressive) jpeg_simple_progression(&c);
    jpeg_start_compress(&c, TRUE);
    std::vector<unsigned char> row(std::size_t(w) * components);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x)
            for (int k = 0; k < components; ++k) row[std::size_t(x) * components + k] = value(x, y, k);
        JSAMPROW r = row.data();
        jpeg_write_scanlines(&c, &r, 1);
    }
    jpeg_finish_compress(&c);
    std::vector<unsigned char> bytes(mem, mem + size);
    jpeg_destroy_compress(&c);
    std::free(mem);
    return bytes;
}

TEST(JpegDecoder, GivesOpenImageIOsValuesOnTheRealPapersAndScreenshots) {
    int files = 0;
    for (const auto& e : fs::recursive_directory_iterator(test::shared_dir() + "/assets")) {
        const std::string ext = e.path().extension().string();
        if (!e.is_regular_file() || (ext != ".jpg" && ext != ".jpeg")) continue;
        const std::vector<unsigned char> bytes = read_input_file(e.path().string(), kMaxImageFileBytes, "image");
        expect_same_values(decode_with_ours(bytes), decode_with_oiio(bytes), e.path().string());
        ++files;
    }
    EXPECT_GE(files, 4);  // the four papers at least
}

TEST(JpegDecoder, GivesOpenImageIOsValuesOnGreyProgressiveAndEveryCode) {
    // Every 8-bit code in every channel, and edges the IDCT and upsampling must reproduce.
    const auto pattern = [](int x, int y, int k) { return (unsigned char)((x * 7 + y * 13 + k * 85) & 255); };
    for (bool progressive : {false, true}) {
        const std::string what = progressive ? "progressive" : "baseline";
        const auto rgb = encode_jpeg(301, 173, 3, JCS_RGB, progressive, pattern);
        const ImageF ours = decode_with_ours(rgb);
        EXPECT_EQ(ours.channels(), 3);
        expect_same_values(ours, decode_with_oiio(rgb), what + " RGB");
        const auto grey = encode_jpeg(64, 257, 1, JCS_GRAYSCALE, progressive, pattern);
        const ImageF ours_grey = decode_with_ours(grey);
        EXPECT_EQ(ours_grey.channels(), 1);
        expect_same_values(ours_grey, decode_with_oiio(grey), what + " grey");
    }
    // The table is v / 255: code 255 is exactly 1 and 0 exactly 0.
    const auto flat = encode_jpeg(16, 16, 1, JCS_GRAYSCALE, false, [](int, int, int) { return (unsigned char)255; });
    EXPECT_EQ(decode_with_ours(flat).at(3, 3, 0), 1.0f);
}

TEST(JpegDecoder, DamagedFilesDecodeAsOpenImageIODecodesThem) {
    const auto pattern = [](int x, int y, int k) { return (unsigned char)((x ^ y) * 3 + k * 40); };
    for (bool progressive : {false, true}) {
        const auto full = encode_jpeg(200, 120, 3, JCS_RGB, progressive, pattern);
        // Truncated: libjpeg warns and fills the rest; neither reader treats the warning as fatal.
        for (std::size_t keep : {full.size() / 2, full.size() - 3}) {
            const std::vector<unsigned char> cut(full.begin(), full.begin() + std::ptrdiff_t(keep));
            expect_same_values(decode_with_ours(cut), decode_with_oiio(cut),
                               std::string(progressive ? "progressive" : "baseline") + " cut at " + std::to_string(keep));
        }
    }
    // No frame header at all: an aq::Error naming the file.
    const std::vector<unsigned char> garbage = {0xFF, 0xD8, 0xFF, 0xD9, 0, 1, 2, 3};
    ImageF img;
    try {
        decode_jpeg(garbage.data(), garbage.size(), "image 'x.jpg'", allocate_into, &img);
        ADD_FAILURE() << "a JPEG without a frame was decoded";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("image 'x.jpg': cannot be decoded"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(img.empty());
}

TEST(JpegDecoder, TheHeaderIsCheckedBeforeTheImageIsAllocated) {
    const auto bytes = encode_jpeg(40, 30, 3, JCS_RGB, false, [](int x, int, int) { return (unsigned char)x; });
    struct Seen {
        ImageHeader h;
        bool called = false;
    } seen;
    const auto refuse = [](void* ctx, const ImageHeader& h) -> PixelDest {
        static_cast<Seen*>(ctx)->h = h;
        static_cast<Seen*>(ctx)->called = true;
        throw Error("refused");
    };
    EXPECT_THROW(decode_jpeg(bytes.data(), bytes.size(), "x", refuse, &seen), Error);
    EXPECT_TRUE(seen.called);
    EXPECT_EQ(seen.h.width, 40);
    EXPECT_EQ(seen.h.height, 30);
    EXPECT_EQ(seen.h.nchannels, 3);
    // Through decode_image, the decode budget is such a check.
    DecodeBudget budget{40 * 30 * 4 * sizeof(float) - 1, "the test's budget"};
    EXPECT_THROW(decode_image(bytes.data(), bytes.size(), "x.jpg", &budget), BudgetError);
}

TEST(JpegDecoder, CmykIsLeftToOpenImageIO) {
    const auto cmyk = encode_jpeg(24, 16, 4, JCS_CMYK, false, [](int x, int y, int k) {
        return (unsigned char)(k == 3 ? 255 : x * 10 + y);
    });
    ImageF img;
    EXPECT_FALSE(decode_jpeg(cmyk.data(), cmyk.size(), "x", allocate_into, &img));
    EXPECT_TRUE(img.empty());  // the callback was not called
    const ImageF decoded = decode_image(cmyk.data(), cmyk.size(), "cmyk.jpg");  // OpenImageIO's reader
    EXPECT_EQ(decoded.width(), 24);
    EXPECT_EQ(decoded.height(), 16);
}

// The live view's preview encoder: what it writes decodes to the image within the loss of its
// quality (a smooth gradient: within a few codes at either quality), at its size and channels.
TEST(JpegEncoder, PreviewsDecodeToTheImage) {
    ImageF img(96, 64, 3);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 96; ++x)
            for (int c = 0; c < 3; ++c) img.at(x, y, c) = float(x + 2 * y + 40 * c) / 400.0f;
    std::vector<unsigned char> bytes, rows;
    double worst[2] = {0, 0};
    int k = 0;
    for (int q : {kPreviewJpegQuality, 100}) {
        aq::encode_jpeg(img, q, bytes, rows);
        const ImageF back = decode_with_ours(bytes);
        ASSERT_EQ(back.width(), 96);
        ASSERT_EQ(back.height(), 64);
        ASSERT_EQ(back.channels(), 3);
        for (std::size_t i = 0; i < img.num_values(); ++i) worst[k] = std::max(worst[k], double(std::abs(back.data()[i] - img.data()[i])));
        ++k;
    }
    EXPECT_LT(worst[0], 8.0 / 255.0);
    EXPECT_LT(worst[1], 3.0 / 255.0);
    ImageF rgba(4, 4, 4);
    EXPECT_THROW(aq::encode_jpeg(rgba, 85, bytes, rows), Error);
    EXPECT_THROW(aq::encode_jpeg(img, 0, bytes, rows), Error);
}

}  // namespace
}  // namespace aq
