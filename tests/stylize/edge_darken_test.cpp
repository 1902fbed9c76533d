// tests/stylize/edge_darken_test.cpp — WC17 eq. 8 (DoG) and WC18 §3.1 (RGBD) edge darkening.
#include "stylize/stages/edge_darken.h"

#include <cmath>

#include <gtest/gtest.h>

#include "tests/stylize/stage_test_util.h"

namespace aq::stylize {
namespace {

using testb::constant;
using testb::noise;

const glm::vec3 kWhite(1.0f);

TEST(EdgeDarkenRgbd, ZeroIntensityLeavesColourUnchanged) {
    const ImageF color = noise(17, 11, 4, 0.0f, 1.0f, 1);
    const ImageF edges = noise(17, 11, 1, 0.0f, 1.0f, 2);
    const ImageF ctrl = noise(17, 11, 4, -1.0f, 1.0f, 3);
    ImageF out;
    edge_darken_rgbd(out, color, edges, ctrl, nullptr, nullptr, kWhite, {0.0f});
    EXPECT_TRUE(out == color);
}

TEST(EdgeDarkenRgbd, NoEdgesLeaveColourUnchanged) {
    const ImageF color = noise(9, 7, 4, 0.0f, 1.0f, 4);
    const ImageF edges(9, 7, 1, 0.0f);
    const ImageF ctrl = noise(9, 7, 4, -1.0f, 1.0f, 5);
    ImageF out;
    edge_darken_rgbd(out, color, edges, ctrl, nullptr, nullptr, kWhite, {3.0f});
    EXPECT_TRUE(out == color);
}

TEST(EdgeDarkenRgbd, DarkensOnlyWhereEdgesAre) {
    // Left half has edges, right half none; colour in [0,1] so C^(1+E) <= C.
    const int w = 16, h = 6;
    const ImageF color = noise(w, h, 4, 0.05f, 0.7f, 6);  // away from the white substrate
    ImageF edges(w, h, 1, 0.0f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w / 2; ++x) edges.at(x, y, 0) = 0.8f;
    const ImageF ctrl(w, h, 4, 0.0f);
    ImageF out;
    edge_darken_rgbd(out, color, edges, ctrl, nullptr, nullptr, kWhite, {1.0f});
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) {
                if (x < w / 2) {
                    EXPECT_LT(out.at(x, y, c), color.at(x, y, c));
                } else {
                    EXPECT_EQ(out.at(x, y, c), color.at(x, y, c));
                }
                EXPECT_EQ(out.at(x, y, 3), color.at(x, y, 3));
            }
}

TEST(EdgeDarkenRgbd, MatchesMnprFormulaByHand) {
    // C = (0.5, 0.2, 0.8), edge 0.4, ci = 0.3 -> x5 = 1.5, intensity 2, bleed 0.1, substrate white.
    // |C - Cs| = sqrt(0.25 + 0.64 + 0.04) = 0.964 -> sat(4.82) = 1; sat(1 - 0.3) = 0.7.
    // E = 0.4 * 2 * 2.5 * 1 * 0.7 = 1.4 -> C^2.4.
    const glm::vec4 c(0.5f, 0.2f, 0.8f, 1.0f);
    const glm::vec4 o = edge_darken_rgbd_px(c, 0.4f, 0.3f, 0.1f, 0.0f, kWhite, {2.0f});
    EXPECT_NEAR(o.x, std::pow(0.5, 2.4), 2e-6);
    EXPECT_NEAR(o.y, std::pow(0.2, 2.4), 2e-6);
    EXPECT_NEAR(o.z, std::pow(0.8, 2.4), 2e-6);
    EXPECT_EQ(o.w, 1.0f);
    // Negative painted intensity is not amplified: ci = -0.5 -> (1 - 0.5); no bleed.
    const glm::vec4 n = edge_darken_rgbd_px(c, 0.4f, -0.5f, 0.0f, 0.0f, kWhite, {2.0f});
    EXPECT_NEAR(n.x, std::pow(0.5, 1.4), 2e-6);
    // Fully bled pixels (mask >= 1/3) and substrate-coloured ones are not darkened.
    EXPECT_EQ(edge_darken_rgbd_px(c, 0.4f, 0.3f, 0.5f, 0.0f, kWhite, {2.0f}), c);
    const glm::vec4 paper(1.0f, 1.0f, 1.0f, 1.0f);
    EXPECT_EQ(edge_darken_rgbd_px(paper, 0.9f, 1.0f, 0.0f, 0.0f, kWhite, {2.0f}), paper);
}

// Ours: E_d / (1 + crowding * crowd). The same pixel as above with crowd 0.5 and crowding 3:
// E = 1.4 / 2.5 = 0.56 -> C^1.56; crowding 0 (the default) or crowd 0 leave WC18's E.
TEST(EdgeDarkenRgbd, CrowdedEdgesDarkenLess) {
    const glm::vec4 c(0.5f, 0.2f, 0.8f, 1.0f);
    const glm::vec4 o = edge_darken_rgbd_px(c, 0.4f, 0.3f, 0.1f, 0.5f, kWhite, {2.0f, 3.0f});
    EXPECT_NEAR(o.x, std::pow(0.5, 1.56), 2e-6);
    EXPECT_NEAR(o.z, std::pow(0.8, 1.56), 2e-6);
    EXPECT_EQ(edge_darken_rgbd_px(c, 0.4f, 0.3f, 0.1f, 0.5f, kWhite, {2.0f, 0.0f}),
              edge_darken_rgbd_px(c, 0.4f, 0.3f, 0.1f, 0.0f, kWhite, {2.0f, 3.0f}));
    // The stage: a crowd map of zeros gives the bytes of no crowd map; a full one darkens less.
    const int w = 8, h = 8;
    const ImageF color = constant(w, h, {0.3f, 0.4f, 0.5f, 1.0f}), edges(w, h, 1, 0.8f), ctrl(w, h, 4, 0.0f);
    const ImageF none(w, h, 1, 0.0f), full(w, h, 1, 1.0f);
    ImageF a, b, d;
    edge_darken_rgbd(a, color, edges, ctrl, nullptr, nullptr, kWhite, {1.0f, 4.0f});
    edge_darken_rgbd(b, color, edges, ctrl, nullptr, &none, kWhite, {1.0f, 4.0f});
    edge_darken_rgbd(d, color, edges, ctrl, nullptr, &full, kWhite, {1.0f, 4.0f});
    EXPECT_EQ(std::vector<float>(a.data(), a.data() + a.num_values()), std::vector<float>(b.data(), b.data() + b.num_values()));
    EXPECT_LT(a.at(3, 3, 0), d.at(3, 3, 0));
    EXPECT_LT(d.at(3, 3, 0), color.at(3, 3, 0));
    // A coarser crowd map is resampled (a constant one gives the same as full size); a larger one is refused.
    const ImageF coarse(3, 3, 1, 1.0f), large(9, 8, 1, 1.0f);
    ImageF e;
    edge_darken_rgbd(e, color, edges, ctrl, nullptr, &coarse, kWhite, {1.0f, 4.0f});
    EXPECT_EQ(std::vector<float>(e.data(), e.data() + e.num_values()), std::vector<float>(d.data(), d.data() + d.num_values()));
    EXPECT_THROW(edge_darken_rgbd(e, color, edges, ctrl, nullptr, &large, kWhite, {}), Error) << "crowd larger than color";
}

TEST(EdgeDarkenRgbd, BleedMaskFromHalfResolutionAlphaSuppressesEdges) {
    const int w = 8, h = 8;
    const ImageF color = constant(w, h, {0.3f, 0.4f, 0.5f, 1.0f});
    const ImageF edges(w, h, 1, 1.0f);
    const ImageF ctrl(w, h, 4, 0.0f);
    const ImageF bleed = constant(4, 4, {0.0f, 0.0f, 0.0f, 1.0f});  // half resolution, mask in alpha
    ImageF out;
    edge_darken_rgbd(out, color, edges, ctrl, &bleed, nullptr, kWhite, {5.0f});
    EXPECT_TRUE(out == color);
}

TEST(EdgeDarkenDog, FlatImageHasNoDogEdgesAndStaysUnchanged) {
    const ImageF color = constant(10, 6, {0.2f, 0.6f, 0.4f, 1.0f});
    const ImageF blurred = constant(5, 3, {0.2f, 0.6f, 0.4f, 1.0f});
    const ImageF ctrl(10, 6, 4, 1.0f);
    ImageF out;
    edge_darken_dog(out, color, blurred, ctrl, {});
    EXPECT_TRUE(out == color);
}

TEST(EdgeDarkenDog, Eq8ByHand) {
    // I = (0.4, 0.5, 0.6), I_b = (0.6, 0.55, 0.5): max(I_b - I) = 0.2 >= smooth_high -> E_m = 0.2.
    // ctrl.edge.r = 0.5, bias 1, intensity 2 -> exponent 1 + 1.5 * 2 * 0.2 = 1.6.
    EdgeDarkenDogParams p;
    p.intensity = 2.0f;
    const glm::vec4 o = edge_darken_dog_px({0.4f, 0.5f, 0.6f, 0.7f}, {0.6f, 0.55f, 0.5f}, 0.5f, p);
    EXPECT_NEAR(o.x, std::pow(0.4, 1.6), 2e-6);
    EXPECT_NEAR(o.y, std::pow(0.5, 1.6), 2e-6);
    EXPECT_NEAR(o.z, std::pow(0.6, 1.6), 2e-6);
    EXPECT_EQ(o.w, 0.7f);
    // Brighter than the blur (I > I_b everywhere): no darkening (WC17: I is subtracted from I_b).
    const glm::vec4 c(0.7f, 0.7f, 0.7f, 1.0f);
    EXPECT_EQ(edge_darken_dog_px(c, {0.5f, 0.5f, 0.5f}, 1.0f, p), c);
    // Weak DoG responses (colour gradients) are attenuated by the smoothstep: E = 0.02 ->
    // t = 0.2, smoothstep = 0.104, E_m = 0.00208.
    const glm::vec4 g = edge_darken_dog_px({0.5f, 0.5f, 0.5f, 1.0f}, {0.52f, 0.5f, 0.5f}, 0.0f, p);
    EXPECT_NEAR(g.x, std::pow(0.5, 1.0 + 2.0 * 0.02 * 0.104), 2e-6);
    // Eq. 8 literal (bias 0): unpainted pixels are not darkened.
    p.ctrl_bias = 0.0f;
    const glm::vec4 u(0.4f, 0.5f, 0.6f, 1.0f);
    EXPECT_EQ(edge_darken_dog_px(u, {0.6f, 0.55f, 0.5f}, 0.0f, p), u);
}

TEST(EdgeDarkenDog, DarkensTheDarkSideOfAStepOnly) {
    // A vertical step dark|bright; the blur (same resolution here) spreads it by one pixel.
    const int w = 12, h = 4;
    ImageF color(w, h, 4), blurred(w, h, 4);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float v = x < 6 ? 0.2f : 0.8f;
            const float b = x == 5 ? 0.5f : (x == 6 ? 0.5f : v);
            for (int c = 0; c < 3; ++c) color.at(x, y, c) = v, blurred.at(x, y, c) = b;
            color.at(x, y, 3) = blurred.at(x, y, 3) = 1.0f;
        }
    ImageF out;
    edge_darken_dog(out, color, blurred, ImageF(w, h, 4, 0.0f), {});
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            if (x == 5)
                EXPECT_LT(out.at(x, y, 0), color.at(x, y, 0));
            else
                EXPECT_EQ(out.at(x, y, 0), color.at(x, y, 0));
        }
}

