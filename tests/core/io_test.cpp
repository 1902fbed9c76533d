// tests/core/io_test.cpp — round trips through OpenImageIO and atomic replacement.
#include "core/io.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "core/input.h"

#include "core/compare.h"
#include "core/hash.h"
#include "tests/test_support.h"

namespace aq {

TEST(ImageIO, ExrRoundTripIsExact) {
    ImageF img(7, 5, 4);
    for (int y = 0; y < 5; ++y)
        for (int x = 0; x < 7; ++x)
            for (int c = 0; c < 4; ++c) img.at(x, y, c) = 0.1f * x - 0.37f * y + 1e-3f * c;
    std::string p = test::output_dir() + "/io_roundtrip.exr";
    write_image(p, img);
    ImageF back = read_image(p);
    EXPECT_EQ(sha256_hex(img), sha256_hex(back));
}

TEST(ImageIO, PngQuantisesAndClamps) {
    ImageF img(2, 1, 3);
    img.at(0, 0, 0) = 2.0f;   // clamps to 255
    img.at(0, 0, 1) = -1.0f;  // clamps to 0
    img.at(1, 0, 2) = 0.5f;   // 127.5 rounds to 128
    std::string p = test::output_dir() + "/io_quant.png";
    write_image(p, img);
    ImageF back = read_image(p);
    EXPECT_FLOAT_EQ(back.at(0, 0, 0), 1.0f);
    EXPECT_FLOAT_EQ(back.at(0, 0, 1), 0.0f);
    EXPECT_FLOAT_EQ(back.at(1, 0, 2), 128.0f / 255.0f);
}

// The encoder keeps its buffers between writes on a thread (an animation's writer reuses the
// pages): a file written after a larger one of another format must hold exactly its own bytes —
// the same bytes as when it was written first — and decode to its own values.
TEST(ImageIO, EachWriteHoldsOnlyItsOwnBytesWhenTheEncoderReusesItsBuffers) {
    auto bytes = [](const std::string& path) {
        std::ifstream f(path, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
    };
    ImageF small(3, 2, 3), big(640, 480, 4);
    for (std::size_t i = 0; i < small.num_values(); ++i) small.data()[i] = float(i % 7) / 6.0f;
    for (std::size_t i = 0; i < big.num_values(); ++i) big.data()[i] = float((i * 2654435761u) % 1000) / 999.0f;
    const std::string dir = test::output_dir();
    for (const char* ext : {".png", ".exr"}) {
        const std::string first = dir + "/reuse_first" + ext, again = dir + "/reuse_again" + ext;
        write_image(first, small);
        write_image(dir + "/reuse_big.exr", big);  // grows the encoded buffer past either small file
        write_image(dir + "/reuse_big.png", big);  // grows the 8-bit scratch too
        write_image(again, small);
        EXPECT_EQ(bytes(first), bytes(again)) << ext;
        const ImageF back = read_image(again);
        ASSERT_TRUE(back.same_size(small)) << ext;
        for (int y = 0; y < small.height(); ++y)
            for (int x = 0; x < small.width(); ++x)
                for (int c = 0; c < 3; ++c) {
                    const float want = std::string(ext) == ".png" ? float(to_unorm8(small.at(x, y, c))) / 255.0f : small.at(x, y, c);
                    EXPECT_FLOAT_EQ(back.at(x, y, c), want) << ext << " at " << x << "," << y << "," << c;
                }
    }
}

// Only the documented formats reach a decoder (docs/limits.md "Image formats"): the format comes
// from the magic bytes where known, else from the extension, and OpenImageIO is not allowed to
// fall back to trying its other readers.
// to_unorm8 equals its definition (NaN -> 0, clamp, std::lround(v * 255)): every 37th float of
// [0, 1] by bit pattern (28.8 million; all 1.07 billion took 10 s), the 33 floats around every tie
// (k + 1/2) / 255, and values outside the range.
TEST(ImageIO, Unorm8EqualsLroundOfTheClampedValue) {
    auto plain = [](float v) {
        v = std::isnan(v) ? 0.0f : std::clamp(v, 0.0f, 1.0f);
        return static_cast<unsigned char>(std::lround(v * 255.0f));
    };
    const std::uint32_t one = 0x3f800000u;  // the bits of 1.0f
    for (std::uint32_t b = 0; b <= one; b += 37) {
        float v;
        std::memcpy(&v, &b, sizeof v);
        if (to_unorm8(v) != plain(v)) FAIL() << "differs at " << v;
    }
    for (int k = 0; k < 255; ++k) {
        float v = (float(k) + 0.5f) / 255.0f;
        for (int u = 0; u < 16; ++u) v = std::nextafter(v, 0.0f);
        for (int u = 0; u < 33; ++u, v = std::nextafter(v, 1.0f)) EXPECT_EQ(to_unorm8(v), plain(v)) << v;
    }
    for (float v : {-1.0f, -0.0f, 1.5f, 1e30f, -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity(),
                    std::numeric_limits<float>::quiet_NaN()})
        EXPECT_EQ(to_unorm8(v), plain(v)) << v;
}

namespace {

//! Inputs of the quantisation tests: every `stride`-th float bit pattern (negatives, NaNs,
//! infinities, denormals included), every tie (k + 0.5) / 255 with its neighbours, +-0, 1, the float
//! above 1, +-infinity and NaN.
std::vector<float> unorm8_test_values(std::uint64_t stride) {
    std::vector<float> v;
    for (std::uint64_t b = 0; b <= 0xffffffffu; b += stride) {
        float f;
        const std::uint32_t u = std::uint32_t(b);
        std::memcpy(&f, &u, sizeof f);
        v.push_back(f);
    }
    for (int k = 0; k < 255; ++k) {
        const float tie = (float(k) + 0.5f) / 255.0f;
        for (float t : {tie, std::nextafter(tie, 0.0f), std::nextafter(tie, 1.0f)}) v.push_back(t);
    }
    for (float f : {0.0f, -0.0f, 1.0f, std::nextafter(1.0f, 2.0f), -std::numeric_limits<float>::infinity(),
                    std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN()})
        v.push_back(f);
    return v;
}

}  // namespace

// The eight-at-a-time quantisation equals to_unorm8 value by value: every 331st float bit pattern
// (13 million: negatives, NaNs, infinities, denormals included), the ties, +-0, at unaligned starts
// and lengths that leave a scalar tail.
TEST(ImageIO, Unorm8OfManyValuesEqualsTheScalarFunction) {
    const std::vector<float> v = unorm8_test_values(331);
    for (std::size_t start : {std::size_t(0), std::size_t(3)}) {
        const std::size_t n = v.size() - start - 5;  // a tail of n % 8 values
        std::vector<unsigned char> got(n + 1, 0xaa);
        to_unorm8_n(v.data() + start, got.data() + 1, n);
        EXPECT_EQ(got[0], 0xaa);  // nothing written before dst
        for (std::size_t i = 0; i < n; ++i)
            if (got[i + 1] != to_unorm8(v[start + i])) FAIL() << "differs at " << v[start + i] << " (index " << i << ")";
    }
}

// The RGB bytes of RGBA pixels: to_unorm8 of every colour value, alpha left out, over the same
// values as above (each value once in each of the R, G, B and A lanes: a lane mix-up or a value from
// the alpha shows), pixel counts that leave a scalar tail, nothing written past the last byte.
TEST(ImageIO, Unorm8RgbOfRgbaPixelsEqualsTheScalarFunction) {
    const std::vector<float> v = unorm8_test_values(1331);
    for (int shift = 0; shift < 4; ++shift) {  // value i in lane (i + shift) % 4
        std::vector<float> rgba(v.size() + 4, 0.25f);
        for (std::size_t i = 0; i < v.size(); ++i) rgba[i + std::size_t(shift)] = v[i];
        for (std::size_t pixels : {rgba.size() / 4, rgba.size() / 4 - 3}) {
            std::vector<unsigned char> got(3 * pixels + 1, 0xaa);
            to_unorm8_rgb_n(rgba.data(), got.data(), pixels);
            EXPECT_EQ(got[3 * pixels], 0xaa);  // nothing written past the end
            for (std::size_t p = 0; p < pixels; ++p)
                for (std::size_t c = 0; c < 3; ++c)
                    if (got[3 * p + c] != to_unorm8(rgba[4 * p + c]))
                        FAIL() << "pixel " << p << " channel " << c << ": " << rgba[4 * p + c] << " shift " << shift;
        }
    }
}

TEST(ImageIO, OnlyTheDocumentedFormatsAreDecoded) {
    ImageF img(3, 2, 3);
    img.at(1, 1, 2) = 0.5f;
    const std::string dir = test::output_dir();
    for (const char* ext : {".png", ".exr", ".tif", ".tga", ".hdr", ".jpg"}) {
        SCOPED_TRACE(ext);
        const std::string p = dir + "/allowed" + ext;
        write_image(p, img);
        const ImageF back = read_image(p);
        EXPECT_EQ(back.width(), 3);
        EXPECT_EQ(back.height(), 2);
    }
    // A PNG named .gif is read as the PNG it is (magic bytes win over the name).
    std::filesystem::copy_file(dir + "/allowed.png", dir + "/png_named.gif");
    EXPECT_EQ(read_image(dir + "/png_named.gif").width(), 3);
    // Bytes that are no valid PNG, in a file named .png, are not handed to OpenImageIO's other
    // readers (its create() tries every reader it has when the named one refuses the bytes):
    // a binary PPM that its PNM reader would decode is refused.
    std::ofstream(dir + "/ppm_named.png", std::ios::binary) << "P6\n3 2\n255\n" << std::string(18, '\x40');
    EXPECT_THROW((void)read_image(dir + "/ppm_named.png"), Error);
    // BMP is written but no longer read (OpenImageIO 2.4's BMP reader: fuzz/README.md findings 6, 7).
    write_image(dir + "/written.bmp", img);
    try {
        (void)read_image(dir + "/written.bmp");
        ADD_FAILURE() << "a BMP was decoded";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("the 'bmp' format is not read"), std::string::npos) << e.what();
    }
    // Formats OpenImageIO knows but we do not read, by magic or by name.
    const std::vector<std::pair<std::string, std::string>> refused = {
        {"a.gif", "GIF89a\x01\x00\x01\x00\x00\x00\x00;"},
        {"a.dds", std::string("DDS \x7c\x00\x00\x00", 8)},
        {"a.psd", "8BPS\x00\x01"},
        {"a.sgi", std::string("\x01\xda\x00\x01", 4)},
        {"a.ppm", "P6\n1 1\n255\nabc"},
    };
    for (const auto& [name, content] : refused) {
        SCOPED_TRACE(name);
        const std::string p = dir + "/" + name;
        std::ofstream(p, std::ios::binary) << content;
        try {
            (void)read_image(p);
            ADD_FAILURE() << "decoded";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("format is not read"), std::string::npos) << e.what();
        }
    }
}

