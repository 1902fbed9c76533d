// tests/core/input_test.cpp — every reader checks what it is given before it allocates
// (core/input.h, core/json_file.h, core/io.h readers): FIFOs and devices refused without
// blocking, size caps, volume images, decode budgets, JSON errors naming file and key.
#include "core/input.h"

#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>

#include <gtest/gtest.h>

#include "core/io.h"
#include "core/json_file.h"
#include "tests/test_support.h"

namespace aq {
namespace {
namespace fs = std::filesystem;

std::string message_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "(no error)";
}

void put(const std::string& path, const std::string& bytes) {
    std::ofstream f(path, std::ios::binary);
    f << bytes;
}

//! A DDS volume texture (DDSCAPS2_VOLUME, depth d) of w x h x d RGBA8 texels.
std::string dds_volume(int w, int h, int d) {
    std::string b(128, '\0');
    auto u32 = [&](std::size_t off, std::uint32_t v) { std::memcpy(&b[off], &v, 4); };
    std::memcpy(&b[0], "DDS ", 4);
    u32(4, 124);                                        // header size
    u32(8, 0x1 | 0x2 | 0x4 | 0x1000 | 0x800000);        // CAPS HEIGHT WIDTH PIXELFORMAT DEPTH
    u32(12, std::uint32_t(h));
    u32(16, std::uint32_t(w));
    u32(20, std::uint32_t(w * 4));                      // pitch
    u32(24, std::uint32_t(d));                          // depth
    u32(76, 32);                                        // pixel format size
    u32(80, 0x40 | 0x1);                                // DDPF_RGB | ALPHAPIXELS
    u32(88, 32);                                        // bits per pixel
    u32(92, 0x00ff0000);
    u32(96, 0x0000ff00);
    u32(100, 0x000000ff);
    u32(104, 0xff000000);
    u32(108, 0x1000 | 0x8);                             // DDSCAPS_TEXTURE | COMPLEX
    u32(112, 0x200000);                                 // DDSCAPS2_VOLUME
    b += std::string(std::size_t(w) * h * d * 4, '\x7f');
    return b;
}

TEST(InputFile, ReadsARegularFileWhole) {
    const std::string p = test::output_dir() + "/a.bin";
    put(p, std::string("abc\0def", 7));
    const auto b = read_input_file(p, 100, "data");
    ASSERT_EQ(b.size(), 7u);
    EXPECT_EQ(b[4], 'd');
    EXPECT_TRUE(is_input_of_run(p));
}

TEST(InputFile, RefusesAFifoWithoutBlocking) {
    const std::string p = test::output_dir() + "/fifo";
    ASSERT_EQ(::mkfifo(p.c_str(), 0600), 0) << std::strerror(errno);
    const auto t0 = std::chrono::steady_clock::now();
    const std::string m = message_of([&] { read_input_file(p, 1000, "paper"); });
    EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(5));
    EXPECT_NE(m.find("FIFO"), std::string::npos) << m;
    EXPECT_NE(m.find(p), std::string::npos) << m;
    EXPECT_NE(message_of([&] { read_image(p); }).find("FIFO"), std::string::npos);
}

TEST(InputFile, RefusesDevicesAndFolders) {
    EXPECT_NE(message_of([] { read_input_file("/dev/zero", 1 << 20, "style file"); }).find("character device"),
              std::string::npos);
    EXPECT_NE(message_of([] { read_json_file("/dev/zero", "style file"); }).find("character device"), std::string::npos);
    EXPECT_NE(message_of([] { read_input_file(test::output_dir(), 100, "scene"); }).find("folder"), std::string::npos);
    EXPECT_NE(message_of([] { read_input_file("/no/such/file", 100, "scene"); }).find("not found"), std::string::npos);
}

TEST(InputFile, RefusesFilesOverTheCapBeforeReading) {
    const std::string p = test::output_dir() + "/big.bin";
    put(p, std::string(1000, 'x'));
    const std::string m = message_of([&] { read_input_file(p, 999, "data"); });
    EXPECT_NE(m.find("exceeds the limit of 999"), std::string::npos) << m;
}

