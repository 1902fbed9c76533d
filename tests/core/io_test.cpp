// tests/core/io_test.cpp — round trips through OpenImageIO and atomic replacement.
#include "core/io.h"

#include <filesystem>

#include <gtest/gtest.h>

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
