// tests/stylize/resample_test.cpp — the half-resolution convention: toolkit::resample (tables, used
// by the stages) equals kernels.h sample_resampled value for value; the even-size downsample is
// the 2x2 box average; constants survive up- and down-sampling exactly.
#include <array>
#include <cstring>
#include <limits>
#include <utility>

#include <gtest/gtest.h>

#include "stylize/kernels.h"
#include "stylize/stages/toolkit.h"
#include "tests/synthetic_gbuffer.h"

namespace aq::stylize {
namespace {

TEST(Resample, TablesMatchSampleResampledBitForBit) {
    const ImageF src = test::synthetic_target("color", 4, 37, 23, 5);
    for (auto [w, h] : {std::pair{19, 12}, {74, 46}, {37, 23}, {10, 31}}) {
        const ImageF r = toolkit::resample(src, w, h, Exec::fast(2));
        const auto v = src.view<glm::vec4>();
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const glm::vec4 e = sample_resampled(v, x, y, w, h);
                for (int c = 0; c < 4; ++c) {
                    const float a = r.at(x, y, c);
                    ASSERT_EQ(std::memcmp(&a, &e[c], sizeof a), 0) << w << "x" << h << " at " << x << "," << y;
                }
            }
    }
}

TEST(Resample, EvenDownsampleIsTheBoxAverageAndConstantsSurvive) {
    ImageF src(8, 6, 1);
    for (int y = 0; y < 6; ++y)
        for (int x = 0; x < 8; ++x) src.at(x, y, 0) = float(x * 10 + y);
    const ImageF d = toolkit::resample(src, half_size(8), half_size(6), Exec::reference());
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 4; ++x) {
            const float box = (src.at(2 * x, 2 * y, 0) + src.at(2 * x + 1, 2 * y, 0) + src.at(2 * x, 2 * y + 1, 0) +
                               src.at(2 * x + 1, 2 * y + 1, 0)) / 4.0f;
            EXPECT_FLOAT_EQ(d.at(x, y, 0), box);
        }
    const ImageF k(5, 3, 2, 0.3f);
    const ImageF up = toolkit::resample(k, 9, 6, Exec::reference());
    for (std::size_t i = 0; i < up.num_values(); ++i) EXPECT_EQ(up.data()[i], 0.3f);
}

}  // namespace
}  // namespace aq::stylize

namespace aq::stylize {
namespace {

// The row-block resampler (cached horizontal rows) equals the plain per-row resampling value for
// value, for up- and downsampling, odd sizes, one channel of four, and blocks starting anywhere.
TEST(Resample, RowResamplerEqualsResampleRow) {
    const ImageF src = test::synthetic_target("color", 4, 37, 23, 9);
    for (auto [w, h] : {std::pair{74, 46}, {73, 45}, {19, 12}, {37, 23}, {100, 7}}) {
        const toolkit::ResampleAxis ax(w, src.width()), ay(h, src.height());
        std::vector<float> want(std::size_t(w) * 4), got(std::size_t(w) * 4), want1(static_cast<std::size_t>(w)), got1(static_cast<std::size_t>(w));
        for (int y0 : {0, 1, h / 2, h - 1}) {
            toolkit::RowResampler<4> up(src.data(), src.width(), w, ax, ay);
            toolkit::RowResampler<1, 4> up1(src.data() + 3, src.width(), w, ax, ay);
            for (int y = y0; y < h; ++y) {
                toolkit::resample_row<4>(src.data(), src.width(), want.data(), w, ax, ay, y);
                up.row(y, got.data());
                ASSERT_EQ(std::memcmp(want.data(), got.data(), want.size() * sizeof(float)), 0)
                    << w << "x" << h << " row " << y << " (block from " << y0 << ")";
                toolkit::resample_row<1, 4>(src.data() + 3, src.width(), want1.data(), w, ax, ay, y);
                up1.row(y, got1.data());
                ASSERT_EQ(std::memcmp(want1.data(), got1.data(), want1.size() * sizeof(float)), 0)
                    << w << "x" << h << " alpha row " << y;
            }
        }
    }
}

}  // namespace
}  // namespace aq::stylize