TEST(EdgeDarkenDog, HalfResolutionBlurIsUpsampledWithGlTextureConvention) {
    // 4x2 output, 2x1 blur. Output x samples the blur at ((x + 0.5) / 4) * 2 with texel centres at
    // +0.5 and clamp to edge: x = 0 -> b0, x = 1 -> b0 + (b1 - b0) / 4, x = 2 -> b0 + 3 (b1 - b0) / 4,
    // x = 3 -> b1. With I = 0.3, b = (0.6, 1.0): E = 0.3, 0.4, 0.6, 0.7 (all >= smooth_high).
    const ImageF color = constant(4, 2, {0.3f, 0.3f, 0.3f, 1.0f});
    ImageF blurred(2, 1, 4, 0.0f);
    for (int c = 0; c < 3; ++c) blurred.at(0, 0, c) = 0.6f, blurred.at(1, 0, c) = 1.0f;
    ImageF out;
    edge_darken_dog(out, color, blurred, ImageF(4, 2, 4, 0.0f), {});
    const double e[4] = {0.3, 0.4, 0.6, 0.7};
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 4; ++x) EXPECT_NEAR(out.at(x, y, 0), std::pow(0.3, 1.0 + e[x]), 3e-6) << x;
}

TEST(EdgeDarken, DarkeningNeverBrightensUnitColours) {
    const ImageF color = noise(23, 13, 4, 0.0f, 1.0f, 7);
    const ImageF edges = noise(23, 13, 1, 0.0f, 1.0f, 8);
    const ImageF ctrl = noise(23, 13, 4, -1.0f, 1.0f, 9);
    const ImageF blurred = noise(12, 7, 4, 0.0f, 1.0f, 10);
    ImageF a, b;
    edge_darken_rgbd(a, color, edges, ctrl, nullptr, nullptr, {0.9f, 0.85f, 0.8f}, {4.0f});
    edge_darken_dog(b, color, blurred, ctrl, {});
    for (std::size_t i = 0; i < color.num_values(); ++i) {
        EXPECT_LE(a.data()[i], color.data()[i]);
        EXPECT_GE(a.data()[i], 0.0f);
        EXPECT_LE(b.data()[i], color.data()[i]);
        EXPECT_GE(b.data()[i], 0.0f);
    }
}

