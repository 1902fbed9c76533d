// linear_to_srgb8 (core/color.h) against linear_to_srgb, bit for bit: every float of the power
// branch (an exhaustive check of the rounding argument of core/color.cpp on this machine's glibc)
// and the values around and outside it, in every lane position.
#include "core/color.h"

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

namespace aq {
namespace {

std::uint32_t bits(float v) { return std::bit_cast<std::uint32_t>(v); }

// Every float from the curve's threshold to 1 inclusive (70,439,397 values), 24 per step: through
// the three-register form and through three calls of the one-register form.
TEST(LinearToSrgb8, EqualsLinearToSrgbOnEveryFloatOfThePowerBranch) {
    const std::uint32_t first = bits(kSrgbLinearThreshold), last = bits(1.0f);
    std::uint64_t mismatches = 0, checked = 0;
    std::uint32_t first_bad = 0;
    for (std::uint32_t u = first; u <= last; u += 24) {
        simd::v8f v[3];
        for (int k = 0; k < 3; ++k)
            for (int i = 0; i < 8; ++i) v[k][i] = std::bit_cast<float>(std::min(u + std::uint32_t(8 * k + i), last));
        simd::v8f t[3] = {v[0], v[1], v[2]};
        linear_to_srgb8(t[0], t[1], t[2]);
        for (int k = 0; k < 3; ++k) {
            const simd::v8f e = linear_to_srgb8(v[k]);
            for (int i = 0; i < 8; ++i) {
                ++checked;
                const std::uint32_t want = bits(linear_to_srgb(v[k][i]));
                if (bits(e[i]) != want || bits(t[k][i]) != want) {
                    if (mismatches++ == 0) first_bad = bits(v[k][i]);
                }
            }
        }
    }
    EXPECT_GE(checked, 70439397u);
    EXPECT_EQ(mismatches, 0u) << "first at the float with bits 0x" << std::hex << first_bad;
}

TEST(LinearToSrgb8, EqualsLinearToSrgbAroundAndOutsideTheDomain) {
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    std::vector<float> values = {0.0f, -0.0f, 1e-45f, 1e-38f, -1e-38f, -0.5f, -1.0f, -inf, inf, nan, -nan,
                                 std::bit_cast<float>(0x7fc12345u), std::bit_cast<float>(0xffa00001u),
                                 1.0f, std::nextafter(1.0f, 2.0f), 1.5f, 2.0f, 1e30f,
                                 std::numeric_limits<float>::max(), kSrgbLinearThreshold,
                                 std::nextafter(kSrgbLinearThreshold, 0.0f), std::nextafter(kSrgbLinearThreshold, 1.0f),
                                 0.001f, 0.18f, 0.5f, 0.999f};
    // Each value in each lane, beside power-branch neighbours (lanes must not affect each other).
    for (std::size_t k = 0; k < values.size(); ++k)
        for (int lane = 0; lane < 8; ++lane) {
            simd::v8f v;
            for (int i = 0; i < 8; ++i) v[i] = 0.05f + 0.1f * float(i);
            v[lane] = values[k];
            const simd::v8f e = linear_to_srgb8(v);
            simd::v8f a = v, b = v * 0.5f, c = v;  // the three-register form, the value in a and c
            linear_to_srgb8(a, b, c);
            for (int i = 0; i < 8; ++i) {
                const std::uint32_t want = bits(linear_to_srgb(v[i]));
                EXPECT_EQ(bits(e[i]), want) << "value 0x" << std::hex << bits(v[i]) << " in lane " << std::dec << i;
                EXPECT_EQ(bits(a[i]), want) << "three-register form, lane " << i;
                EXPECT_EQ(bits(c[i]), want) << "three-register form, lane " << i;
                EXPECT_EQ(bits(b[i]), bits(linear_to_srgb(v[i] * 0.5f))) << "three-register form, lane " << i;
            }
        }
}

}  // namespace
}  // namespace aq
