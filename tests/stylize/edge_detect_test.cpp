// tests/stylize/edge_detect_test.cpp — RGBD Sobel (WC18 §3): flat images have no edges, a step gives
// the hand-computed Sobel response, the depth weight scales depth steps, magnitude clamps at 1.
#include <gtest/gtest.h>

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

}  // namespace
}  // namespace aq::stylize
