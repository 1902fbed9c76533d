// tests/stylize/gaps_overlaps_test.cpp — WC18 Algorithm 1 on a small synthetic two-colour image.
#include "stylize/stages/gaps_overlaps.h"

#include <cmath>
#include <cstring>

#include <gtest/gtest.h>

#include "stylize/ryb.h"
#include "tests/stylize/stage_test_util.h"

namespace aq::stylize {
namespace {

using testb::noise;

constexpr int kW = 16, kH = 5;
const glm::vec3 kPaper(0.97f, 0.95f, 0.9f);

//! Left half colour a, right half colour b (alpha 1).
ImageF two_colours(glm::vec3 a, glm::vec3 b) {
    ImageF img(kW, kH, 4);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const glm::vec3 c = x < kW / 2 ? a : b;
            img.at(x, y, 0) = c.r, img.at(x, y, 1) = c.g, img.at(x, y, 2) = c.b, img.at(x, y, 3) = 1.0f;
        }
    return img;
}

//! Extended edges: a linear ramp peaking at the boundary between x = 7 and x = 8,
//! E(x) = max(0, 1 - |x + 0.5 - 8| / 4): 0.125, 0.375, 0.625, 0.875 | 0.875, 0.625, 0.375, 0.125.
ImageF ramp_edges() {
    ImageF e(kW, kH, 1);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) e.at(x, y, 0) = std::max(0.0f, 1.0f - std::fabs(float(x) + 0.5f - 8.0f) / 4.0f);
    return e;
}

ImageF ctrl_b(float v, int w = kW, int h = kH) {
    ImageF c(w, h, 4, 0.0f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) c.at(x, y, 2) = v;
    return c;
}

glm::vec4 px(const ImageF& img, int x, int y) {
    return {img.at(x, y, 0), img.at(x, y, 1), img.at(x, y, 2), img.at(x, y, 3)};
}

const glm::vec3 kYellow = ryb_to_rgb({0, 1, 0});
const glm::vec3 kBlue = ryb_to_rgb({0, 0, 1});

TEST(GapsOverlaps, ZeroControlLeavesColourUnchanged) {
    const ImageF color = two_colours(kYellow, kBlue);
    ImageF out;
    gaps_overlaps(out, color, ramp_edges(), ctrl_b(0.0f), nullptr, kPaper, {});
    EXPECT_TRUE(out == color);
}

TEST(GapsOverlaps, OverlapsMixNeighbouringColoursInRyb) {
    const ImageF color = two_colours(kYellow, kBlue);
    ImageF out;
    gaps_overlaps(out, color, ramp_edges(), ctrl_b(1.0f), nullptr, kPaper, {});  // p = 5
    const glm::vec3 mixed = mix_ryb(kYellow, kBlue);
    EXPECT_GT(mixed.g, mixed.r);  // yellow + blue = green in RYB
    EXPECT_GT(mixed.g, mixed.b);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const glm::vec4 o = px(out, x, y);
            if (x >= 4 && x <= 11) {  // inside the extended edge (E > 0.1)
                EXPECT_NEAR(o.r, mixed.r, 1e-6f) << x;
                EXPECT_NEAR(o.g, mixed.g, 1e-6f) << x;
                EXPECT_NEAR(o.b, mixed.b, 1e-6f) << x;
            } else {
                EXPECT_EQ(o, px(color, x, y)) << x;
            }
            EXPECT_EQ(o.a, 1.0f);
        }
}

TEST(GapsOverlaps, OverlapWidthFollowsTheControl) {
    // p = 0.4 * 5 = 2: only pixels within 2 steps of the other colour overlap.
    const ImageF color = two_colours(kYellow, kBlue);
    ImageF out;
    gaps_overlaps(out, color, ramp_edges(), ctrl_b(0.4f), nullptr, kPaper, {});
    for (int x = 0; x < kW; ++x) {
        const bool changed = px(out, x, 2) != px(color, x, 2);
        EXPECT_EQ(changed, x >= 6 && x <= 9) << x;
    }
}

TEST(GapsOverlaps, NonConvergingMarchMixesWithThePixelBehind) {
    // Algorithm 1 lines 22-26: the extended edges fall off to the right everywhere, so the gradient
    // points left. Yellow pixel x = 7 marches left over yellow for all m steps, then mixes with the
    // pixel behind it (x = 8, blue).
    const ImageF color = two_colours(kYellow, kBlue);
    ImageF edges(kW, kH, 1);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) edges.at(x, y, 0) = 1.0f - float(x) / 16.0f;
    ImageF out;
    gaps_overlaps(out, color, edges, ctrl_b(1.0f), nullptr, kPaper, {});
    const glm::vec3 mixed = mix_ryb(kYellow, kBlue);
    EXPECT_NEAR(out.at(7, 2, 0), mixed.r, 1e-6f);
    EXPECT_NEAR(out.at(7, 2, 1), mixed.g, 1e-6f);
    EXPECT_NEAR(out.at(7, 2, 2), mixed.b, 1e-6f);
    // Blue x = 8 finds yellow one step to the left: the same mix, by the forward march.
    EXPECT_NEAR(out.at(8, 2, 1), mixed.g, 1e-6f);
}