// The fast schedule skips 64-pixel chunks without an edge (tested eight at a time). One edge pixel
// per chunk, first, second, last and in a partial last chunk, one NaN edge: reference, fast and
// fast in place agree bit for bit (fails when the test misses a pixel of the chunk).
TEST(EdgeDarkenRgbd, ChunksWithOneEdgePixelAreNotSkipped) {
    const int w = 64 * 4 + 3, h = 5;
    const ImageF color = noise(w, h, 4, 0.1f, 0.9f, 51);
    ImageF edges(w, h, 1, 0.0f);
    const int at[] = {0, 64 + 1, 2 * 64 + 63, 4 * 64 + 2};
    for (int y = 0; y < h; ++y) {
        for (int x : at) edges.at(x, y, 0) = 0.8f;
        edges.at(3 * 64 + 7, y, 0) = std::nanf("");
    }
    const ImageF ctrl = noise(w, h, 4, -1.0f, 1.0f, 52);
    ImageF ref, fast, in_place = color;
    edge_darken_rgbd(ref, color, edges, ctrl, nullptr, nullptr, kWhite, {}, Exec::reference());
    edge_darken_rgbd(fast, color, edges, ctrl, nullptr, nullptr, kWhite, {}, Exec::fast(2));
    edge_darken_rgbd(in_place, in_place, edges, ctrl, nullptr, nullptr, kWhite, {}, Exec::fast(2));
    for (int x : at) ASSERT_NE(ref.at(x, 0, 0), color.at(x, 0, 0)) << "the edge pixel at " << x << " darkens";
    EXPECT_TRUE(testb::same_values(ref, fast));
    EXPECT_TRUE(testb::same_values(ref, in_place));
}