// A header announcing more pixels than its bytes can hold is refused before decoding (fuzzing
// found a 21-byte RLE TGA announcing 2835 x 11775 that cost 0.97 s and 651 MB).
TEST(ImageIO, AHeaderPromisingMorePixelsThanItsBytesCanHoldIsRefused) {
    const std::string p = test::output_dir() + "/bomb.tga";
    const unsigned char tga[21] = {0, 0, 10, 0, 0, 0, 0, 0, 0x10, 0, 0, 0, 0x13, 0x0b, 0xff, 0x2d, 0x20, 0x88, 0xf5, 0xcb, 0xff};
    std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(tga), sizeof tga);
    try {
        (void)read_image(p);
        ADD_FAILURE() << "decoded";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("pixels per byte"), std::string::npos) << e.what();
    }
    // A real image of that format and a highly compressible PNG still read.
    ImageF flat(512, 512, 3, 0.25f);
    write_image(test::output_dir() + "/flat.png", flat);
    EXPECT_EQ(read_image(test::output_dir() + "/flat.png").width(), 512);
}

TEST(ImageIO, FailedWriteLeavesExistingFileUntouched) {
    std::string dir = test::output_dir();
    std::string p = dir + "/io_keep.png";
    ImageF good(4, 4, 3, 0.25f);
    write_image(p, good);
    auto before = std::filesystem::file_size(p);
    // An unknown extension fails before anything replaces the good file.
    EXPECT_THROW(write_image(dir + "/io_keep.notaformat", good), Error);
    EXPECT_THROW(write_image(dir + "/no_such_dir/x.png", good), Error);
    EXPECT_EQ(std::filesystem::file_size(p), before);
    for (auto& e : std::filesystem::directory_iterator(dir))
        EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
}