namespace aq::stylize {
namespace {

// At equal sizes every form of the resampling convention is exactly the identity, also where the
// bilinear formula is not: sizes whose (x + 0.5) / n * n rounds away from x + 0.5 in float, -0
// (a + (c - a) * 0 gives +0) and infinities beside finite texels (inf - a gives NaN weights).
TEST(Resample, EqualSizesAreExactlyTheIdentity) {
    // Some n whose float texel coordinate is not x + 0.5 at some x (so the identity is not free).
    int inexact_sizes = 0;
    for (int n : {520, 719, 1080, 1920})
        for (int x = 0; x < n; ++x)
            if (texel_coord(x, n, n) != float(x) + 0.5f) {
                ++inexact_sizes;
                break;
            }
    EXPECT_GT(inexact_sizes, 0) << "no size needs the identity rule: pick others";
    for (auto [w, h] : {std::pair{1080, 3}, {719, 5}, {37, 23}}) {
        ImageF src = test::synthetic_target("color", 4, w, h, 13);
        src.at(1, 1, 0) = -0.0f;
        src.at(2, 2, 1) = std::numeric_limits<float>::infinity();
        src.at(3, 1, 2) = -std::numeric_limits<float>::infinity();
        const auto same_bits = [](float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; };
        const ImageF r = toolkit::resample(src, w, h, Exec::fast(2));
        ASSERT_EQ(std::memcmp(r.data(), src.data(), src.num_values() * sizeof(float)), 0) << w << "x" << h;
        const toolkit::Resampler up(w, h, w, h);
        EXPECT_TRUE(up.identity());
        const auto v = std::as_const(src).view<glm::vec4>();
        for (int c = 0; c < 4; ++c) {
            const toolkit::Plane p = toolkit::plane(src, c);
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    ASSERT_TRUE(same_bits(toolkit::sample_resampled_plane(p, x, y, w, h), src.at(x, y, c)));
                    ASSERT_TRUE(same_bits(up.sample(p, x, y), src.at(x, y, c)));
                    ASSERT_TRUE(same_bits(sample_resampled(v, x, y, w, h)[c], src.at(x, y, c)));
                }
        }
        const toolkit::ResampleAxis ax(w, w), ay(h, h);
        toolkit::RowResampler<1, 4> up1(src.data() + 2, w, w, ax, ay);
        toolkit::RowResampler<4> up4(src.data(), w, w, ax, ay);
        std::vector<float> row(std::size_t(w) * 4);
        for (int y = 0; y < h; ++y) {
            up1.row(y, row.data());
            for (int x = 0; x < w; ++x) ASSERT_TRUE(same_bits(row[std::size_t(x)], src.at(x, y, 2)));
            EXPECT_EQ(up4.row_or_source(y, row.data()), src.data() + std::size_t(y) * w * 4);  // read in place
        }
    }
}

}  // namespace
}  // namespace aq::stylize