TEST(EdgeDarken, ChecksInputsAndNeverWritesThem) {
    const ImageF color = constant(8, 8, {0.5f, 0.5f, 0.5f, 1.0f});
    const ImageF small(4, 4, 1, 0.0f);
    const ImageF ctrl(8, 8, 4, 0.0f);
    ImageF out;
    try {
        edge_darken_rgbd(out, color, small, ctrl, nullptr, nullptr, kWhite, {});
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("'edges'"), std::string::npos) << e.what();
    }
    EXPECT_THROW(edge_darken_rgbd(out, ImageF(8, 8, 3), ImageF(8, 8, 1), ctrl, nullptr, nullptr, kWhite, {}), Error);
    ImageF alias(8, 8, 1, 0.0f);  // the output may be the colour (in place), never another input
    EXPECT_THROW(edge_darken_rgbd(alias, color, alias, ctrl, nullptr, nullptr, kWhite, {}), Error);
    EdgeDarkenDogParams bad;
    bad.smooth_low = bad.smooth_high = 0.2f;
    EXPECT_THROW(edge_darken_dog(out, color, color, ctrl, bad), Error);
}

TEST(EdgeDarken, NonFiniteInputsDoNotCrash) {
    const ImageF color = testb::poison(noise(16, 9, 4, 0.0f, 1.0f, 11));
    const ImageF edges = testb::poison(noise(16, 9, 1, 0.0f, 1.0f, 12), 3);
    const ImageF ctrl = testb::poison(noise(16, 9, 4, -1.0f, 1.0f, 13), 5);
    const ImageF blurred = testb::poison(noise(8, 5, 4, 0.0f, 1.0f, 14), 4);
    ImageF a, b;
    edge_darken_rgbd(a, color, edges, ctrl, &blurred, nullptr, kWhite, {1.0f});
    edge_darken_dog(b, color, blurred, ctrl, {});
    EXPECT_EQ(a.width(), 16);
    EXPECT_EQ(b.width(), 16);
}

}  // namespace
}  // namespace aq::stylize
