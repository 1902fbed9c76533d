// tests/stylize/substrate_test.cpp — paper distortion (WC17 §3.3 / MNPR) and substrate lighting
// (WC18 eq. 5).
#include "stylize/stages/substrate_distort.h"
#include "stylize/stages/substrate_light.h"

#include <cmath>
#include <cstring>
#include <limits>

#include <gtest/gtest.h>

#include "stylize/paper.h"
#include "tests/stylize/stage_test_util.h"
#include "tests/test_support.h"

namespace aq::stylize {
namespace {

using testb::constant;
using testb::noise;

//! Paper whose normal is the same everywhere: R,G = encoded n.xy.
ImageF uniform_paper(int w, int h, float r, float g) {
    ImageF p(w, h, 3, 0.5f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) p.at(x, y, 0) = r, p.at(x, y, 1) = g;
    return p;
}

TEST(SubstrateDistort, FlatPaperIsTheIdentity) {
    const ImageF color = noise(19, 12, 4, 0.0f, 1.0f, 41);
    const ImageF depth = noise(19, 12, 1, 0.0f, 1.0f, 42);
    const ImageF ctrl = noise(19, 12, 4, -1.0f, 1.0f, 43);
    const ImageF flat = flat_paper(19, 12);
    SubstrateDistortParams p;
    p.distortion = 10.0f;
    ImageF a, b;
    substrate_distort(a, color, depth, ctrl, &flat, p);
    substrate_distort(b, color, depth, ctrl, nullptr, p);
    EXPECT_TRUE(a == color);
    EXPECT_TRUE(b == color);
}

TEST(SubstrateDistort, ShiftsByTheNormalTimesControl) {
    // n = (1, 0) (R = 1): k = sat(0 + 0.2) = 0.2, offset = 1 * distortion * 5 * 0.2 = 2 px with
    // distortion 2 -> every pixel takes its right neighbour's right neighbour (clamped at the border).
    const int w = 12, h = 3;
    ImageF color(w, h, 4);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) color.at(x, y, 0) = float(x), color.at(x, y, 3) = 1.0f;
    const ImageF paper = uniform_paper(w, h, 1.0f, 0.5f);
    SubstrateDistortParams p;
    p.distortion = 2.0f;
    ImageF out;
    substrate_distort(out, color, ImageF(w, h, 1, 0.5f), ImageF(w, h, 4, 0.0f), &paper, p);
    for (int x = 0; x < w; ++x) EXPECT_NEAR(out.at(x, 1, 0), float(std::min(x + 2, w - 1)), 1e-5f) << x;
}

TEST(SubstrateDistort, DoesNotSampleForegroundFromBehindADepthStep) {
    // Left half foreground (depth 0.2, colour red), right half background (depth 0.8, blue).
    // The paper pushes every sample 3 px to the left (n = (-1, 0), distortion 3).
    const int w = 16, h = 4;
    ImageF color(w, h, 4), depth(w, h, 1);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const bool fg = x < 8;
            color.at(x, y, 0) = fg ? 1.0f : 0.0f;
            color.at(x, y, 2) = fg ? 0.0f : 1.0f;
            color.at(x, y, 3) = 1.0f;
            depth.at(x, y, 0) = fg ? 0.2f : 0.8f;
        }
    const ImageF paper = uniform_paper(w, h, 0.0f, 0.5f);
    SubstrateDistortParams p;
    p.distortion = 3.0f;
    ImageF out;
    substrate_distort(out, color, depth, ImageF(w, h, 4, 0.0f), &paper, p);
    for (int y = 0; y < h; ++y)
        for (int x = 8; x < w; ++x) {  // background pixels never take the foreground colour
            EXPECT_EQ(out.at(x, y, 0), 0.0f) << x;
            EXPECT_EQ(out.at(x, y, 2), 1.0f) << x;
        }
    // Both-sided guard: foreground pixels do not take the background colour either (push right).
    const ImageF right = uniform_paper(w, h, 1.0f, 0.5f);
    p.both_sides = true;
    substrate_distort(out, color, depth, ImageF(w, h, 4, 0.0f), &right, p);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const bool fg = x < 8;
            EXPECT_EQ(out.at(x, y, 0), fg ? 1.0f : 0.0f) << x;
            EXPECT_EQ(out.at(x, y, 2), fg ? 0.0f : 1.0f) << x;
        }
}

TEST(SubstrateDistort, RealPaperKeepsColoursOfAConstantImage) {
    const ImageF paper = prepare_paper({test::asset("paper/mnpr/rough_default_2k.jpg"), "mnpr", 1.0f, 1.0f}, 40, 30);
    const ImageF color = constant(40, 30, {0.25f, 0.5f, 0.75f, 1.0f});
    ImageF out;
    substrate_distort(out, color, ImageF(40, 30, 1, 0.3f), ImageF(40, 30, 4, 1.0f), &paper, {});
    for (std::size_t i = 0; i < out.num_values(); ++i) EXPECT_NEAR(out.data()[i], color.data()[i], 1e-6f);
}

