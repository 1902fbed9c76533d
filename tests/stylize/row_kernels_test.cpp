// tests/stylize/row_kernels_test.cpp — the vectorised row kernels of the pointwise stages (inputs
// gathered into arrays, exponents with selects, powers of the affected pixels packed) compute,
// value for value, the per-pixel functions that define the stages (edge_darken_rgbd_px,
// pigment_apply_wc18_px, the pigment_density formula). Inputs cover chunk tails, painted and
// unpainted pixels, uncovered pixels, dry-brush and granulation, and NaN/Inf.
#include <cmath>
#include <cstring>

#include <gtest/gtest.h>

#include "stylize/kernels.h"
#include "stylize/kernels.h"
#include "stylize/stages/edge_darken.h"
#include "stylize/stages/pigment_apply.h"
#include "stylize/stages/pigment_density.h"
#include "tests/stylize/stage_test_util.h"

namespace aq::stylize {
namespace {

using testb::noise;
using testb::poison;

//! Bit-equal, or both NaN (a NaN's payload is not part of the contract).
bool same(float a, float b) { return (std::isnan(a) && std::isnan(b)) || std::memcmp(&a, &b, sizeof a) == 0; }

void expect_pixel(const ImageF& out, int x, int y, glm::vec4 want, const char* what) {
    for (int c = 0; c < 4; ++c)
        ASSERT_TRUE(same(out.at(x, y, c), want[c]))
            << what << " at " << x << "," << y << " channel " << c << ": " << out.at(x, y, c) << " vs " << want[c];
}

glm::vec4 px4(const ImageF& img, int x, int y) {
    return {img.at(x, y, 0), img.at(x, y, 1), img.at(x, y, 2), img.at(x, y, 3)};
}

// Zero out a band so that unpainted / edge-free runs longer than a chunk exist too.
ImageF with_zero_band(ImageF img, int x0, int x1) {
    for (int y = 0; y < img.height(); ++y)
        for (int x = x0; x < x1 && x < img.width(); ++x)
            for (int c = 0; c < img.channels(); ++c) img.at(x, y, c) = 0.0f;
    return img;
}

constexpr int kW = 150, kH = 9;  // 150 = two 64-pixel chunks and a tail

TEST(RowKernels, EdgeDarkenRgbdEqualsPixelFunction) {
    const glm::vec3 sub(0.95f, 0.9f, 0.85f);
    for (bool bad : {false, true}) {
        ImageF color = noise(kW, kH, 4, -0.1f, 1.1f, 11);
        // Edges zero over [10, 140): the chunk [64, 128) has none (the stage copies such a chunk;
        // with `bad`, under NaN/Inf control and colour).
        ImageF edges = noise(kW, kH, 1, -0.2f, 1.0f, 12);
        ImageF ctrl = noise(kW, kH, 4, -1.0f, 1.0f, 13);
        if (bad) color = poison(color, 5), edges = poison(edges, 11), ctrl = poison(ctrl, 13);
        edges = with_zero_band(edges, 10, 140);
        for (int y = 0; y < kH; y += 2) edges.at(100, y, 0) = -0.0f;  // -0 is no edge either
        const ImageF bleed_full = noise(kW, kH, 1, 0.0f, 0.5f, 14);
        const ImageF bleed_half = noise((kW + 1) / 2, (kH + 1) / 2, 4, 0.0f, 0.5f, 15);
        const ImageF crowd = noise((kW + 3) / 4, (kH + 3) / 4, 1, 0.0f, 1.0f, 16);  // coarse: resampled
        for (float intensity : {1.0f, 3.5f}) {
            const EdgeDarkenRgbdParams p{intensity, intensity == 1.0f ? 0.0f : 2.5f};
            ImageF out, out_half, out_none;
            edge_darken_rgbd(out, color, edges, ctrl, &bleed_full, &crowd, sub, p, Exec::fast(2));
            edge_darken_rgbd(out_half, color, edges, ctrl, &bleed_half, nullptr, sub, p, Exec::fast(2));
            edge_darken_rgbd(out_none, color, edges, ctrl, nullptr, nullptr, sub, p, Exec::reference());
            const toolkit::Plane bh = toolkit::plane(bleed_half, 3);
            const toolkit::Resampler up(kW, kH, bleed_half.width(), bleed_half.height());
            const toolkit::Resampler upc(kW, kH, crowd.width(), crowd.height());
            const toolkit::Plane cp = toolkit::plane(crowd, 0);
            for (int y = 0; y < kH; ++y)
                for (int x = 0; x < kW; ++x) {
                    const glm::vec4 c = px4(color, x, y);
                    const float e = edges.at(x, y, 0), ci = ctrl.at(x, y, 0);
                    expect_pixel(out, x, y, edge_darken_rgbd_px(c, e, ci, bleed_full.at(x, y, 0), upc.sample(cp, x, y), sub, p),
                                 "full bleed, crowd");
                    expect_pixel(out_half, x, y, edge_darken_rgbd_px(c, e, ci, up.sample(bh, x, y), 0.0f, sub, p), "half bleed");
                    expect_pixel(out_none, x, y, edge_darken_rgbd_px(c, e, ci, 0.0f, 0.0f, sub, p), "no bleed");
                }
        }
    }
}

TEST(RowKernels, PigmentApplyWc18EqualsPixelFunction) {
    const glm::vec3 sub(1.0f, 0.97f, 0.9f);
    for (bool bad : {false, true}) {
        ImageF color = noise(kW, kH, 4, -0.05f, 1.05f, 21);
        for (int y = 0; y < kH; ++y)  // uncovered pixels (alpha below the mask) in runs and alone
            for (int x = 0; x < kW; ++x)
                if ((x > 60 && x < 140) || (x * 7 + y) % 13 == 0) color.at(x, y, 3) = 0.0f;  // [64, 128) all
        ImageF ctrl = noise(kW, kH, 4, -1.0f, 1.0f, 22);  // G < -H: dry-brush; else granulation
        ImageF paper = noise(kW, kH, 3, 0.0f, 1.0f, 23);
        if (bad) color = poison(color, 6), ctrl = poison(ctrl, 9), paper = poison(paper, 17);
        for (const PigmentApplyWc18Params& p :
             {PigmentApplyWc18Params{}, PigmentApplyWc18Params{12.0f, 40.0f, 2.5f, 0.6f}}) {
            ImageF out, out_flat;
            pigment_apply_wc18(out, color, ctrl, &paper, sub, p, Exec::fast(2));
            pigment_apply_wc18(out_flat, color, ctrl, nullptr, sub, p, Exec::reference());
            for (int y = 0; y < kH; ++y)
                for (int x = 0; x < kW; ++x) {
                    const glm::vec4 c = px4(color, x, y);
                    const float a = ctrl.at(x, y, 1);
                    expect_pixel(out, x, y, pigment_apply_wc18_px(c, paper.at(x, y, 2), a, sub, p), "paper");
                    expect_pixel(out_flat, x, y, pigment_apply_wc18_px(c, 0.5f, a, sub, p), "flat paper");
                }
        }
    }
}

TEST(RowKernels, PigmentDensityEqualsFormula) {
    const glm::vec3 sub(0.9f, 0.92f, 0.8f);
    for (bool bad : {false, true}) {
        ImageF color = noise(kW, kH, 4, -0.2f, 1.2f, 31);
        ImageF ctrl = with_zero_band(noise(kW, kH, 4, -1.0f, 1.0f, 32), 10, 100);  // d = 1 in a band
        if (bad) color = poison(color, 7), ctrl = poison(ctrl, 5);
        for (float strength : {1.0f, 2.5f}) {
            ImageF out;
            pigment_density(out, color, ctrl, sub, {strength}, Exec::fast(2));
            for (int y = 0; y < kH; ++y)
                for (int x = 0; x < kW; ++x) {
                    // spec §4.3: d = 1 + s * ctrl.b, c' = |c|^d, out = mix(substrate, c', sat(d))
                    const float d = 1.0f + strength * ctrl.at(x, y, 2);
                    glm::vec4 want;
                    for (int c = 0; c < 3; ++c) want[c] = mix(sub[c], pow_c(std::fabs(color.at(x, y, c)), d), sat(d));
                    want[3] = color.at(x, y, 3);
                    expect_pixel(out, x, y, want, "pigment_density");
                }
        }
    }
}

}  // namespace
}  // namespace aq::stylize
