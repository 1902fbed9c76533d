// tests/core/simd_test.cpp — core/simd.h's register helpers: those that move values take every
// lane's value from the place the helper names, for every lane position; floor8 is std::floor.
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "core/simd.h"

namespace aq {
namespace {

// floor8 computes (the one helper that does): the bits of std::floor in every lane, for values
// around and between integers of both signs, -0, halves, the float range's ends, infinities, NaN.
TEST(Simd, Floor8IsStdFloorInEveryLane) {
    const float inf = std::numeric_limits<float>::infinity();
    const std::vector<float> values = {-0.0f, 0.0f, 0.5f, -0.5f, 0.999999f, -0.999999f, 1.0f, -1.0f, 1.5f, -1.5f,
                                       2.4999998f, -2.5000002f, 8388607.5f, -8388607.5f, 16777216.0f, 3.0e38f,
                                       -3.0e38f, 1.0e-40f, -1.0e-40f, inf, -inf,
                                       std::numeric_limits<float>::quiet_NaN()};
    for (std::size_t start = 0; start < values.size(); ++start) {
        simd::v8f v;
        for (int k = 0; k < 8; ++k) v[k] = values[(start + std::size_t(k)) % values.size()];
        const simd::v8f f = simd::floor8(v);
        for (int k = 0; k < 8; ++k) {
            const float want = std::floor(v[k]), got = f[k];
            EXPECT_EQ(0, std::memcmp(&want, &got, sizeof want)) << "floor(" << v[k] << ") lane " << k << ": " << got;
        }
    }
}

// Each stride, from every start within a pixel, up to the last value of a buffer that ends at
// q[7 S] (reading past it would fault under the sanitizer build or read garbage here).
template <int S>
void expect_strided(const char* name) {
    for (int start = 0; start < S; ++start) {
        std::vector<float> buf(std::size_t(start + 7 * S + 1));
        for (std::size_t i = 0; i < buf.size(); ++i) buf[i] = float(i) + 0.25f;
        const simd::v8f v = simd::strided8<S>(buf.data() + start);
        for (int k = 0; k < 8; ++k) EXPECT_EQ(v[k], buf[std::size_t(start + k * S)]) << name << " start " << start << " lane " << k;
    }
}

TEST(Simd, Strided8TakesEveryStthValueAndReadsNoFurther) {
    expect_strided<1>("S = 1");
    expect_strided<3>("S = 3");
    expect_strided<4>("S = 4");
}

TEST(Simd, Gather8LoadsEachLanesIndex) {
    std::vector<float> base(1000);
    for (std::size_t i = 0; i < base.size(); ++i) base[i] = float(i) * 0.5f;
    const simd::v8i idx = {999, 0, 7, 7, 512, 3, 100, 1};
    const simd::v8f v = simd::gather8(base.data(), idx);
    for (int l = 0; l < 8; ++l) EXPECT_EQ(v[l], base[std::size_t(idx[l])]) << "lane " << l;
}

TEST(Simd, Permute16TakesEachLaneFromTheSixteenValues) {
    simd::v8f lo, hi;
    for (int k = 0; k < 8; ++k) lo[k] = float(k) + 0.5f, hi[k] = float(k + 8) + 0.5f;
    for (int start = 0; start < 16; ++start) {
        simd::v8i idx;
        for (int k = 0; k < 8; ++k) idx[k] = (start + 5 * k) % 16;  // every index, in every lane
        const simd::v8f v = simd::permute16(lo, hi, idx);
        for (int k = 0; k < 8; ++k) EXPECT_EQ(v[k], float(idx[k]) + 0.5f) << "lane " << k << " index " << idx[k];
    }
}

TEST(Simd, Bits8SetsTheBitOfEachSetLane) {
    for (unsigned want = 0; want < 256; ++want) {
        simd::v8i m;
        for (int l = 0; l < 8; ++l) m[l] = (want >> l) & 1u ? -1 : 0;
        EXPECT_EQ(simd::bits8(m), want);
    }
}

}  // namespace
}  // namespace aq
