// core/sine.h: the eight-lane form equals the scalar definition bit for bit, the definition is
// within one ulp of the true sine, and on the platform of the golden hashes (x86-64 glibc 2.36
// with FMA) it equals what std::sin returned there, which the hand tremor used before.
#include <gnu/libc-version.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "core/sine.h"

namespace {

std::uint32_t bits(float f) { return std::bit_cast<std::uint32_t>(f); }

// The hardest inputs to round: the 134 whose double result, before the final rounding to float,
// lies within 16 double ulps of a midpoint between two floats (two exactly on one), found by an
// exhaustive search of all 2^32 inputs (docs/determinism.md "The tremor's sine"). Any change of
// the double arithmetic by a few ulps (an FMA split in two, another evaluation order) flips some.
constexpr std::uint32_t kHardToRound[] = {
    0x39e8976c, 0x3a5352ca, 0x3c1a4e86, 0x3c295076, 0x3e5e2fd3, 0x3f12f6a5, 0x3f20b232, 0x3f86ac3d,
    0x40490fdb, 0x40a22fcd, 0x40ec1c92, 0x41e231d6, 0x427ce759, 0x4368d704, 0x4395f186, 0x43ef68c6,
    0x44006446, 0x44543a04, 0x44abe3b2, 0x45d21d68, 0x46ad98f3, 0x47498131, 0x4839e9bf, 0x4a9f5684,
    0x4bc04e7f, 0x4c15cf16, 0x4c219bbe, 0x4f63a05b, 0x4fefbbc4, 0x511f3675, 0x518a3b20, 0x548d73eb,
    0x5544eb77, 0x560649ce, 0x56ec64a5, 0x599ed489, 0x5ad58e1c, 0x5cfcef3b, 0x5d0fd0ed, 0x5d26612f,
    0x5d64059e, 0x5e8e0bb2, 0x5ffc6c29, 0x6130d130, 0x63c80358, 0x643a6d38, 0x6572d9f0, 0x6797c5ba,
    0x67ccbc71, 0x6a2417a3, 0x6ab577ee, 0x6eb43b13, 0x7036c415, 0x70cb2662, 0x724397ae, 0x72b9634d,
    0x76a5bfc6, 0x77d2788f, 0x785e5a15, 0x797b40c6, 0x7adc1bf7, 0x7ba5b83e, 0x7bfbee41, 0x7c0ce612,
    0x7c4b4264, 0x7ce72378, 0x7f29bcab, 0xb9e8976c, 0xba5352ca, 0xbc1a4e86, 0xbc295076, 0xbe5e2fd3,
    0xbf12f6a5, 0xbf20b232, 0xbf86ac3d, 0xc0490fdb, 0xc0a22fcd, 0xc0ec1c92, 0xc1e231d6, 0xc27ce759,
    0xc368d704, 0xc395f186, 0xc3ef68c6, 0xc4006446, 0xc4543a04, 0xc4abe3b2, 0xc5d21d68, 0xc6ad98f3,
    0xc7498131, 0xc839e9bf, 0xca9f5684, 0xcbc04e7f, 0xcc15cf16, 0xcc219bbe, 0xcf63a05b, 0xcfefbbc4,
    0xd11f3675, 0xd18a3b20, 0xd48d73eb, 0xd544eb77, 0xd60649ce, 0xd6ec64a5, 0xd99ed489, 0xdad58e1c,
    0xdcfcef3b, 0xdd0fd0ed, 0xdd26612f, 0xdd64059e, 0xde8e0bb2, 0xdffc6c29, 0xe130d130, 0xe3c80358,
    0xe43a6d38, 0xe572d9f0, 0xe797c5ba, 0xe7ccbc71, 0xea2417a3, 0xeab577ee, 0xeeb43b13, 0xf036c415,
    0xf0cb2662, 0xf24397ae, 0xf2b9634d, 0xf6a5bfc6, 0xf7d2788f, 0xf85e5a15, 0xf97b40c6, 0xfadc1bf7,
    0xfba5b83e, 0xfbfbee41, 0xfc0ce612, 0xfc4b4264, 0xfce72378, 0xff29bcab
};
// The hardest inputs to reduce: the 12 (53 < |y| < 117, near multiples of pi/2) whose
// results change when the reduction y - n pi/2 is rounded twice instead of fused (the same 12
// where glibc's own non-FMA variant differs from its FMA one), found by the same search.
constexpr std::uint32_t kHardToReduce[] = {
    0x4255b0a9, 0x42a35c07, 0x42a35d44, 0x42a97360, 0x42cf5854, 0x42e87a55,
    0xc255b0a9, 0xc2a35c07, 0xc2a35d44, 0xc2a97360, 0xc2cf5854, 0xc2e87a55,
};

// About a million inputs: every 4099th bit pattern (both signs, every exponent, NaN and infinity
// included), +-64 patterns around each branch threshold of the algorithm (top 12 bits of |y|:
// 0x398 tiny, 0x3f4 the old small-argument branch, 0x42f large reduction, 0x7f8 non-finite), and
// the hardest inputs to round and to reduce.
std::vector<float> sweep() {
    std::vector<float> v;
    for (std::uint32_t b : kHardToRound) v.push_back(std::bit_cast<float>(b));
    for (std::uint32_t b : kHardToReduce) v.push_back(std::bit_cast<float>(b));
    for (std::uint64_t b = 0; b < (std::uint64_t(1) << 32); b += 4099) v.push_back(std::bit_cast<float>(std::uint32_t(b)));
    for (std::uint32_t top : {0x398u, 0x3f4u, 0x42fu, 0x7f8u})
        for (std::uint32_t sign : {0u, 0x80000000u})
            for (int d = -64; d <= 64; ++d) v.push_back(std::bit_cast<float>(sign | std::uint32_t(std::int64_t(top << 20) + d)));
    while (v.size() % 8) v.push_back(0.0f);
    return v;
}

TEST(Sine, EightAtATimeEqualsTheDefinition) {
    const std::vector<float> in = sweep();
    std::vector<float> out(in.size());
    for (std::size_t i = 0; i < in.size(); i += 8) aq::sine8(&in[i], &out[i]);
    std::size_t bad = 0;
    for (std::size_t i = 0; i < in.size(); ++i)
        if (bits(out[i]) != bits(aq::sine(in[i])) && bad++ < 5)
            ADD_FAILURE() << std::hexfloat << "sine8(" << in[i] << ") = " << out[i] << ", sine = " << aq::sine(in[i]);
    EXPECT_EQ(bad, 0u) << "of " << in.size();
    // In place (in == out) is allowed.
    float a[8] = {0.5f, -3.0f, 1e3f, -7e20f, 1e-9f, 100.0f, 119.99f, 120.0f}, b[8];
    aq::sine8(a, b);
    aq::sine8(a, a);
    EXPECT_EQ(std::memcmp(a, b, sizeof a), 0);
}

TEST(Sine, WithinOneUlpOfTheTrueSine) {
    std::size_t checked = 0;
    for (float y : sweep()) {
        const float s = aq::sine(y);
        if (!std::isfinite(y)) {
            EXPECT_TRUE(std::isnan(s)) << y;
            continue;
        }
        const double exact = std::sin(double(y));  // glibc's double sine: correctly rounded here
        const float lo = std::nextafter(float(exact), -2.0f), hi = std::nextafter(float(exact), 2.0f);
        ASSERT_TRUE(s >= lo && s <= hi) << std::hexfloat << "sine(" << y << ") = " << s << ", sin = " << exact;
        ++checked;
    }
    EXPECT_GT(checked, 1000000u);
}

TEST(Sine, ValuesWithAKnownAnswer) {
    EXPECT_EQ(bits(aq::sine(0.0f)), bits(0.0f));
    EXPECT_EQ(bits(aq::sine(-0.0f)), bits(-0.0f));
    const float denormal = std::numeric_limits<float>::denorm_min() * 3;
    EXPECT_EQ(aq::sine(denormal), denormal);
    EXPECT_EQ(aq::sine(0x1p-13f), 0x1p-13f);  // below 2^-12 sin y rounds to y
    EXPECT_EQ(aq::sine(float(M_PI / 2)), 1.0f);
    EXPECT_EQ(aq::sine(-float(M_PI / 2)), -1.0f);
    EXPECT_EQ(aq::sine(float(M_PI / 6)), 0.5f);
    EXPECT_NEAR(aq::sine(float(M_PI)), 0.0f, 1e-7f);
    EXPECT_TRUE(std::isnan(aq::sine(std::numeric_limits<float>::infinity())));
    EXPECT_TRUE(std::isnan(aq::sine(-std::numeric_limits<float>::infinity())));
    EXPECT_TRUE(std::isnan(aq::sine(std::numeric_limits<float>::quiet_NaN())));
    // The large reduction: sin(1e6) = -0.34999350217129294 (to double precision).
    EXPECT_NEAR(aq::sine(1e6f), -0.34999350217129294, 1e-7);
}

// The regression check behind the golden hashes: they hold the tremor of std::sin (glibc's sinf),
// which the tremor called before core/sine.h. On x86-64 glibc 2.36 with FMA (the platform of the
// goldens) glibc picks __sinf_fma, whose results sine() reproduces (all 2^32 inputs checked once,
// docs/determinism.md). Elsewhere the C library may round differently; sine() does not follow it.
TEST(Sine, EqualsTheSinfOfTheGoldensPlatform) {
    if (std::strcmp(gnu_get_libc_version(), "2.36") != 0 || !__builtin_cpu_supports("fma"))
        GTEST_SKIP() << "not the goldens' platform (glibc " << gnu_get_libc_version() << ")";
    std::size_t bad = 0;
    for (float y : sweep())
        if (bits(aq::sine(y)) != bits(std::sin(y)) && bad++ < 5)
            ADD_FAILURE() << std::hexfloat << "sine(" << y << ") = " << aq::sine(y) << ", sinf = " << std::sin(y);
    EXPECT_EQ(bad, 0u);
}

}  // namespace
