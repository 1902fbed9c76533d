// tests/stylize/resample_test.cpp — the half-resolution convention: detail::resample (tables, used
// by the stages) equals kernels.h sample_resampled value for value; the even-size downsample is
// the 2x2 box average; constants survive up- and down-sampling exactly.
#include <cstring>

#include <gtest/gtest.h>

#include "stylize/kernels.h"
#include "stylize/stages/stage_util.h"
#include "tests/stylize/synthetic_gbuffer.h"

namespace aq::stylize {
namespace {

TEST(Resample, TablesMatchSampleResampledBitForBit) {
    const ImageF src = test::synthetic_target("color", 4, 37, 23, 5);
    for (auto [w, h] : {std::pair{19, 12}, {74, 46}, {37, 23}, {10, 31}}) {
        const ImageF r = detail::resample(src, w, h, Exec::fast(2));
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
    const ImageF d = detail::resample(src, half_size(8), half_size(6), Exec::reference());
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 4; ++x) {
            const float box = (src.at(2 * x, 2 * y, 0) + src.at(2 * x + 1, 2 * y, 0) + src.at(2 * x, 2 * y + 1, 0) +
                               src.at(2 * x + 1, 2 * y + 1, 0)) / 4.0f;
            EXPECT_FLOAT_EQ(d.at(x, y, 0), box);
        }
    const ImageF k(5, 3, 2, 0.3f);
    const ImageF up = detail::resample(k, 9, 6, Exec::reference());
    for (std::size_t i = 0; i < up.num_values(); ++i) EXPECT_EQ(up.data()[i], 0.3f);
}

}  // namespace
}  // namespace aq::stylize