TEST(SubstrateLight, FlatPaperGivesAConstantFactor) {
    // Flat paper: N = (0, 0, 1), N.L = tilt/89 = 45/89. Eq. 5: Id = 1 - (1 - 45/89) * 0.5.
    const ImageF color = noise(11, 7, 4, 0.0f, 1.0f, 51);
    const ImageF flat = flat_paper(11, 7);
    ImageF lin, sq;
    substrate_light(lin, color, &flat, {}, false);
    substrate_light(sq, color, nullptr, {}, true);
    const float nl = 45.0f / 89.0f;
    const float id_lin = 1.0f - (1.0f - nl) * 0.5f, id_sq = 1.0f - (1.0f - nl) * (1.0f - nl) * 0.5f;
    for (int y = 0; y < 7; ++y)
        for (int x = 0; x < 11; ++x) {
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(lin.at(x, y, c), color.at(x, y, c) * id_lin, 1e-6f);
                EXPECT_NEAR(sq.at(x, y, c), color.at(x, y, c) * id_sq, 1e-6f);
            }
            EXPECT_EQ(lin.at(x, y, 3), color.at(x, y, 3));
        }
}

TEST(SubstrateLight, SlopesFacingTheLightAreBrighter) {
    // Light from direction 180 deg: L = (0, -1, tilt/89). A normal with n.y < 0 faces it.
    // MNPR normal N = (-(R - 0.5), -(G - 0.5), 1): G = 1 -> n.y = -0.5 (facing), G = 0 -> +0.5.
    const ImageF color = constant(2, 1, {0.5f, 0.5f, 0.5f, 1.0f});
    ImageF paper(2, 1, 3, 0.5f);
    paper.at(0, 0, 1) = 1.0f;
    paper.at(1, 0, 1) = 0.0f;
    ImageF out;
    substrate_light(out, color, &paper, {}, false);
    EXPECT_GT(out.at(0, 0, 0), out.at(1, 0, 0));
    // Eq. 5 by hand for the facing pixel: N.L = 0.5 + 45/89; Id = 1 - (1 - N.L) * 0.5.
    const float nl = 0.5f * 1.0f + 45.0f / 89.0f;
    EXPECT_NEAR(out.at(0, 0, 0), 0.5f * (1.0f - (1.0f - nl) * 0.5f), 1e-5f);
    // Zero shading: unchanged.
    SubstrateLightParams none;
    none.shading = 0.0f;
    substrate_light(out, color, &paper, none, false);
    EXPECT_TRUE(out == color);
}

// The row loops (templated on the paper's channel count: none, 3, 4) compute substrate_light_px
// itself, bit for bit, at every pixel, for both curves and with and without normalisation.
TEST(SubstrateLight, RowsEqualThePerPixelFunctionForEveryPaperLayout) {
    const int w = 45, h = 13;  // rows not a multiple of any vector width
    const ImageF color = noise(w, h, 4, 0.0f, 1.0f, 71);
    const ImageF p3 = noise(w, h, 3, 0.0f, 1.0f, 72), p4 = noise(w, h, 4, 0.0f, 1.0f, 73);
    for (const ImageF* paper : {static_cast<const ImageF*>(nullptr), &p3, &p4})
        for (bool squared : {false, true})
            for (bool normalize : {false, true}) {
                SubstrateLightParams p;
                p.normalize = normalize;
                p.roughness = 1.7f;
                const glm::vec3 l = substrate_light_dir(p);
                const float norm = substrate_light_norm(l, p, squared);
                ImageF out;
                substrate_light(out, color, paper, p, squared, Exec::fast(2));
                for (int y = 0; y < h; ++y)
                    for (int x = 0; x < w; ++x) {
                        const float tr = paper ? paper->at(x, y, 0) : 0.5f, tg = paper ? paper->at(x, y, 1) : 0.5f;
                        const glm::vec4 c(color.at(x, y, 0), color.at(x, y, 1), color.at(x, y, 2), color.at(x, y, 3));
                        const glm::vec4 want = substrate_light_px(c, tr, tg, l, norm, p, squared);
                        for (int k = 0; k < 4; ++k)
                            ASSERT_EQ(out.at(x, y, k), want[k]) << x << "," << y << " channel " << k << " paper "
                                                                << (paper ? paper->channels() : 0);
                    }
            }
}

