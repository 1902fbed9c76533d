// tests/stylize/edge_blur_test.cpp — WC17 5x5 blur, WC18 variable-width edge blur and the extended
// edges of gaps & overlaps: constants stay constant, impulses reproduce the normalised kernels
// (computed here independently), painted width widens the kernel, zero edges stay zero.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "core/exec.h"
#include "stylize/stages/edge_blur.h"
#include "stylize/stages/extend_edges.h"

namespace aq::stylize {
namespace {

//! exp(-o^2 / (2 sigma^2)) for |o| <= r, normalised.
std::vector<double> gauss(int r, double sigma) {
    std::vector<double> g(std::size_t(2 * r + 1));
    double s = 0;
    for (int o = -r; o <= r; ++o) s += g[std::size_t(o + r)] = std::exp(-double(o * o) / (2 * sigma * sigma));
    for (double& v : g) v /= s;
    return g;
}

TEST(EdgeBlurWc17, ConstantStaysConstantAtHalfResolution) {
    ImageF c(21, 13, 4, 0.4f), o;
    for (int y = 0; y < 13; ++y)
        for (int x = 0; x < 21; ++x) c.at(x, y, 2) = 0.7f;
    edge_blur_wc17(o, c, EdgeBlurWc17Params{}, Exec::reference());
    EXPECT_EQ(o.width(), 11);
    EXPECT_EQ(o.height(), 7);
    for (int y = 0; y < 7; ++y)
        for (int x = 0; x < 11; ++x) {
            EXPECT_EQ(o.at(x, y, 0), 0.4f);
            EXPECT_EQ(o.at(x, y, 2), 0.7f);
        }
}

TEST(EdgeBlurWc17, ImpulseReproducesThe5x5Gaussian) {
    ImageF c(11, 11, 4, 0.0f), o;
    c.at(5, 5, 1) = 1.0f;
    EdgeBlurWc17Params p;
    p.half_res = false;
    edge_blur_wc17(o, c, p, Exec::reference());
    const auto g = gauss(2, 1.0);
    for (int dy = -3; dy <= 3; ++dy)
        for (int dx = -3; dx <= 3; ++dx) {
            const double expect = (std::abs(dx) <= 2 && std::abs(dy) <= 2) ? g[std::size_t(dx + 2)] * g[std::size_t(dy + 2)] : 0.0;
            EXPECT_NEAR(o.at(5 + dx, 5 + dy, 1), expect, 1e-6) << dx << "," << dy;
        }
}

TEST(EdgeBlurWc18, KernelSizeFollowsMnprAndIsGuarded) {
    EXPECT_EQ(edge_blur_kernel_size(3, 0.0f), 3);
    EXPECT_EQ(edge_blur_kernel_size(3, 1.0f), 12);
    EXPECT_EQ(edge_blur_kernel_size(3, 0.5f), 7);   // int(3 + 4.5)
    EXPECT_EQ(edge_blur_kernel_size(3, -1.0f), 1);  // max(1, 3 - 9)
    EXPECT_EQ(edge_blur_kernel_size(3, std::numeric_limits<float>::quiet_NaN()), 1);
    EXPECT_EQ(edge_blur_kernel_size(3, 1e30f), 12);
}

// The eight-lane K (the fast traversal's) equals the scalar definition for every width, on a sweep
// of the control's range and past it, and on the values that need the guards.
TEST(EdgeBlurWc18, KernelSizeOfEightLanesEqualsTheScalarDefinition) {
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    std::vector<float> c = {0.0f, -0.0f, 1.0f, -1.0f, nan, -nan, inf, -inf, 1e30f, -1e30f, 1e-40f, 0.5f};
    for (int i = -3000; i <= 3000; ++i) c.push_back(float(i) / 2000.0f);          // the range and past it
    for (int k = 1; k <= 64; ++k) c.push_back(std::nextafter(float(k) / 12.0f - 0.25f, 0.0f));  // near steps
    while (c.size() % 8) c.push_back(0.25f);
    for (int width = 1; width <= 16; ++width)
        for (std::size_t i = 0; i < c.size(); i += 8) {
            simd::v8f v;
            std::memcpy(&v, &c[i], sizeof v);
            const simd::v8i k = edge_blur_kernel_size8(width, v);
            for (int l = 0; l < 8; ++l)
                ASSERT_EQ(k[l], edge_blur_kernel_size(width, c[i + std::size_t(l)])) << "width " << width << " ctrl " << c[i + std::size_t(l)];
        }
}

TEST(EdgeBlurWc18, ConstantStaysConstantWhateverTheWidth) {
    ImageF e(23, 17, 1, 0.6f), k(23, 17, 4), o;
    for (std::size_t i = 0; i < k.num_values(); ++i) k.data()[i] = float(int(i % 9) - 4) / 4.0f;
    edge_blur_wc18(o, e, k, EdgeBlurWc18Params{}, Exec::reference());
    for (std::size_t i = 0; i < o.num_values(); ++i) EXPECT_EQ(o.data()[i], 0.6f);
}

TEST(EdgeBlurWc18, ImpulseReproducesTheKernelOfThePaintedWidth) {
    const int n = 31, c = 15;
    for (float ctrl : {0.0f, 1.0f}) {
        ImageF e(n, n, 1, 0.0f), k(n, n, 4, 0.0f), o;
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) k.at(x, y, 1) = ctrl;
        e.at(c, c, 0) = 1.0f;
        edge_blur_wc18(o, e, k, EdgeBlurWc18Params{}, Exec::reference());
        const int K = ctrl == 0.0f ? 3 : 12;  // W = 3: K = W, or 4W at full painted width
        const auto g = gauss(K - 1, K / 2.0);
        for (int dy = -K; dy <= K; ++dy)
            for (int dx = -K; dx <= K; ++dx) {
                const bool in = std::abs(dx) < K && std::abs(dy) < K;
                const double expect = in ? g[std::size_t(dx + K - 1)] * g[std::size_t(dy + K - 1)] : 0.0;
                EXPECT_NEAR(o.at(c + dx, c + dy, 0), expect, 2e-6) << "K " << K << " at " << dx << "," << dy;
            }
    }
}

// The fast traversal computes only the columns whose taps can read a non-zero value and writes
// +0 elsewhere: on sparse edges (blobs at the borders and corners, rows without any edge, -0 and
// NaN among the zeros) it must still give the reference's bits, for every width and border rule.
TEST(EdgeBlurWc18, FastEqualsReferenceOnSparseEdges) {
    const int w = 97, h = 71;
    ImageF e(w, h, 1, 0.0f), k(w, h, 4, 0.0f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)  // painted width: the widest kernel on the left half, varied on the right
            k.at(x, y, 1) = x < w / 2 ? 1.0f : float((x * 7 + y * 13) % 21 - 10) / 10.0f;
    auto blob = [&](int cx, int cy, float v) {
        for (int y = std::max(0, cy - 2); y <= std::min(h - 1, cy + 2); ++y)
            for (int x = std::max(0, cx - 1); x <= std::min(w - 1, cx + 3); ++x) e.at(x, y, 0) = v * float(1 + x % 3);
    };
    blob(0, 0, 0.5f);
    blob(w - 1, h - 1, 0.25f);
    blob(48, 20, 1.0f);
    blob(3, 40, 0.75f);
    blob(w - 2, 44, 0.125f);
    e.at(70, 60, 0) = -0.0f;  // not +0: its row and column are computed
    e.at(20, 66, 0) = std::numeric_limits<float>::quiet_NaN();
    // W = 4 (K up to 16) is the widest whose weights are permuted from two registers, W = 5 gathers.
    for (const int width : {1, 3, 4, 5})
        for (const Border b : {Border::Clamp, Border::Mirror}) {
            EdgeBlurWc18Params p;
            p.width = width;
            p.border = b;
            ImageF ref, fast1, fast2;
            edge_blur_wc18(ref, e, k, p, Exec::reference());
            edge_blur_wc18(fast1, e, k, p, Exec::fast(1));
            edge_blur_wc18(fast2, e, k, p, Exec::fast(2));
            ASSERT_EQ(ref.num_values(), fast1.num_values());
            int zeros = 0;
            for (std::size_t i = 0; i < ref.num_values(); ++i) {
                ASSERT_EQ(std::memcmp(&ref.data()[i], &fast1.data()[i], 4), 0) << "width " << width << " value " << i;
                ASSERT_EQ(std::memcmp(&ref.data()[i], &fast2.data()[i], 4), 0) << "width " << width << " value " << i;
                zeros += ref.data()[i] == 0.0f;
            }
            EXPECT_GT(zeros, int(ref.num_values() / 3));     // the zero spans are exercised
            EXPECT_LT(zeros, int(ref.num_values()) - 100);   // and so are the computed ones
        }
}

// Each row's non-zero span is found eight values at a time from both ends: one lone edge per row,
// at every column (so at every position within a group of eight, near both ends), gives the
// reference's bits.
TEST(EdgeBlurWc18, FastEqualsReferenceForALoneEdgeAtEveryColumn) {
    const int w = 61, h = 2 * 61;
    ImageF e(w, h, 1, 0.0f), k(w, h, 4, 0.0f);
    for (int y = 0; y < h; ++y) e.at(y % w, y, 0) = 0.5f + 0.25f * float(y / w);
    for (const int width : {1, 3}) {
        EdgeBlurWc18Params p;
        p.width = width;
        ImageF ref, fast;
        edge_blur_wc18(ref, e, k, p, Exec::reference());
        edge_blur_wc18(fast, e, k, p, Exec::fast(2));
        ASSERT_EQ(0, std::memcmp(ref.data(), fast.data(), ref.num_values() * sizeof(float))) << "width " << width;
    }
}

TEST(ExtendEdges, ZeroStaysZeroAndOneStaysOne) {
    ImageF z(13, 9, 1, 0.0f), one(13, 9, 1, 1.0f), o;
    extend_edges(o, z, ExtendEdgesParams{}, Exec::reference());
    for (std::size_t i = 0; i < o.num_values(); ++i) EXPECT_EQ(o.data()[i], 0.0f);
    extend_edges(o, one, ExtendEdgesParams{}, Exec::reference());
    for (std::size_t i = 0; i < o.num_values(); ++i) EXPECT_EQ(o.data()[i], 1.0f);
}

// The fast gamma takes the power of a whole 256-value chunk where at least a quarter of it is
// positive, and of the packed positive values elsewhere: both must give the reference's bits, and
// non-positive values (-0, negative, NaN) must give +0 in both.
TEST(ExtendEdges, FastEqualsReferenceForSparseAndDenseEdges) {
    const int w = 300, h = 40;
    ImageF e(w, h, 1, 0.0f);
    std::uint32_t s = 12345u;
    auto rnd = [&] { return float((s = s * 1664525u + 1013904223u) >> 8) / float(1u << 24); };
    for (int y = 0; y < h; ++y) {
        // Rows 0-9: one value in 40 positive; 10-19: one in 6; 20-29: half; 30-39: all.
        const int every = y < 10 ? 40 : y < 20 ? 6 : y < 30 ? 2 : 1;
        for (int x = 0; x < w; ++x) {
            float v = x % every == 0 ? 0.05f + rnd() : -rnd();
            if (x % 37 == 5) v = -0.0f;
            if (x % 53 == 7) v = std::numeric_limits<float>::quiet_NaN();
            e.at(x, y, 0) = v;
        }
    }
    for (int W : {1, 3}) {  // W = 1: the blur is the identity, so the gamma sees the values above
        ExtendEdgesParams p;
        p.width = W;
        ImageF ref, f1, f2;
        extend_edges(ref, e, p, Exec::reference());
        extend_edges(f1, e, p, Exec::fast(1));
        extend_edges(f2, e, p, Exec::fast(2));
        ASSERT_EQ(0, std::memcmp(ref.data(), f1.data(), ref.num_values() * sizeof(float))) << "W " << W;
        ASSERT_EQ(0, std::memcmp(ref.data(), f2.data(), ref.num_values() * sizeof(float))) << "W " << W;
    }
}

TEST(ExtendEdges, ImpulseGivesTheLinearKernelThenMnprGamma) {
    const int n = 15, c = 7;
    for (int W : {3, 5}) {
        ImageF e(n, n, 1, 0.0f), o;
        e.at(c, c, 0) = 1.0f;
        ExtendEdgesParams p;
        p.width = W;
        extend_edges(o, e, p, Exec::reference());
        std::vector<double> lin(std::size_t(2 * W - 1));
        double s = 0;
        for (int l = -(W - 1); l <= W - 1; ++l) s += lin[std::size_t(l + W - 1)] = 1.0 - double(std::abs(l)) / W;
        for (int dy = -W; dy <= W; ++dy)
            for (int dx = -W; dx <= W; ++dx) {
                double b = 0;
                if (std::abs(dx) < W && std::abs(dy) < W) b = lin[std::size_t(dx + W - 1)] / s * lin[std::size_t(dy + W - 1)] / s;
                const double expect = b > 0 ? std::pow(std::pow(b, 1.0 / b), 2.0 / W) : 0.0;
                EXPECT_NEAR(o.at(c + dx, c + dy, 0), expect, 2e-5) << "W " << W << " at " << dx << "," << dy;
            }
    }
}

}  // namespace
}  // namespace aq::stylize