// In place (StageVariant::in_place_input), every pixel still reads the colours before any change:
// blue x = 8 marches into x = 7, which itself becomes a mix; written at once, x = 8 would mix with
// that mix. Every traversal, one image as input and output, against separate images.
TEST(GapsOverlaps, InPlaceReadsTheColoursBeforeAnyChange) {
    const ImageF color = two_colours(kYellow, kBlue);
    ImageF edges(kW, kH, 1);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) edges.at(x, y, 0) = 1.0f - float(x) / 16.0f;
    for (const Exec& ex : {Exec::reference(), Exec::fast(1), Exec::fast(2)}) {
        ImageF separate;
        gaps_overlaps(separate, color, edges, ctrl_b(1.0f), nullptr, kPaper, {}, ex);
        ImageF inplace = color;
        gaps_overlaps(inplace, inplace, edges, ctrl_b(1.0f), nullptr, kPaper, {}, ex);
        EXPECT_EQ(0, std::memcmp(separate.data(), inplace.data(), separate.num_values() * sizeof(float)))
            << "threads " << ex.threads << " traversal " << int(ex.traversal);
        EXPECT_NE(px(inplace, 7, 2), px(color, 7, 2));  // the case happens: both pixels change
        EXPECT_NE(px(inplace, 8, 2), px(color, 8, 2));
    }
}

TEST(GapsOverlaps, NoOverlapWithTheSubstrateColour) {
    const ImageF color = two_colours(kYellow, kPaper);
    ImageF out;
    gaps_overlaps(out, color, ramp_edges(), ctrl_b(1.0f), nullptr, kPaper, {});
    for (int x = 0; x < kW / 2; ++x) EXPECT_EQ(px(out, x, 2), px(color, x, 2)) << x;
}

TEST(GapsOverlaps, GapsProduceTheSubstrateColour) {
    const ImageF color = two_colours({0.8f, 0.1f, 0.1f}, {0.1f, 0.2f, 0.7f});
    ImageF out;
    gaps_overlaps(out, color, ramp_edges(), ctrl_b(-1.0f), nullptr, kPaper, {});
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const glm::vec4 o = px(out, x, y);
            if (x >= 4 && x <= 11) {
                EXPECT_EQ(o, glm::vec4(kPaper, 1.0f)) << x;
            } else {
                EXPECT_EQ(o, px(color, x, y)) << x;
            }
        }
}

TEST(GapsOverlaps, SmallGapControlOpensOnlyTheDirectEdge) {
    // p = -0.1 * 5 = -0.5 (|p| > 0.1 but < 1 step): only E > 2/m = 0.4 becomes a gap.
    const ImageF color = two_colours({0.8f, 0.1f, 0.1f}, {0.1f, 0.2f, 0.7f});
    ImageF out;
    gaps_overlaps(out, color, ramp_edges(), ctrl_b(-0.1f), nullptr, kPaper, {});
    for (int x = 0; x < kW; ++x) {
        const bool gap = px(out, x, 1) == glm::vec4(kPaper, 1.0f);
        EXPECT_EQ(gap, x >= 6 && x <= 9) << x;
    }
}

TEST(GapsOverlaps, TransparentGapsZeroAlphaAndKeepColour) {
    const ImageF color = two_colours({0.8f, 0.1f, 0.1f}, {0.1f, 0.2f, 0.7f});
    GapsOverlapsParams p;
    p.transparent_gaps = true;
    ImageF out;
    gaps_overlaps(out, color, ramp_edges(), ctrl_b(-1.0f), nullptr, kPaper, p);
    for (int x = 0; x < kW; ++x) {
        const glm::vec4 o = px(out, x, 0), c = px(color, x, 0);
        EXPECT_EQ(glm::vec3(o), glm::vec3(c));
        EXPECT_EQ(o.a, (x >= 4 && x <= 11) ? 0.0f : 1.0f) << x;
    }
}

TEST(GapsOverlaps, BledAndUnpaintedPixelsAreLeftAlone) {
    ImageF color = two_colours(kYellow, kBlue);
    ImageF bleed(kW, kH, 1, 0.5f);
    ImageF out;
    gaps_overlaps(out, color, ramp_edges(), ctrl_b(1.0f), &bleed, kPaper, {});
    EXPECT_TRUE(out == color);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) color.at(x, y, 3) = 0.05f;
    gaps_overlaps(out, color, ramp_edges(), ctrl_b(-1.0f), nullptr, kPaper, {});
    EXPECT_TRUE(out == color);
}

