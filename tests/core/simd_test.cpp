// tests/core/simd_test.cpp — core/simd.h's register helpers move values, never compute them:
// every lane's value comes from the place the helper names, for every lane position.
#include <cstring>
#include <vector>

#include <gtest/gtest.h>

#include "core/simd.h"

namespace aq {
namespace {

TEST(Simd, RgbaChannel8PicksOneChannelOfEightPixelsInOrder) {
    float px[32];
    for (int i = 0; i < 32; ++i) px[i] = float(100 * (i / 4) + i % 4);  // pixel p, channel c: 100 p + c
    const simd::v8f c[4] = {simd::rgba_channel8<0>(px), simd::rgba_channel8<1>(px), simd::rgba_channel8<2>(px),
                            simd::rgba_channel8<3>(px)};
    for (int ch = 0; ch < 4; ++ch)
        for (int p = 0; p < 8; ++p) EXPECT_EQ(c[ch][p], float(100 * p + ch)) << "channel " << ch << " pixel " << p;
}

TEST(Simd, Gather8LoadsEachLanesIndex) {
    std::vector<float> base(1000);
    for (std::size_t i = 0; i < base.size(); ++i) base[i] = float(i) * 0.5f;
    const simd::v8i idx = {999, 0, 7, 7, 512, 3, 100, 1};
    const simd::v8f v = simd::gather8(base.data(), idx);
    for (int l = 0; l < 8; ++l) EXPECT_EQ(v[l], base[std::size_t(idx[l])]) << "lane " << l;
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
