// tests/scenes/fuzz_regressions_test.cpp — the minimised inputs of fuzzing findings
// (fuzz/regressions/<target>/, fuzz/README.md "Findings") read by the unit tests, so a finding fixed
// stays fixed in every build, not only in the clang fuzz build. Each reader must end in an
// aq::Error (or load): any other exception, a crash or a sanitizer report fails.
#include <gtest/gtest.h>

#include <filesystem>
#include <algorithm>
#include <fstream>
#include <memory>
#include <iterator>
#include <string>
#include <vector>

#include "core/io.h"
#include "scenes/gltf_loader.h"
#include "scenes/scene_file.h"
#include "tests/test_support.h"

namespace aq::scene {
namespace {
namespace fs = std::filesystem;

fs::path regressions(const std::string& target) { return fs::path(aq::test::source_dir()) / "fuzz" / "regressions" / target; }

std::vector<unsigned char> bytes_of(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

//! Copies a regression input into this test's own folder (readers may look beside it).
std::string copy_to_output(const fs::path& p, const std::string& name) {
    const fs::path dst = fs::path(aq::test::output_dir()) / "fuzz" / name;
    fs::create_directories(dst.parent_path());
    fs::copy_file(p, dst, fs::copy_options::overwrite_existing);
    return dst.string();
}

//! Runs fn; passes on success or aq::Error, fails on any other exception.
template <class Fn>
void expect_clean(const std::string& what, Fn&& fn) {
    try {
        fn();
    } catch (const aq::Error&) {
    } catch (const std::exception& e) {
        ADD_FAILURE() << what << ": threw a non-aq::Error exception: " << e.what();
    }
}

//! The aq::Error message of decoding `bytes` from a heap copy of exactly their size (so ASan sees
//! any read outside them); a failure, and "", when the bytes decode.
std::string decode_error(const std::vector<unsigned char>& bytes, const std::string& name) {
    const std::unique_ptr<unsigned char[]> heap(new unsigned char[bytes.size()]);
    std::copy(bytes.begin(), bytes.end(), heap.get());
    try {
        (void)decode_image_bytes(heap.get(), bytes.size(), name);
    } catch (const aq::Error& e) {
        return e.what();
    }
    ADD_FAILURE() << name << ": decoded";
    return "";
}

// OpenImageIO 2.4's GIF reader throws std::length_error from ImageInput::open for a 13-byte GIF
// whose logical screen is 12298 x 26234; decode_image let it escape (not an aq::Error), so a glTF
// texture in that state failed the whole model instead of being "treated as absent".
TEST(FuzzRegressions, GifWithHugeScreenIsAnImageError) {
    const fs::path in = regressions("image") / "gif-screen-size-length-error.gif";
    const std::vector<unsigned char> b = bytes_of(in);
    ASSERT_EQ(b.size(), 13u);
    // GIF is no longer read at all (the format allow-list in core/io.cpp); decode_image also turns
    // any exception of a reader into aq::Error.
    const std::string e = decode_error(b, "texture.gif");
    EXPECT_NE(e.find("image 'texture.gif': "), std::string::npos) << e;
    const std::string path = copy_to_output(in, "paper.gif");
    EXPECT_THROW((void)aq::read_image(path), aq::Error);
}

// A 14-byte GIF announcing a 16383 x 16383 screen: OpenImageIO's GIF reader allocated the whole
// screen (1.3 GB resident, 3.4 s) inside open(), before the size check on the decoded header.
// First fixed by checking the GIF screen from its header; GIF is now outside the allow-list of
// formats read, so no GIF reaches OpenImageIO.
TEST(FuzzRegressions, GifScreenIsCheckedBeforeOpenImageIOAllocatesIt) {
    const std::vector<unsigned char> b = bytes_of(regressions("image") / "gif-screen-16383x16383.gif");
    ASSERT_EQ(b.size(), 14u);
    const std::string e = decode_error(b, "bomb.gif");
    EXPECT_NE(e.find("the 'gif' format is not read"), std::string::npos) << e;
}

// Two BMPs on which OpenImageIO 2.4's BMP reader failed under ASan in CI's fuzz smoke runs:
// a 70-byte file whose pixel-data offset is -2, which its in-memory reader then copied from before
// the buffer (finding 6; core/oiio_mem_reader.h now bounds every read, tests/core/
// mem_reader_test.cpp), and a 1432-byte 32-bit BI_BITFIELDS file on which the BMP reader itself
// dereferenced address -2 (finding 7, a SEGV inside read_native_scanline). BMP is no longer read:
// both are refused, by their magic bytes, before any decoder runs.
TEST(FuzzRegressions, BmpFilesAreRefusedBeforeTheBmpReaderRuns) {
    for (const char* name : {"bmp-pixel-offset-minus-2.bmp", "bmp-bitfields-32bpp-segv.bmp"}) {
        SCOPED_TRACE(name);
        const fs::path in = regressions("image") / name;
        const std::vector<unsigned char> b = bytes_of(in);
        ASSERT_GE(b.size(), 54u);
        ASSERT_EQ(b[0], 'B');
        const std::string e = decode_error(b, "texture.png");  // the magic bytes win over the name
        EXPECT_NE(e.find("the 'bmp' format is not read"), std::string::npos) << e;
        EXPECT_THROW((void)aq::read_image(copy_to_output(in, "paper.bmp")), aq::Error);
    }
}

// A 408-byte progressive JPEG announcing 37318 x 11143: OpenImageIO 2.4's JPEG reader allocated
// libjpeg's whole-image buffers inside open() (2.5 GB resident, 3 s in the release CLI) before its
// spec reached our size check (fuzz/README.md finding 8). The frame size is now read from the
// JPEG's own header first; the message says so (the late check names no header).
TEST(FuzzRegressions, JpegFrameSizeIsCheckedBeforeOpenImageIOAllocates) {
    const fs::path in = regressions("image") / "jpeg-progressive-37318x11143-in-408-bytes.jpg";
    const std::vector<unsigned char> b = bytes_of(in);
    ASSERT_EQ(b.size(), 408u);
    const std::string e = decode_error(b, "texture.jpg");
    EXPECT_NE(e.find("(JPEG frame header)"), std::string::npos) << e;
    EXPECT_NE(e.find("37318x11143"), std::string::npos) << e;
}

// A 1,433-byte run-length TGA announcing 2835 x 11653 (within the pixel limit and the general
// 32,768 pixels-per-byte rule) made us allocate the image, 647 MB and 1.06 s in the release CLI,
// before the reader hit the end of the data (fuzz/README.md finding 9, a timeout under ASan). TGA
// packs at most 128 pixels in two bytes, so it is refused from its header; a real, maximally
// compressed TGA (one run-length packet per 128 pixels) still reads.
TEST(FuzzRegressions, TgaDensityIsBoundedByItsRunLengthCoding) {
    const fs::path in = regressions("image") / "tga-rle-2835x11653-in-1433-bytes.tga";
    const std::vector<unsigned char> b = bytes_of(in);
    ASSERT_EQ(b.size(), 1433u);
    const std::string e = decode_error(b, "texture.tga");
    EXPECT_NE(e.find("2835x11653"), std::string::npos) << e;
    EXPECT_NE(e.find("64 pixels per byte"), std::string::npos) << e;

    // 256 x 256 8-bit grey, every row two full run-length packets of value 200: 62.9 pixels/byte.
    std::vector<unsigned char> tga = {0, 0, 11, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 1, 8, 0};
    for (int k = 0; k < 512; ++k) tga.insert(tga.end(), {0xFF, 200});
    const ImageF img = decode_image_bytes(tga.data(), tga.size(), "dense.tga");
    ASSERT_EQ(img.width(), 256);
    ASSERT_EQ(img.height(), 256);
    EXPECT_FLOAT_EQ(img.at(17, 201, 0), 200.0f / 255.0f);
}

TEST(FuzzRegressions, EveryImageInputIsReadOrRefused) {
    for (const auto& e : fs::directory_iterator(regressions("image"))) {
        SCOPED_TRACE(e.path().string());
        const std::vector<unsigned char> b = bytes_of(e.path());
        expect_clean("decode_image_bytes", [&] { (void)decode_image_bytes(b.data(), b.size(), e.path().filename().string()); });
        const std::string path = copy_to_output(e.path(), e.path().filename().string());
        expect_clean("read_image", [&] { (void)aq::read_image(path); });
    }
}

TEST(FuzzRegressions, EveryGltfAndSceneInputIsLoadedOrRefused) {
    for (const std::string target : {"gltf", "scene_file"}) {
        if (!fs::is_directory(regressions(target))) continue;
        for (const auto& e : fs::directory_iterator(regressions(target))) {
            SCOPED_TRACE(e.path().string());
            if (target == "gltf") {
                const std::string path = copy_to_output(e.path(), "in.gltf");
                expect_clean("load_gltf", [&] { (void)load_gltf(path); });
            } else {
                const std::string path = copy_to_output(e.path(), "scene.json");
                expect_clean("load_scene", [&] { (void)load_scene(path); });
            }
        }
    }
}

}  // namespace
}  // namespace aq::scene
