// tests/stylize/edge_detect_test.cpp — RGBD Sobel (WC18 §3): flat images have no edges, a step gives
// the hand-computed Sobel response, the depth weight scales depth steps, magnitude clamps at 1.
#include <gtest/gtest.h>

#include <cstring>
#include <iterator>
#include <limits>

#include "stylize/stages/edge_detect.h"

namespace aq::stylize {
namespace {

TEST(EdgeDetect, FlatImageHasNoEdgesWithEitherBorder) {
    ImageF c(9, 7, 4, 0.37f), z(9, 7, 1, 0.6f), e;
    for (Border b : {Border::Clamp, Border::Mirror}) {
        EdgeDetectParams p;
        p.border = b;
        edge_detect_rgbd_sobel(e, c, z, p, Exec::reference());
        for (std::size_t i = 0; i < e.num_values(); ++i) EXPECT_EQ(e.data()[i], 0.0f);
    }
}

TEST(EdgeDetect, ColourStepGivesTheSobelResponse) {
    // r steps by 0.1 between columns 3 and 4: |V| = (1 + 2 + 1) * 0.1 at columns 3 and 4, 0 elsewhere.
    ImageF c(8, 5, 4, 0.0f), z(8, 5, 1, 0.5f), e;
    for (int y = 0; y < 5; ++y)
        for (int x = 4; x < 8; ++x) c.at(x, y, 0) = 0.1f;
    edge_detect_rgbd_sobel(e, c, z, EdgeDetectParams{}, Exec::reference());
    for (int y = 0; y < 5; ++y)
        for (int x = 0; x < 8; ++x) {
            const float expect = (x == 3 || x == 4) ? 0.4f : 0.0f;
            EXPECT_NEAR(e.at(x, y, 0), expect, 1e-6f) << x << "," << y;
        }
}

TEST(EdgeDetect, DepthStepIsWeightedAndMagnitudeClamped) {
    ImageF c(6, 4, 4, 0.2f), z(6, 4, 1, 0.3f), e;
    for (int y = 2; y < 4; ++y)
        for (int x = 0; x < 6; ++x) z.at(x, y, 0) = 0.31f;  // horizontal depth step of 0.01
    edge_detect_rgbd_sobel(e, c, z, EdgeDetectParams{}, Exec::reference());
    EXPECT_NEAR(e.at(2, 1, 0), 4 * 0.01f * kSobelDepthWeight, 1e-5f);
    EXPECT_NEAR(e.at(2, 2, 0), 4 * 0.01f * kSobelDepthWeight, 1e-5f);
    EXPECT_EQ(e.at(2, 0, 0), 0.0f);
    EdgeDetectParams strong;
    strong.depth_weight = 1000.0f;
    edge_detect_rgbd_sobel(e, c, z, strong, Exec::reference());
    EXPECT_EQ(e.at(2, 1, 0), 1.0f);
}

// The fast traversal writes +0 for flat neighbourhoods without the Sobel sums: its bytes equal the
// reference's on a frame of flat regions with what could break that premise — a lone pixel at each
// column of the 64-pixel chunks' edges, +0 beside -0, infinities and NaN (flat, but their differences
// are NaN), a flat region of the largest finite value, flat rows that differ (a one-row stripe), an
// infinite depth weight, both borders.
TEST(EdgeDetect, FlatRegionsGiveTheReferenceBytes) {
    const int lone[] = {0, 1, 62, 63, 64, 65, 66, 127, 128, 129, 191, 192, 202};
    const int w = 203, h = 3 * int(std::size(lone)) + 9;
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    ImageF c(w, h, 4, 0.62f), z(w, h, 1, 1.0f);
    for (std::size_t i = 0; i < std::size(lone); ++i) c.at(lone[i], 3 * int(i) + 5, 1) = 0.3f;  // each on its own rows
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < w; ++x) {
            c.at(x, y, 0) = x % 2 ? 0.0f : -0.0f;  // +0 and -0: equal, not the same bits
            z.at(x, y, 0) = x < 70 ? inf : (x < 140 ? nan : std::numeric_limits<float>::max());
        }
    for (int x = 0; x < w; ++x) c.at(x, h - 1, 2) = x < 100 ? -inf : 0.5f;
    for (int x = 0; x < w; ++x) c.at(x, h - 4, 1) = 0.9f;  // a one-row stripe: each row flat, rows differ
    for (Border b : {Border::Clamp, Border::Mirror})
        for (float wd : {kSobelDepthWeight, inf}) {
            EdgeDetectParams p;
            p.border = b;
            p.depth_weight = wd;
            ImageF ref, fast;
            edge_detect_rgbd_sobel(ref, c, z, p, Exec::reference());
            edge_detect_rgbd_sobel(fast, c, z, p, Exec::fast(2));
            int zeros = 0;
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    const float a = fast.at(x, y, 0), r = ref.at(x, y, 0);
                    zeros += r == 0.0f;
                    // NaN where the reference has NaN (its sign bit may differ: the two traversals
                    // combine two NaN operands in different orders, as before the flat test), else
                    // the same bits.
                    if (r != r) {
                        ASSERT_NE(a, a) << x << "," << y << ", wd " << wd;
                    } else {
                        ASSERT_EQ(std::memcmp(&a, &r, sizeof(float)), 0)
                            << x << "," << y << ": " << a << " vs " << r << ", wd " << wd;
                    }
                }
            if (wd != inf) {  // inf x 0 is NaN
                EXPECT_GT(zeros, w * h / 4) << "flat regions present";
            }
        }
}

}  // namespace
}  // namespace aq::stylize