TEST(ImageRead, RefusesAVolumeTextureFromItsHeader) {
    // Issue 8: a DDS volume (depth 8) once overflowed a width x height x channels buffer.
    const std::string p = test::output_dir() + "/volume.dds";
    put(p, dds_volume(4, 4, 8));
    const std::string m = message_of([&] { read_image(p); });
    EXPECT_NE(m.find("volume"), std::string::npos) << m;
    EXPECT_NE(m.find("volume.dds"), std::string::npos) << m;
    const std::string big = test::output_dir() + "/volume4096.dds";
    put(big, dds_volume(16, 16, 4096));
    EXPECT_NE(message_of([&] { read_image(big); }).find("volume"), std::string::npos);
}

TEST(ImageRead, DecodeBudgetIsCheckedFromTheHeader) {
    const std::string p = test::output_dir() + "/img.png";
    write_image(p, ImageF(64, 32, 3, 0.5f));
    DecodeBudget budget{64 * 32 * 16 * 2 - 1, "a test budget"};
    EXPECT_NO_THROW(read_image(p, &budget));  // one image fits
    EXPECT_EQ(budget.bytes_left, std::size_t(64 * 32 * 16 - 1));
    try {
        read_image(p, &budget);
        ADD_FAILURE() << "second image should exceed the budget";
    } catch (const BudgetError& e) {
        EXPECT_NE(std::string(e.what()).find("a test budget"), std::string::npos) << e.what();
    }
}

TEST(Json, NumberOutOfRangeNamesFileAndKey) {
    const std::string p = test::output_dir() + "/style.json";
    put(p, R"({"name": "x", "paper": {"file": "p.png", "scale": 1e400}})");
    const std::string m = message_of([&] { read_json_file(p, "style file"); });
    EXPECT_NE(m.find("style.json"), std::string::npos) << m;
    EXPECT_NE(m.find("paper.scale"), std::string::npos) << m;
    EXPECT_EQ(m.find("[json.exception"), std::string::npos) << m;
}

TEST(Json, ArrayPositionsAreNamed) {
    const std::string m = message_of([] { parse_json(R"({"steps": [{"a": 1}, {"b": 2e999}]})", "f.json"); });
    EXPECT_NE(m.find("steps[1].b"), std::string::npos) << m;
}

TEST(Json, DeepNestingIsRefusedBeforeParsing) {
    const std::string deep(100000, '[');
    const std::string m = message_of([&] { parse_json(deep, "deep.json"); });
    EXPECT_NE(m.find("nested deeper"), std::string::npos) << m;
}

TEST(PathPolicy, InsideTheFolderIsAllowedOutsideIsNot) {
    const fs::path root = fs::path(test::output_dir()) / "model";
    fs::create_directories(root / "tex");
    put((root / "tex" / "a.png").string(), "x");
    put((fs::path(test::output_dir()) / "secret.bin").string(), "s");
    fs::create_symlink(fs::path(test::output_dir()) / "secret.bin", root / "link.bin");
    PathPolicy pol{root, false};
    EXPECT_EQ(path_policy_violation(pol, (root / "tex" / "a.png").string()), "");
    EXPECT_EQ(path_policy_violation(pol, (root / "tex" / ".." / "tex" / "a.png").string()), "");
    EXPECT_NE(path_policy_violation(pol, (root / ".." / "secret.bin").string()), "");
    EXPECT_NE(path_policy_violation(pol, (root / "link.bin").string()), "");  // symlink target outside
    EXPECT_NE(path_policy_violation(pol, "/etc/passwd"), "");
    EXPECT_NE(path_policy_violation(pol, (fs::path(test::output_dir()) / "modelx" / "a.png").string()), "");
    pol.allow_outside = true;
    EXPECT_EQ(path_policy_violation(pol, "/etc/passwd"), "");
}

}  // namespace
}  // namespace aq