TEST(Substrate, TraversalsAgreeAndNonFiniteInputsDoNotCrash) {
    const int w = 90, h = 70;
    const ImageF paper = testb::poison(noise(w, h, 3, 0.0f, 1.0f, 61), 13);
    const ImageF color = testb::poison(noise(w, h, 4, 0.0f, 1.0f, 62));
    const ImageF depth = testb::poison(noise(w, h, 1, 0.0f, 1.0f, 63), 3);
    const ImageF ctrl = testb::poison(noise(w, h, 4, -1.0f, 1.0f, 64), 5);
    SubstrateDistortParams p;
    p.distortion = 10.0f;
    p.border = Border::Mirror;
    ImageF a, b, c, d;
    substrate_distort(a, color, depth, ctrl, &paper, p, Exec::reference());
    substrate_distort(b, color, depth, ctrl, &paper, p, Exec::fast(2));
    substrate_light(c, color, &paper, {}, false, Exec::reference());
    substrate_light(d, color, &paper, {}, false, Exec::fast(2));
    EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.num_values() * sizeof(float)));
    EXPECT_EQ(0, std::memcmp(c.data(), d.data(), c.num_values() * sizeof(float)));
}

// A model on a flat background: the fast traversal skips the taps of the background's margins
// (every tap within reach holds the pixel's own value). It must give the reference's bits for
// backgrounds with and without -0, a speck near the border, a row whose first pixel differs, a
// NaN at a row's end, both border rules, both depth rules and a reach of 7 and 52 pixels.
TEST(SubstrateDistort, FastEqualsReferenceAroundAModelOnAFlatBackground) {
    const int w = 200, h = 120;
    // Random normals, and uniform ones with the full control: every offset 4.5 px to the right,
    // then to the left (the reach of the taps, exactly).
    const ImageF papers[3] = {noise(w, h, 3, 0.0f, 1.0f, 71), uniform_paper(w, h, 0.95f, 0.5f),
                              uniform_paper(w, h, 0.05f, 0.5f)};
    const ImageF ctrls[3] = {noise(w, h, 4, -1.0f, 1.0f, 72), ImageF(w, h, 4, 1.0f), ImageF(w, h, 4, 1.0f)};
    const ImageF model_c = noise(w, h, 4, 0.0f, 1.0f, 73), model_z = noise(w, h, 1, 0.2f, 0.6f, 74);
    for (const glm::vec4 bg : {glm::vec4(0.0f), glm::vec4(0.3f, -0.0f, 0.5f, 0.0f), glm::vec4(0.2f, 0.2f, 0.2f, 1.0f)}) {
        ImageF color = constant(w, h, bg), depth(w, h, 1, 1.0f);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const float dx = (x - 110.0f) / 40.0f, dy = (y - 60.0f) / 30.0f;
                if (dx * dx + dy * dy < 1.0f) {
                    for (int k = 0; k < 4; ++k) color.at(x, y, k) = model_c.at(x, y, k);
                    depth.at(x, y, 0) = model_z.at(x, y, 0);
                }
            }
        color.at(3, 50, 0) = 0.9f;                                   // a speck near the left border
        color.at(0, 30, 1) = 0.7f;                                   // a row whose first pixel differs
        color.at(w - 1, 90, 2) = std::numeric_limits<float>::quiet_NaN();  // not finite at a row's end
        depth.at(150, 5, 0) = 0.5f;                                  // a depth step near the top
        for (int y = 100; y < h; ++y)                                // an infinite corner
            for (int x = 0; x < 60; ++x) color.at(x, y, 0) = std::numeric_limits<float>::infinity();
        for (int pc = 0; pc < 3; ++pc)
        for (const float dist : {1.0f, 10.0f})
            for (const Border border : {Border::Clamp, Border::Mirror})
                for (const bool both : {false, true}) {
                    SubstrateDistortParams p;
                    p.distortion = dist;
                    p.border = border;
                    p.both_sides = both;
                    p.depth_threshold = both ? 0.0f : 0.01f;
                    ImageF ref, f1, f2;
                    substrate_distort(ref, color, depth, ctrls[pc], &papers[pc], p, Exec::reference());
                    substrate_distort(f1, color, depth, ctrls[pc], &papers[pc], p, Exec::fast(1));
                    substrate_distort(f2, color, depth, ctrls[pc], &papers[pc], p, Exec::fast(2));
                    SCOPED_TRACE(::testing::Message() << "paper " << pc << " bg " << bg.x << "," << bg.y << " distortion " << dist
                                                      << " border " << int(border) << " both " << both);
                    ASSERT_EQ(0, std::memcmp(ref.data(), f1.data(), ref.num_values() * sizeof(float)));
                    ASSERT_EQ(0, std::memcmp(ref.data(), f2.data(), ref.num_values() * sizeof(float)));
                }
    }
}

TEST(Substrate, ChecksInputs) {
    const ImageF color = constant(8, 8, {0.5f, 0.5f, 0.5f, 1.0f});
    ImageF out;
    try {
        substrate_distort(out, color, ImageF(8, 7, 1), ImageF(8, 8, 4), nullptr, {});
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("'depth'"), std::string::npos) << e.what();
    }
    const ImageF two_ch(8, 8, 2);
    EXPECT_THROW(substrate_light(out, color, &two_ch, {}, false), Error);
}

}  // namespace
}  // namespace aq::stylize
