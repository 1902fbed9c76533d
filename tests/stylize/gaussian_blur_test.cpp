// tests/stylize/gaussian_blur_test.cpp — the LD06 depth-map blur (stylize/stages/gaussian_blur.h):
// the blurred map of a constant depth is that constant (issue 11), an impulse reproduces the
// normalised separable Gaussian computed here independently, and only one channel is accepted.
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "stylize/stages/gaussian_blur.h"

namespace aq::stylize {
namespace {

TEST(GaussianBlur, ConstantDepthStaysExactlyConstant) {
    for (float depth : {0.0f, 0.37f, 1.0f})
        for (Exec ex : {Exec::reference(), Exec::fast(2)}) {
            const ImageF d(61, 47, 1, depth);
            ImageF o;
            gaussian_blur(o, d, GaussianBlurParams{}, ex);
            ASSERT_EQ(o.width(), 61);
            ASSERT_EQ(o.height(), 47);
            for (int y = 0; y < 47; ++y)
                for (int x = 0; x < 61; ++x) ASSERT_EQ(o.at(x, y, 0), depth) << x << "," << y;
        }
}

TEST(GaussianBlur, ImpulseReproducesTheSeparableGaussian) {
    GaussianBlurParams p;
    p.radius = 3;
    p.sigma = 1.5f;
    ImageF d(15, 15, 1, 0.0f), o;
    d.at(7, 7, 0) = 1.0f;
    gaussian_blur(o, d, p, Exec::reference());
    std::vector<double> g(7);
    double s = 0;
    for (int k = -3; k <= 3; ++k) s += g[std::size_t(k + 3)] = std::exp(-double(k * k) / (2.0 * 1.5 * 1.5));
    for (int y = 0; y < 15; ++y)
        for (int x = 0; x < 15; ++x) {
            const int dx = x - 7, dy = y - 7;
            const double want = std::abs(dx) <= 3 && std::abs(dy) <= 3 ? g[std::size_t(dx + 3)] * g[std::size_t(dy + 3)] / (s * s) : 0.0;
            EXPECT_NEAR(o.at(x, y, 0), want, 1e-6) << x << "," << y;
        }
}

// downsample k: the output is ceil(size / k); each coarse pixel starts as the mean of its block (the
// blocks at the right and bottom edges are partial), then the Gaussian runs on the coarse map.
TEST(GaussianBlur, DownsampleBlurstheBlockMeans) {
    ImageF d(10, 7, 1, 0.0f);
    for (int y = 0; y < 7; ++y)
        for (int x = 0; x < 10; ++x) d.at(x, y, 0) = float(x + 10 * y);
    GaussianBlurParams p;
    p.downsample = 4;
    p.radius = 1;
    p.sigma = 0.1f;  // weights exp(-50) beside the centre: the block means themselves, to 1e-6
    for (Exec ex : {Exec::reference(), Exec::fast(2)}) {
        ImageF o;
        gaussian_blur(o, d, p, ex);
        ASSERT_EQ(o.width(), 3);
        ASSERT_EQ(o.height(), 2);
        for (int by = 0; by < 2; ++by)
            for (int bx = 0; bx < 3; ++bx) {
                double sum = 0;
                int n = 0;
                for (int y = 4 * by; y < std::min(7, 4 * by + 4); ++y)
                    for (int x = 4 * bx; x < std::min(10, 4 * bx + 4); ++x) sum += d.at(x, y, 0), ++n;
                EXPECT_NEAR(o.at(bx, by, 0), sum / n, 1e-4) << bx << "," << by;
            }
    }
    // A constant stays exactly constant at any k.
    p.radius = 4, p.sigma = 2.0f, p.downsample = 3;
    ImageF c(23, 11, 1, 0.37f), o;
    gaussian_blur(o, c, p, Exec::fast(2));
    for (int y = 0; y < o.height(); ++y)
        for (int x = 0; x < o.width(); ++x) ASSERT_EQ(o.at(x, y, 0), 0.37f);
}

TEST(GaussianBlur, OnlyOneChannelIsAccepted) {
    ImageF o;
    EXPECT_THROW(gaussian_blur(o, ImageF(8, 8, 3, 0.5f), GaussianBlurParams{}), Error);
}

}  // namespace
}  // namespace aq::stylize

