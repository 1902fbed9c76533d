// tests/stylize/pigment_apply_test.cpp — WC17 eq. 9 granulation, WC18 eq. 1-4 dry-brush and
// granulation, checked against values computed by hand here.
#include "stylize/stages/pigment_apply.h"

#include <cmath>
#include <cstring>

#include <gtest/gtest.h>

#include "tests/stylize/stage_test_util.h"

namespace aq::stylize {
namespace {

using testb::constant;
using testb::noise;

const glm::vec3 kWhite(1.0f);

//! Paper with the given heights in B and flat normals.
ImageF paper_with_heights(int w, int h, float (*height)(int x, int y)) {
    ImageF p(w, h, 3, 0.5f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) p.at(x, y, 2) = height(x, y);
    return p;
}

TEST(PigmentApplyWc17, FlatPaperAndZeroControlLeaveColourUnchanged) {
    const ImageF color = noise(13, 9, 4, 0.0f, 1.0f, 21);
    const ImageF ctrl(13, 9, 4, 0.0f);
    ImageF out;
    pigment_apply_wc17(out, color, ctrl, nullptr, {});
    EXPECT_TRUE(out == color);
    // Negative controls are "no granulation" in WC17's [0,1] range too.
    pigment_apply_wc17(out, color, ImageF(13, 9, 4, -0.7f), nullptr, {});
    EXPECT_TRUE(out == color);
}

TEST(PigmentApplyWc17, Eq9ByHand) {
    // I = 0.6, H = 0.3 -> P_iv = 0.7; Ctrl = 0.5, d = 2 -> k = 0.7.
    // I_g = 0.6 (0.6 - 0.7) + 0.4 * 0.6^1.7.
    PigmentApplyWc17Params p;
    p.density = 2.0f;
    const glm::vec4 o = pigment_apply_wc17_px({0.6f, 0.6f, 1.0f, 1.0f}, 0.3f, 0.5f, p);
    const double k = 0.7;
    EXPECT_NEAR(o.x, 0.6 * (0.6 - k) + 0.4 * std::pow(0.6, 1.0 + k), 2e-6);
    // A saturated channel (I = 1) is darkened by subtraction: 1 - k (the reason for the split model).
    EXPECT_NEAR(o.z, 1.0 - k, 2e-6);
    // Literal eq. 9: subtract P_iv itself.
    p.literal = true;
    const glm::vec4 l = pigment_apply_wc17_px({0.9f, 0.9f, 0.9f, 1.0f}, 0.3f, 0.5f, p);
    EXPECT_NEAR(l.x, 0.9 * (0.9 - 0.7) + 0.1 * std::pow(0.9, 1.7), 2e-6);
    // Roughness scales the relief: r = 0 flattens the paper to 0.5 -> P_iv = 0.5.
    p.literal = false;
    p.roughness = 0.0f;
    const glm::vec4 r = pigment_apply_wc17_px({0.6f, 0.6f, 0.6f, 1.0f}, 0.3f, 0.5f, p);
    EXPECT_NEAR(r.x, 0.6 * (0.6 - 0.5) + 0.4 * std::pow(0.6, 1.5), 2e-6);
}

TEST(PigmentApplyWc17, ValleysGetDarkerThanPeaks) {
    const int w = 10, h = 2;
    const ImageF color = constant(w, h, {0.5f, 0.6f, 0.7f, 1.0f});
    const ImageF paper = paper_with_heights(w, h, [](int x, int) { return x < 5 ? 0.1f : 0.9f; });
    ImageF out;
    pigment_apply_wc17(out, color, ImageF(w, h, 4, 1.0f), &paper, {});
    for (int c = 0; c < 3; ++c) EXPECT_LT(out.at(0, 0, c), out.at(9, 0, c));
}

TEST(PigmentApplyWc18, GranulationEq1To4ByHand) {
    // C = (0.4, 0.6, 0.2), H = 0.3, a = 0.5 (granulation), r = 1, D = 5.
    // Hr = 0.3; d_g = 0.7; L = 0.2126*0.4 + 0.7152*0.6 + 0.0722*0.2 = 0.52808;
    // d_g = 0.7 (1 - L) + 3.5 L = 2.178624; H_iv = 1 - (0.06 + 0.8) = 0.14;
    // d_a = 1 + 2.178624 * 0.14 * 5 = 2.5250368. |C - white| = sqrt(0.36+0.16+0.64) > 0.2 -> full.
    const glm::vec4 c(0.4f, 0.6f, 0.2f, 1.0f);
    const glm::vec4 o = pigment_apply_wc18_px(c, 0.3f, 0.5f, kWhite, {});
    const double L = 0.2126 * 0.4 + 0.7152 * 0.6 + 0.0722 * 0.2;
    const double dg = 0.7 * (1 - L) + 3.5 * L;
    const double da = 1 + dg * (1 - (0.3 * 0.2 + 0.8)) * 5;
    EXPECT_NEAR(o.x, std::pow(0.4, da), 2e-6);
    EXPECT_NEAR(o.y, std::pow(0.6, da), 2e-6);
    EXPECT_NEAR(o.z, std::pow(0.2, da), 2e-6);
    EXPECT_EQ(o.w, 1.0f);
}

TEST(PigmentApplyWc18, DryBrushEq2ByHand) {
    // a = -0.6 (dry-brush), H = 0.5 < 0.6: t = sat(|0.5 - 0.6| * 5) = 0.5 -> halfway to Cs.
    const glm::vec3 cs(0.9f, 0.85f, 0.8f);
    const glm::vec4 o = pigment_apply_wc18_px({0.2f, 0.3f, 0.4f, 0.9f}, 0.5f, -0.6f, cs, {});
    EXPECT_NEAR(o.x, 0.55f, 1e-6f);
    EXPECT_NEAR(o.y, 0.575f, 1e-6f);
    EXPECT_NEAR(o.z, 0.6f, 1e-6f);
    EXPECT_EQ(o.w, 0.9f);
}

TEST(PigmentApplyWc18, DryBrushOnlyWherePaperIsBelowTheThreshold) {
    // Heights 0..1 across x; a = -0.6: pixels with Hr < 0.6 move towards the substrate, the others
    // granulate (get darker, away from the white substrate).
    const int w = 21, h = 3;
    const ImageF color = constant(w, h, {0.3f, 0.5f, 0.2f, 1.0f});
    const ImageF paper = paper_with_heights(w, h, [](int x, int) { return (float(x) + 0.5f) / 21.0f; });
    const ImageF ctrl = constant(w, h, {0.0f, -0.6f, 0.0f, 0.0f});
    const glm::vec3 cs(0.95f, 0.92f, 0.9f);
    ImageF out;
    pigment_apply_wc18(out, color, ctrl, &paper, cs, {});
    for (int x = 0; x < w; ++x) {
        const float hr = (float(x) + 0.5f) / 21.0f;
        for (int c = 0; c < 3; ++c) {
            const float in = color.at(x, 1, c), o = out.at(x, 1, c);
            if (hr < 0.6f) {
                EXPECT_GT(o, in) << x;      // towards the (brighter) substrate
                EXPECT_LE(o, cs[c] + 1e-6f);
            } else {
                EXPECT_LE(o, in) << x;      // granulation darkens
            }
        }
    }
}

TEST(PigmentApplyWc18, BackgroundAndSubstrateColouredPixelsAreLeftAlone) {
    const glm::vec4 bg(0.3f, 0.3f, 0.3f, 0.0f);  // alpha 0: no painted surface
    EXPECT_EQ(pigment_apply_wc18_px(bg, 0.2f, 0.8f, kWhite, {}), bg);
    const glm::vec4 paper(1.0f, 1.0f, 1.0f, 1.0f);
    EXPECT_EQ(pigment_apply_wc18_px(paper, 0.2f, 0.8f, kWhite, {}), paper);
}

TEST(PigmentApply, TraversalsAgreeAndNonFiniteInputsDoNotCrash) {
    const ImageF color = testb::poison(noise(70, 67, 4, 0.0f, 1.0f, 31));
    const ImageF ctrl = testb::poison(noise(70, 67, 4, -1.0f, 1.0f, 32), 5);
    const ImageF paper = testb::poison(noise(70, 67, 3, 0.0f, 1.0f, 33), 11);
    ImageF a, b, c, d;
    pigment_apply_wc18(a, color, ctrl, &paper, kWhite, {}, Exec::reference());
    pigment_apply_wc18(b, color, ctrl, &paper, kWhite, {}, Exec::fast(2));
    pigment_apply_wc17(c, color, ctrl, &paper, {}, Exec::reference());
    pigment_apply_wc17(d, color, ctrl, &paper, {}, Exec::fast(2));
    EXPECT_TRUE(testb::same_values(a, b));  // the plain reference loop vs the row kernel
    EXPECT_TRUE(testb::same_values(c, d));
}

// The fast schedule skips 64-pixel chunks without a covered pixel (alpha >= kPigmentAlphaMask),
// testing the alphas two pixels per register. One covered pixel per chunk, at each position a
// chunk and a register can put it (first, second, last, odd and even), nearly black (no other
// channel passes the alpha test), among uncovered pixels whose colour channels would: reference, fast,
// and fast in place agree bit for bit (fails when a lane other than alpha is tested).
TEST(PigmentApplyWc18, ChunksWithOneCoveredPixelAreNotSkipped) {
    const int w = 64 * 4 + 5, h = 6;  // a partial last chunk of 5 (odd) pixels
    ImageF color = constant(w, h, {0.6f, 0.7f, 0.8f, 0.0f});
    const int at[] = {0, 64 + 1, 2 * 64 + 63, 3 * 64 + 30, 4 * 64 + 4};
    for (int y = 0; y < h; ++y)
        for (int x : at) color.at(x, y, 3) = 1.0f, color.at(x, y, 0) = color.at(x, y, 1) = color.at(x, y, 2) = 0.005f;
    const ImageF ctrl = noise(w, h, 4, -1.0f, 1.0f, 41), paper = noise(w, h, 3, 0.0f, 1.0f, 42);
    ImageF ref, fast, in_place = color;
    pigment_apply_wc18(ref, color, ctrl, &paper, kWhite, {}, Exec::reference());
    pigment_apply_wc18(fast, color, ctrl, &paper, kWhite, {}, Exec::fast(2));
    pigment_apply_wc18(in_place, in_place, ctrl, &paper, kWhite, {}, Exec::fast(2));
    for (int x : at) {
        bool painted = false;
        for (int y = 0; y < h; ++y) painted |= ref.at(x, y, 0) != 0.005f;
        ASSERT_TRUE(painted) << "the covered pixels at x " << x << " change";
    }
    EXPECT_EQ(0, std::memcmp(ref.data(), fast.data(), ref.num_values() * sizeof(float)));
    EXPECT_EQ(0, std::memcmp(ref.data(), in_place.data(), ref.num_values() * sizeof(float)));
}

TEST(PigmentApply, ChecksInputs) {
    const ImageF color = constant(8, 8, {0.5f, 0.5f, 0.5f, 1.0f});
    ImageF out;
    const ImageF small_paper(4, 4, 3, 0.5f);
    try {
        pigment_apply_wc18(out, color, ImageF(8, 8, 4), &small_paper, kWhite, {});
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("'paper'"), std::string::npos) << e.what();
    }
    EXPECT_THROW(pigment_apply_wc17(out, color, ImageF(8, 8, 1), nullptr, {}), Error);  // needs G
}

}  // namespace
}  // namespace aq::stylize