namespace aq::stylize {
namespace {

// Halving axes (ResampleAxis::pairs: taps 2x and 2x + 1 addressed without the tables) give the
// tabled per-row resampling's values bit for bit: four channels, one of four, one of one; output
// widths that leave tails of the vector loops; weights that are not 0.5 in float (1920 -> 960);
// -0, infinities and NaN in the source.
TEST(Resample, HalvingRowsEqualTheTabledRows) {
    const toolkit::ResampleAxis wide(960, 1920);
    EXPECT_TRUE(wide.pairs);
    bool inexact = false;
    for (float t : wide.t) inexact = inexact || t != 0.5f;
    EXPECT_TRUE(inexact) << "every weight is 0.5: the per-pixel weight is not exercised";
    EXPECT_FALSE(toolkit::ResampleAxis(19, 37).pairs);  // odd source: the last tap is clamped
    EXPECT_FALSE(toolkit::ResampleAxis(40, 40).pairs);
    EXPECT_FALSE(toolkit::ResampleAxis(80, 40).pairs);
    const auto same = [](const std::vector<float>& a, const std::vector<float>& b) {
        return std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
    };
    for (auto [sw, sh] : {std::pair{1920, 4}, {74, 46}, {34, 10}, {2, 2}}) {
        ImageF src = test::synthetic_target("color", 4, sw, sh, 21);
        ImageF one = test::synthetic_target("depth", 1, sw, sh, 22);
        src.at(1, 1, 0) = -0.0f;
        src.at(0, 1, 0) = -0.0f;  // -0 beside -0: a + (b - a) * t = -0 + (+0) * t = +0
        src.at(2 % sw, 0, 1) = std::numeric_limits<float>::infinity();
        src.at(3 % sw, 1, 2) = std::numeric_limits<float>::quiet_NaN();
        src.at(sw - 1, sh - 1, 3) = -std::numeric_limits<float>::infinity();
        one.at(1, 0, 0) = -0.0f;
        one.at(0, 0, 0) = -0.0f;
        one.at(sw - 2, sh - 1, 0) = std::numeric_limits<float>::infinity();
        const int w = sw / 2, h = sh / 2;
        const toolkit::ResampleAxis ax(w, sw), ay(h, sh);
        ASSERT_TRUE(ax.pairs) << sw;
        toolkit::RowResampler<4> up4(src.data(), sw, w, ax, ay);
        toolkit::RowResampler<1, 4> up2(src.data() + 2, sw, w, ax, ay);
        toolkit::RowResampler<1> up1(one.data(), sw, w, ax, ay);
        std::vector<float> want4(std::size_t(w) * 4), got4(want4.size()), want(static_cast<std::size_t>(w)), got(want.size());
        for (int y = 0; y < h; ++y) {
            toolkit::resample_row<4>(src.data(), sw, want4.data(), w, ax, ay, y);
            up4.row(y, got4.data());
            ASSERT_TRUE(same(want4, got4)) << sw << " rgba row " << y;
            toolkit::resample_row<1, 4>(src.data() + 2, sw, want.data(), w, ax, ay, y);
            up2.row(y, got.data());
            ASSERT_TRUE(same(want, got)) << sw << " channel 2 row " << y;
            toolkit::resample_row<1>(one.data(), sw, want.data(), w, ax, ay, y);
            up1.row(y, got.data());
            ASSERT_TRUE(same(want, got)) << sw << " one channel row " << y;
        }
    }
}

}  // namespace
// Resampler::sample8 (the row kernels' eight-pixel form) gives sample's bits lane by lane: half,
// full and odd source sizes, 1- and 4-channel planes, every start column of a row.
TEST(Resample, Sample8EqualsSample) {
    for (auto [w, h, sw, sh] : {std::array{37, 23, 19, 12}, {37, 23, 37, 23}, {64, 9, 17, 5}, {16, 4, 16, 2}}) {
        for (int C : {1, 4}) {
            ImageF src = test::synthetic_target("color", 4, sw, sh, 7);
            if (C == 1) src = test::synthetic_target("edges", 1, sw, sh, 7);
            src.data()[3] = -0.0f;
            src.data()[src.num_values() / 2] = std::numeric_limits<float>::infinity();
            const toolkit::Resampler up(w, h, sw, sh);
            const toolkit::Plane p = toolkit::plane(src, C - 1);
            for (int y = 0; y < h; ++y)
                for (int x = 0; x + 8 <= w; ++x) {
                    const toolkit::v8f v = up.sample8(p, x, y);
                    for (int l = 0; l < 8; ++l) {
                        const float want = up.sample(p, x + l, y), got = v[l];
                        ASSERT_EQ(std::memcmp(&got, &want, sizeof want), 0) << w << "x" << h << " from " << sw << "x" << sh
                                                                             << ", " << C << " channels, (" << x + l << ", " << y << ")";
                    }
                }
        }
    }
}

}  // namespace aq::stylize