#include <cstring>
#include <limits>

#include "stylize/stages/blur.h"

namespace aq::stylize {
namespace {

// The fast passes write rows whose every tap row is zero (±0) as +0 without their taps: bands of
// zero rows, rows of −0, zero rows beside a NaN and beside a tiny value, for 1 and 3 channels, both
// borders, radius 0 and 6: the plain loop's bytes at 1, 2 and 8 threads.
TEST(SeparableBlur, ZeroRowsSkippedByTheFastPassesKeepTheBytes) {
    for (int C : {1, 3}) {
        const int W = 33, H = 41;
        ImageF img(W, H, C, 0.0f);
        for (int y = 12; y < 20; ++y)
            for (int x = 3; x < 29; ++x)
                for (int c = 0; c < C; ++c) img.at(x, y, c) = float((x * 7 + y + c) % 5) / 4.0f;
        for (int x = 0; x < W; ++x) img.at(x, 2, 0) = -0.0f;  // a row of -0
        img.at(5, 30, 0) = std::numeric_limits<float>::quiet_NaN();
        img.at(9, 37, C - 1) = 1e-30f;
        for (int radius : {0, 6})
            for (Border b : {Border::Clamp, Border::Mirror}) {
                const std::vector<float> w = gaussian_weights(radius, 2.5f);
                ImageF ref;
                separable_blur(ref, img, w, b, Exec::reference());
                for (int threads : {1, 2, 8}) {
                    ImageF fast;
                    separable_blur(fast, img, w, b, Exec::fast(threads));
                    ASSERT_EQ(0, std::memcmp(ref.data(), fast.data(), ref.num_values() * sizeof(float)))
                        << C << " channels, radius " << radius << ", border " << int(b) << ", " << threads << " threads";
                }
                EXPECT_EQ(ref.at(0, 0, 0), 0.0f);  // far from everything: zero
                EXPECT_TRUE(std::isnan(ref.at(5, 30, 0)));
            }
    }
}

// The same within rows: 64-pixel column chunks whose every tap is zero are written as +0. Single
// values exactly at the reach of a chunk (its first pixel's leftmost tap, its last pixel's
// rightmost tap), one value whose rows reach a chunk vertically, -0, NaN and a tiny value in other
// chunks, 1 and 3 channels, both borders: the plain loop's bytes (fails when a reach is one short).
TEST(SeparableBlur, ZeroColumnChunksSkippedByTheFastPassesKeepTheBytes) {
    for (int C : {1, 3}) {
        const int W = 300, H = 40, r = 6;
        ImageF img(W, H, C, 0.0f);
        for (int y = 0; y < H; ++y) {
            img.at(64 - r, y, 0) = 0.5f;           // chunk 1's first tap (x 64, a = -r)
            img.at(191 + r, y, C - 1) = 0.25f;     // chunk 2's last tap (x 191, a = r)
            img.at(280 + y % 3, y, 0) = -0.0f;     // -0 in chunk 4
        }
        img.at(270, 20, 0) = 1.0f;                 // rows 20 - r .. 20 + r of chunk 4
        img.at(10, 5, 0) = std::numeric_limits<float>::quiet_NaN();
        img.at(230, 33, 0) = 1e-30f;
        for (Border b : {Border::Clamp, Border::Mirror}) {
            const std::vector<float> w = gaussian_weights(r, 2.5f);
            ImageF ref, fast;
            separable_blur(ref, img, w, b, Exec::reference());
            separable_blur(fast, img, w, b, Exec::fast(2));
            ASSERT_EQ(0, std::memcmp(ref.data(), fast.data(), ref.num_values() * sizeof(float)))
                << C << " channels, border " << int(b);
            EXPECT_GT(ref.at(64, 3, 0), 0.0f);     // the reaches do reach
            EXPECT_GT(ref.at(191, 3, C - 1), 0.0f);
            EXPECT_GT(ref.at(270, 20 + r, 0), 0.0f);
        }
    }
}

}  // namespace
}  // namespace aq::stylize