TEST(GapsOverlaps, TraversalsAgreeAndNonFiniteInputsDoNotCrash) {
    const int w = 80, h = 70;
    const ImageF color = testb::poison(noise(w, h, 4, 0.0f, 1.0f, 71), 9);
    const ImageF edges = testb::poison(noise(w, h, 1, 0.0f, 1.0f, 72), 7);
    const ImageF ctrl = testb::poison(noise(w, h, 4, -1.0f, 1.0f, 73), 11);
    GapsOverlapsParams p;
    p.steps = 16;
    p.border = Border::Mirror;
    ImageF a, b;
    gaps_overlaps(a, color, edges, ctrl, nullptr, kPaper, p, Exec::reference());
    gaps_overlaps(b, color, edges, ctrl, nullptr, kPaper, p, Exec::fast(2));
    EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.num_values() * sizeof(float)));
}

// Frames are mostly inactive (no edges, no coverage): with such runs (no edges over x in
// [60, 140), no coverage over [140, 210)), active pixels on both sides of them and a run of faint
// edges only (x < 60), the fast traversal gives the reference's bits.
TEST(GapsOverlaps, TraversalsAgreeWithInactiveChunks) {
    const int w = 230, h = 9;
    ImageF color = testb::poison(noise(w, h, 4, 0.0f, 1.0f, 81), 13);
    ImageF edges = noise(w, h, 1, 0.0f, 1.0f, 82);
    const ImageF ctrl = noise(w, h, 4, -1.0f, 1.0f, 83);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < 60; ++x) edges.at(x, y, 0) *= 0.3f;  // faint: just above the threshold
        for (int x = 60; x < 140; ++x) edges.at(x, y, 0) = 0.0f;
        for (int x = 140; x < 210; ++x) color.at(x, y, 3) = 0.0f;
    }
    for (const float b : {-1.0f, 1.0f}) {
        ImageF c = ctrl;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) c.at(x, y, 2) = b * std::fabs(c.at(x, y, 2));  // gaps, then overlaps
        ImageF a, f;
        gaps_overlaps(a, color, edges, c, nullptr, kPaper, {}, Exec::reference());
        gaps_overlaps(f, color, edges, c, nullptr, kPaper, {}, Exec::fast(2));
        EXPECT_EQ(0, std::memcmp(a.data(), f.data(), a.num_values() * sizeof(float))) << b;
        EXPECT_FALSE(a == color) << b;  // some pixels change
        int changed_faint = 0;  // among the faint edges, alone in their chunk
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < 60; ++x)
                for (int ch = 0; ch < 4; ++ch) changed_faint += std::memcmp(&a.at(x, y, ch), &color.at(x, y, ch), 4) != 0;
        EXPECT_GT(changed_faint, 0) << b;
    }
}

// The fast traversal tests eight pixels at a time, the bleeding mask resampled eight at a time
// (Resampler::sample8): with a mask around the threshold at full and half size, one channel or
// four (alpha), a width that is no multiple of eight, gaps and overlaps, separate images and in
// place, it gives the reference's bits; and the mask does hold some pixels back (fails when the
// lanes' bleeding test is dropped).
TEST(GapsOverlaps, TraversalsAgreeWithABleedingMaskAtFullAndHalfSize) {
    const int w = 83, h = 21;
    const ImageF color = noise(w, h, 4, 0.2f, 1.0f, 101);
    const ImageF edges = noise(w, h, 1, 0.0f, 1.0f, 102);
    for (const int half : {0, 1})
        for (const int channels : {1, 4})
            for (const float b : {-1.0f, 1.0f}) {
                const ImageF mask = noise(half ? (w + 1) / 2 : w, half ? (h + 1) / 2 : h, channels, 0.0f, 0.02f, 103);
                ImageF ctrl = noise(w, h, 4, 0.0f, 1.0f, 104);
                for (int y = 0; y < h; ++y)
                    for (int x = 0; x < w; ++x) ctrl.at(x, y, 2) *= b;
                ImageF ref, fast, unmasked;
                gaps_overlaps(ref, color, edges, ctrl, &mask, kPaper, {}, Exec::reference());
                gaps_overlaps(fast, color, edges, ctrl, &mask, kPaper, {}, Exec::fast(2));
                EXPECT_EQ(0, std::memcmp(ref.data(), fast.data(), ref.num_values() * sizeof(float)))
                    << "half " << half << " channels " << channels << " b " << b;
                ImageF in_place = color;
                gaps_overlaps(in_place, in_place, edges, ctrl, &mask, kPaper, {}, Exec::fast(2));
                EXPECT_EQ(0, std::memcmp(ref.data(), in_place.data(), ref.num_values() * sizeof(float)))
                    << "in place, half " << half << " channels " << channels << " b " << b;
                gaps_overlaps(unmasked, color, edges, ctrl, nullptr, kPaper, {}, Exec::reference());
                EXPECT_FALSE(unmasked == ref) << "the mask changes nothing: half " << half << " b " << b;
            }
}

