// tests/stylize/gaussian_blur_test.cpp — the LD06 depth-map blur (stylize/stages/gaussian_blur.h):
// the blurred map of a constant depth is that constant (issue 11), an impulse reproduces the
// normalised separable Gaussian computed here independently, and only one channel is accepted.
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

TEST(GaussianBlur, OnlyOneChannelIsAccepted) {
    ImageF o;
    EXPECT_THROW(gaussian_blur(o, ImageF(8, 8, 3, 0.5f), GaussianBlurParams{}), Error);
}

}  // namespace
}  // namespace aq::stylize