//! An image whose encoding is larger than the file-size limit used below (noise compresses badly).
ImageF noisy_image() {
    ImageF img(64, 64, 3);
    std::uint32_t h = 12345;
    for (std::size_t i = 0; i < img.num_values(); ++i) {
        h = h * 1664525u + 1013904223u;
        img.data()[i] = float(h >> 8) / float(1u << 24);
    }
    return img;
}

std::string file_bytes(const std::string& p) {
    std::ifstream f(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

bool has_temporaries(const std::string& dir) {
    for (auto& e : std::filesystem::directory_iterator(dir))
        if (e.path().filename().string().rfind(".aqtmp", 0) == 0) return true;
    return false;
}

// A full disk, simulated by the kernel: with RLIMIT_FSIZE every write past the limit fails with
// EFBIG (SIGXFSZ ignored, as the CLI does). The good file must survive byte for byte, the failure
// must be an aq::Error naming the file, and no temporary may be left.
class WriteFailure : public ::testing::TestWithParam<const char*> {};

TEST_P(WriteFailure, OnAFullFileSystemTheOldFileIsKept) {
    // The child re-executes this test ("threadsafe"; a plain fork() of a process whose encoder
    // thread pools run can deadlock), so it does every step itself and reports by exit code.
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    const std::string ext = GetParam();
    auto child = [&] {
        const std::string dir = test::output_dir();
        const std::string p = dir + "/keep" + ext;
        write_image(p, ImageF(8, 8, 3, 0.25f));  // the good file (small, written without a limit)
        const std::string before = file_bytes(p);
        ::signal(SIGXFSZ, SIG_IGN);
        rlimit lim;
        lim.rlim_cur = lim.rlim_max = 512;
        ::setrlimit(RLIMIT_FSIZE, &lim);
        try {
            write_image(p, noisy_image());
            std::_Exit(10);  // wrote past the limit: impossible unless errors are ignored
        } catch (const Error& e) {
            const std::string m = e.what();
            if (m.find(p) == std::string::npos || m.find("unchanged") == std::string::npos) {
                std::fprintf(stderr, "message: %s\n", m.c_str());
                std::_Exit(11);
            }
        }
        if (file_bytes(p) != before) std::_Exit(12);  // the good file was modified
        if (has_temporaries(dir)) std::_Exit(13);      // a temporary was left behind
        std::_Exit(3);
    };
    EXPECT_EXIT(child(), ::testing::ExitedWithCode(3), "") << "10: wrote past the limit, 11: message, 12: old file "
                                                              "modified, 13: temporary left";
    // Without the limit the same write succeeds and replaces the file.
    const std::string p = test::output_dir() + "/keep" + ext;
    write_image(p, ImageF(8, 8, 3, 0.25f));
    const std::string before = file_bytes(p);
    write_image(p, noisy_image());
    EXPECT_NE(file_bytes(p), before);
}

INSTANTIATE_TEST_SUITE_P(EveryFormat, WriteFailure, ::testing::Values(".png", ".exr", ".jpg", ".tif"),
                         [](const auto& info) { return std::string(info.param + 1); });

// Files of 1 to 64 MB go through O_DIRECT in whole 4096-byte blocks, then are truncated: every
// size around the threshold and the block reads back byte for byte, also over a longer file.
TEST(ImageIO, LargeFilesReadBackExactlyAtEverySizeAroundTheDirectWrite) {
    const std::string dir = test::output_dir();
    const std::size_t mb = std::size_t(1) << 20;
    std::string data(3 * mb + 4097, '\0');
    for (std::size_t i = 0; i < data.size(); ++i) data[i] = char((i * 131 + (i >> 12)) & 0xff);
    const std::string p = dir + "/large.bin";
    for (std::size_t n : {std::size_t(4095), mb - 1, mb, mb + 1, mb + 4096, 3 * mb + 4097, 2 * mb + 17}) {
        write_file_atomically(p, data.data(), n);
        EXPECT_EQ(file_bytes(p), data.substr(0, n)) << n << " bytes";
    }
    EXPECT_FALSE(has_temporaries(dir));
}

TEST(ImageIO, RefusesToOverwriteAnInputOfTheRun) {
    const std::string p = test::output_dir() + "/input.png";
    write_image(p, ImageF(4, 4, 3, 0.5f));
    const std::string before = file_bytes(p);
    (void)read_image(p);
    EXPECT_TRUE(is_input_of_run(p));
    try {
        write_image(p, ImageF(4, 4, 3, 0.9f));
        ADD_FAILURE() << "overwrote an input";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("input of this run"), std::string::npos) << e.what();
    }
    EXPECT_EQ(file_bytes(p), before);
}

// Issue 47 item 4: a destination that exists and is not a regular file is never replaced by one.
TEST(ImageIO, SpecialFilesAreWrittenThroughOrRefusedNeverReplaced) {
    namespace fs = std::filesystem;
    const std::string dir = test::output_dir();
    const std::string text = "{\"x\": 1}\n";
    // A character device: written through (here /dev/null; it stays a device).
    write_file_atomically("/dev/null", text.data(), text.size());
    EXPECT_TRUE(fs::is_character_file("/dev/null"));
    // A FIFO with no reader: refused at once (never blocks), and it stays a FIFO.
    const std::string fifo = dir + "/pipe";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    try {
        write_file_atomically(fifo, text.data(), text.size());
        ADD_FAILURE() << "wrote into a FIFO with no reader";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("FIFO with no reader"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(fs::is_fifo(fifo));
    // A FIFO with a reader: the bytes go to the reader.
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {  // system calls only (no allocation after fork)
        const int in = ::open(fifo.c_str(), O_RDONLY);  // blocks until the writer opens
        char got[64];
        std::size_t n = 0;
        for (ssize_t r; in >= 0 && n < sizeof got && (r = ::read(in, got + n, sizeof got - n)) > 0;) n += std::size_t(r);
        std::_Exit(n == text.size() && std::memcmp(got, text.data(), n) == 0 ? 0 : 1);
    }
    bool written = false;
    for (int i = 0; i < 500 && !written; ++i) {  // until the child has opened its end (<= 5 s)
        try {
            write_file_atomically(fifo, text.data(), text.size());
            written = true;
        } catch (const Error&) {
            ::usleep(10000);
        }
    }
    EXPECT_TRUE(written);
    int st = 0;
    ::waitpid(child, &st, 0);
    EXPECT_TRUE(WIFEXITED(st) && WEXITSTATUS(st) == 0) << "the reader did not get the bytes";
    EXPECT_TRUE(fs::is_fifo(fifo));
    // A symbolic link: the file it names is replaced, the link stays (also a link to a link).
    write_file_atomically(dir + "/target.json", "old", 3);
    fs::create_symlink("target.json", dir + "/link1");
    fs::create_symlink(dir + "/link1", dir + "/link2");
    write_file_atomically(dir + "/link2", text.data(), text.size());
    EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir + "/link1")));
    EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir + "/link2")));
    EXPECT_EQ(file_bytes(dir + "/target.json"), text);
    // A loop of links is refused.
    fs::create_symlink(dir + "/loop_b", dir + "/loop_a");
    fs::create_symlink(dir + "/loop_a", dir + "/loop_b");
    EXPECT_THROW(write_file_atomically(dir + "/loop_a", text.data(), text.size()), Error);
    EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir + "/loop_a")));
    // A socket: refused.
    const std::string sock = dir + "/sock";
    const int sfd = ::socket(AF_UNIX, SOCK_STREAM, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    std::strncpy(addr.sun_path, sock.c_str(), sizeof addr.sun_path - 1);
    if (sock.size() < sizeof addr.sun_path && ::bind(sfd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0) {
        EXPECT_THROW(write_file_atomically(sock, text.data(), text.size()), Error);
        EXPECT_TRUE(fs::is_socket(sock));
    }
    ::close(sfd);
}

TEST(ImageIO, StaleTemporariesOfDeadProcessesAreRemoved) {
    const std::string dir = test::output_dir();
    // A PID that is not alive: a child that has exited and been reaped.
    const pid_t dead = ::fork();
    if (dead == 0) std::_Exit(0);
    ASSERT_GT(dead, 0);
    int st = 0;
    ::waitpid(dead, &st, 0);
    const std::string stale = dir + "/.aqtmp." + std::to_string(dead) + ".0.frame.png";
    const std::string live = dir + "/.aqtmp." + std::to_string(::getppid()) + ".0.other.png";
    std::ofstream(stale) << "half";
    std::ofstream(live) << "in progress";
    write_image(dir + "/next.png", ImageF(4, 4, 3, 0.5f));
    EXPECT_FALSE(std::filesystem::exists(stale)) << "a dead process's temporary was kept";
    EXPECT_TRUE(std::filesystem::exists(live)) << "a live process's temporary was removed";
    std::filesystem::remove(live);
}

TEST(Compare, IdenticalAndKnownDifference) {
    ImageF a(4, 4, 1, 0.5f), b = a;
    auto s = compare_images(a, b);
    EXPECT_EQ(s.max_abs, 0.0);
    EXPECT_TRUE(std::isinf(s.psnr));
    b.at(1, 2, 0) = 0.75f;
    s = compare_images(a, b);
    EXPECT_NEAR(s.max_abs, 0.25, 1e-7);
    EXPECT_EQ(s.max_x, 1);
    EXPECT_EQ(s.max_y, 2);
    EXPECT_NEAR(s.mean_abs, 0.25 / 16, 1e-7);
    EXPECT_NEAR(s.frac_over, 1.0 / 16, 1e-12);
}

}  // namespace aq