// The fast traversal marches gaps eight pixels at a time, its bilinear taps gathered, and samples a
// lane whose footprint leaves the image by the border rule: faint edges inside (no tap above 1/m,
// no direct edge, random gradients) and strong ones on the image's outer ring, 16-step marches, so
// many marches leave the image before they meet the ring: clamp and mirror, the reference's bits,
// and some pixels far from the ring become gaps (fails when the outside lanes are mis-sampled).
TEST(GapsOverlaps, TraversalsAgreeWhereGapMarchesLeaveTheImage) {
    const int w = 48, h = 40;
    const ImageF color = noise(w, h, 4, 0.2f, 1.0f, 111);
    ImageF edges = noise(w, h, 1, 0.051f, 0.062f, 112);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            if (x == 0 || y == 0 || x == w - 1 || y == h - 1) edges.at(x, y, 0) = 0.5f;
    GapsOverlapsParams p;
    p.steps = 16;
    p.edge_threshold = 0.05f;
    for (const Border border : {Border::Clamp, Border::Mirror}) {
        p.border = border;
        ImageF ref, fast;
        gaps_overlaps(ref, color, edges, ctrl_b(-1.0f, w, h), nullptr, kPaper, p, Exec::reference());
        gaps_overlaps(fast, color, edges, ctrl_b(-1.0f, w, h), nullptr, kPaper, p, Exec::fast(2));
        EXPECT_EQ(0, std::memcmp(ref.data(), fast.data(), ref.num_values() * sizeof(float))) << "border " << int(border);
        int inner_gaps = 0;
        for (int y = 4; y < h - 4; ++y)
            for (int x = 4; x < w - 4; ++x) inner_gaps += std::memcmp(&ref.data()[(std::size_t(y) * w + x) * 4], &color.data()[(std::size_t(y) * w + x) * 4], 16) != 0;
        EXPECT_GT(inner_gaps, 0) << "border " << int(border);
    }
}

// The fast traversal copies 64-pixel chunks whose extended edges are nowhere above the threshold,
// testing eight edges at a time: one edge pixel per chunk, first, second, last and in a partial
// last chunk, gaps and overlaps: the reference's bits, and the gaps open there (fails when the
// test misses a pixel of the chunk).
TEST(GapsOverlaps, ChunksWithOneEdgePixelAreNotCopied) {
    const int w = 64 * 3 + 5, h = 7;
    const ImageF color = noise(w, h, 4, 0.2f, 1.0f, 91);
    ImageF edges(w, h, 1, 0.0f);
    const int at[] = {0, 64 + 1, 2 * 64 - 1, 3 * 64 + 3};
    for (int y = 0; y < h; ++y)
        for (int x : at) edges.at(x, y, 0) = 0.9f;
    for (const float b : {-1.0f, 1.0f}) {
        ImageF a, f;
        gaps_overlaps(a, color, edges, ctrl_b(b, w, h), nullptr, kPaper, {}, Exec::reference());
        gaps_overlaps(f, color, edges, ctrl_b(b, w, h), nullptr, kPaper, {}, Exec::fast(2));
        EXPECT_EQ(0, std::memcmp(a.data(), f.data(), a.num_values() * sizeof(float))) << b;
        if (b < 0.0f) {  // a lone edge above 2/m is a gap (an overlap needs a gradient)
            for (int x : at)
                EXPECT_NE(std::memcmp(&a.data()[(3 * w + x) * 4], &color.data()[(3 * w + x) * 4], 16), 0) << "at " << x;
        }
    }
}

TEST(GapsOverlaps, ChecksInputs) {
    const ImageF color = two_colours(kYellow, kBlue);
    ImageF out;
    try {
        gaps_overlaps(out, color, ramp_edges(), ImageF(kW, kH, 2), nullptr, kPaper, {});
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("'ctrl_edge'"), std::string::npos) << e.what();
    }
    GapsOverlapsParams bad;
    bad.steps = 0;
    EXPECT_THROW(gaps_overlaps(out, color, ramp_edges(), ctrl_b(1.0f), nullptr, kPaper, bad), Error);
}

}  // namespace
}  // namespace aq::stylize
