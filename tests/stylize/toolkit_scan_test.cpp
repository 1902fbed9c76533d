// tests/stylize/toolkit_scan_test.cpp — the toolkit's whole-image checks (toolkit.h any_index,
// nonzero_channels, any_beyond, any_above), which stages use to choose a schedule (skip empty layers):
// each answer equals a plain scalar scan, for every channel count, for a single telling value at
// every kind of position (first, inside a vector, the unvectorised tail, a parallel block's edge),
// on the reference traversal and on 1, 2 and 8 threads.
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

#include <gtest/gtest.h>

#include "stylize/stages/toolkit.h"

namespace aq::stylize {
namespace {

std::vector<Exec> traversals() { return {Exec::reference(), Exec::fast(1), Exec::fast(2), Exec::fast(8)}; }

TEST(ToolkitScan, NonzeroChannelsEqualsThePlainScan) {
    for (int C : {1, 2, 3, 4}) {
        for (auto [w, h] : {std::pair{301, 217}, {8, 1}, {7, 3}}) {
            const std::size_t nv = std::size_t(w) * h * C;
            for (std::size_t pos : {std::size_t(0), std::size_t(5), nv / 2, std::size_t(1) << 15, nv - 1}) {
                if (pos >= nv) continue;
                for (float v : {1.0f, -2.5e-38f, std::numeric_limits<float>::quiet_NaN(), -0.0f}) {
                    ImageF img(w, h, C, 0.0f);
                    img.data()[pos] = v;
                    std::uint32_t want = 0;
                    for (std::size_t j = 0; j < nv; ++j) want |= std::uint32_t(img.data()[j] != 0.0f) << (j % std::size_t(C));
                    EXPECT_EQ(want, v == 0.0f ? 0u : 1u << (pos % std::size_t(C)));  // -0 is 0; NaN is not
                    for (const Exec& ex : traversals())
                        EXPECT_EQ(toolkit::nonzero_channels(ex, img), want) << C << " channels, " << w << "x" << h
                                                                            << ", value " << v << " at " << pos;
                }
            }
        }
    }
    // The serial form on a row: the same answer as the plain scan of that row.
    ImageF row(37, 1, 4, 0.0f);
    row.at(36, 0, 2) = 1.0f;
    row.at(3, 0, 0) = std::numeric_limits<float>::quiet_NaN();
    EXPECT_EQ(toolkit::nonzero_channels_of(row.data(), row.num_values(), 4), 0x5u);
    ImageF full(40, 30, 4, 0.5f);
    for (const Exec& ex : traversals()) EXPECT_EQ(toolkit::nonzero_channels(ex, full), 0xfu);
}

TEST(ToolkitScan, AnyBeyondFindsEveryValueOutsideTheBound) {
    const std::size_t n = 100003;  // not a multiple of 8 or of the chunk
    const float inf = std::numeric_limits<float>::infinity(), fmax = std::numeric_limits<float>::max();  // fmax: finite
    for (std::size_t pos : {std::size_t(0), std::size_t(9), std::size_t(1024), n / 2, n - 3, n - 1}) {
        for (auto [v, bound] : {std::pair{inf, fmax}, {-inf, fmax}, {std::numeric_limits<float>::quiet_NaN(), fmax},
                                {1.5e30f, 1e30f}, {-1.5e30f, 1e30f}, {std::nextafter(1.0f, 2.0f), 1.0f}}) {
            std::vector<float> d(n, -bound);  // within the bound, at its edge
            d[pos] = v;
            for (const Exec& ex : traversals()) {
                EXPECT_TRUE(toolkit::any_beyond(ex, d.data(), n, bound)) << v << " at " << pos << ", bound " << bound;
                EXPECT_FALSE(toolkit::any_beyond(ex, d.data(), pos, bound)) << "before " << pos;
            }
            EXPECT_FALSE(toolkit::all_within(d.data(), n, bound));
            EXPECT_EQ(toolkit::all_within(d.data() + pos + 1, n - pos - 1, bound), true);
        }
    }
    for (const Exec& ex : traversals()) EXPECT_FALSE(toolkit::any_beyond(ex, nullptr, 0, 1.0f));
}

// any_above (the row kernels' skip tests): the plain scan's answer for one value just above the
// bound at every kind of position (inside a vector, the scalar tail), values at the bound and NaN
// not counting.
TEST(ToolkitScan, AnyAboveEqualsThePlainScan) {
    for (std::size_t n : {std::size_t(0), std::size_t(1), std::size_t(7), std::size_t(8), std::size_t(64), std::size_t(67)})
        for (float bound : {0.0f, 0.1f})
            for (std::size_t pos = 0; pos <= n; ++pos) {  // pos == n: no value above
                std::vector<float> d(n, bound);
                for (std::size_t j = 0; j < n; j += 3) d[j] = std::numeric_limits<float>::quiet_NaN();
                if (pos < n) d[pos] = std::nextafter(bound, 1.0f);
                bool want = false;
                for (float v : d) want |= v > bound;
                EXPECT_EQ(toolkit::any_above(d.data(), n, bound), want) << n << " values, bound " << bound << ", at " << pos;
                EXPECT_EQ(want, pos < n);
            }
}

// all_equal (edge_detect's flat test): the plain scan's answer with one differing value at every
// position (inside a 64-value block, the scalar tail); -0 equals +0, NaN equals nothing.
TEST(ToolkitScan, AllEqualEqualsThePlainScan) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (std::size_t n : {std::size_t(0), std::size_t(1), std::size_t(8), std::size_t(64), std::size_t(66), std::size_t(131)})
        for (float v : {0.25f, 0.0f, -0.0f, nan})
            for (std::size_t pos = 0; pos <= n; ++pos) {  // pos == n: none differs
                std::vector<float> d(n, v == 0.0f ? -v : v);  // +0 <-> -0 where v is zero
                if (pos < n) d[pos] = std::nextafter(0.25f, 1.0f);
                bool want = true;
                for (float x : d) want &= x == v;
                EXPECT_EQ(toolkit::all_equal(d.data(), n, v), want) << n << " values of " << v << ", at " << pos;
                EXPECT_EQ(want, (pos == n || n == 0) && !(v != v && n > 0));
            }
}

// any_negative_zero (bleed_blend's quiet-row test): -0 found at every position, +0, NaN and the
// smallest negative value not counted.
TEST(ToolkitScan, AnyNegativeZeroFindsOnlyMinusZero) {
    for (std::size_t n : {std::size_t(0), std::size_t(1), std::size_t(8), std::size_t(13), std::size_t(64)})
        for (std::size_t pos = 0; pos <= n; ++pos) {  // pos == n: no -0
            std::vector<float> d(n, 0.0f);
            for (std::size_t j = 1; j < n; j += 3) d[j] = j % 2 ? std::numeric_limits<float>::quiet_NaN() : -std::numeric_limits<float>::denorm_min();
            if (pos < n) d[pos] = -0.0f;
            EXPECT_EQ(toolkit::any_negative_zero(d.data(), n), pos < n) << n << " values, at " << pos;
        }
}

// store_rgba8 writes pixel i as (r[i], g[i], b[i], a[i]), every bit moved (NaN payloads, -0).
TEST(ToolkitStore, Rgba8InterleavesEightPixelsBitForBit) {
    float planes[4][8], out[32];
    for (int c = 0; c < 4; ++c)
        for (int i = 0; i < 8; ++i) planes[c][i] = float(c * 10 + i) + 0.25f;
    planes[1][3] = -0.0f;
    const std::uint32_t nan_bits = 0x7fc01234u;
    std::memcpy(&planes[2][6], &nan_bits, sizeof nan_bits);
    toolkit::store_rgba8(out, planes[0], planes[1], planes[2], planes[3]);
    for (int i = 0; i < 8; ++i)
        for (int c = 0; c < 4; ++c) EXPECT_EQ(std::memcmp(&out[4 * i + c], &planes[c][i], sizeof(float)), 0) << i << "," << c;
}

TEST(ToolkitScan, AnyIndexAnswersLikeTheLoop) {
    const std::size_t n = 250000;
    for (std::size_t hit : {std::size_t(0), std::size_t(65536), n - 1, n}) {  // n: no hit
        for (const Exec& ex : traversals())
            EXPECT_EQ(toolkit::any_index(ex, n, [&](std::size_t i) { return i == hit; }), hit < n) << hit;
    }
}

// plane8 moves eight values of a plane into a register: for every channel layout a plane can
// have (a constant, one channel, channel c of 2, 3 or 4 interleaved) and every
// column up to the row's end (the last pixel's last channel is the image's last value), it
// equals the plane's values one by one, bit for bit (a NaN payload and -0 included).
TEST(ToolkitPlane8, EqualsThePlanesValuesOneByOne) {
    using namespace toolkit;
    const int w = 19, h = 3;
    for (int C : {1, 2, 3, 4})
        for (int c = 0; c < C; ++c) {
            ImageF img(w, h, C);
            for (std::size_t i = 0; i < img.num_values(); ++i) img.data()[i] = float(i) * 0.5f - 3.0f;
            img.data()[c] = -0.0f;
            img.data()[img.num_values() - 1] = std::bit_cast<float>(0x7fc01234u);
            const Plane p = plane(img, c);
            for (int y = 0; y < h; ++y)
                for (int x = 0; x + 8 <= w; ++x) {
                    const v8f v = plane8(p, x, y);
                    for (int l = 0; l < 8; ++l)
                        ASSERT_EQ(std::bit_cast<std::uint32_t>(v[l]), std::bit_cast<std::uint32_t>(p(x + l, y)))
                            << C << " channels, channel " << c << " at (" << x + l << ", " << y << ")";
                }
        }
    const float k = 0.75f;
    const v8f v = plane8(constant_plane(&k, w, h), 3, 2);
    for (int l = 0; l < 8; ++l) EXPECT_EQ(v[l], k);
}

}  // namespace
}  // namespace aq::stylize
