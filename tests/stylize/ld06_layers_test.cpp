// tests/stylize/ld06_layers_test.cpp — LD06 part 2 stages (issue 12; docs/ld06.md "Layers"):
// id_layers splits IDs into four layers (fold packs the rest), layer_wash's shape / edge darkening /
// automatic level of detail / variants, color_ramp's Gooch ends, glaze's two compositing rules,
// shadow_layer and stroke_ink leaving the picture alone where there is nothing to paint. Expected
// values come from the spec's formulas evaluated here, not from the implementation's output.
#include <cmath>
#include <algorithm>
#include <array>
#include <cstring>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "stylize/paper.h"
#include "stylize/stages/color_ramp.h"
#include "stylize/stages/glaze.h"
#include "stylize/stages/id_layers.h"
#include "stylize/stages/layer_wash.h"
#include "stylize/stages/shadow_layer.h"
#include "stylize/stages/stroke_ink.h"

namespace aq::stylize {
namespace {

ImageF disk(int w, int h, float cx, float cy, float r) {
    ImageF img(w, h, 1, 0.0f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            if (std::hypot(x + 0.5f - cx, y + 0.5f - cy) < r) img.at(x, y, 0) = 1.0f;
    return img;
}

TEST(IdLayers, SplitsIdsIntoFourLayersAndFoldsTheRest) {
    ImageF ids(9, 1, 1);
    const float v[9] = {0, 1, 2, 3, 4, 5, 6, 2.4f, 0.3f};  // 0 = background; id n = layer n - 1
    for (int x = 0; x < 9; ++x) ids.at(x, 0, 0) = v[x];
    for (bool fold : {true, false}) {
        ImageF o[4];
        ImageF* out[4] = {&o[0], &o[1], &o[2], &o[3]};
        IdLayersParams p;
        p.first = 1;  // layers 1..4 = ids 2..5
        p.fold = fold;
        id_layers(out, ids, p, Exec::reference());
        // expected slot per pixel: id 2 -> 0, 3 -> 1, 4 -> 2, 5 -> 3, 6 -> 3 (fold) or none
        const int slot[9] = {-1, -1, 0, 1, 2, 3, fold ? 3 : -1, 0, -1};
        for (int x = 0; x < 9; ++x)
            for (int k = 0; k < 4; ++k) EXPECT_EQ(o[k].at(x, 0, 0), slot[x] == k ? 1.0f : 0.0f) << "x " << x << " k " << k;
    }
}

LayerWashParams flat_wash() {
    LayerWashParams p;
    p.shape.border = 0;
    p.shape.granulation = 0;
    return p;
}

TEST(LayerWash, FullLayerIsOneFullWashAndAbsentLayersAreEmpty) {
    const ImageF full(40, 30, 1, 1.0f);
    const ImageF* layers[4] = {&full, nullptr, nullptr, nullptr};
    ImageF o;
    layer_wash(o, layers, nullptr, 40, 30, flat_wash(), Exec::reference());
    ASSERT_EQ(o.channels(), 4);
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x) {
            ASSERT_EQ(o.at(x, y, 0), 1.0f);  // ρ = 1 exactly (delta-form blur), a = 1, e = 0
            for (int k = 1; k < 4; ++k) ASSERT_EQ(o.at(x, y, k), 0.0f);
        }
}

TEST(LayerWash, EdgesAreDarkerThanTheInteriorAndNothingOutside) {
    const ImageF d = disk(96, 96, 48, 48, 30);
    const ImageF* layers[4] = {&d, nullptr, nullptr, nullptr};
    ImageF o;
    layer_wash(o, layers, nullptr, 96, 96, flat_wash(), Exec::fast(2));
    EXPECT_NEAR(o.at(48, 48, 0), 1.0f, 1e-5);      // deep inside: a full wash, no edge term
    EXPECT_GT(o.at(48 + 27, 48, 0), 1.15f);        // just inside the border: pigment gathers
    EXPECT_EQ(o.at(48 + 40, 48, 0), 0.0f);         // outside the blurred border: nothing
    EXPECT_EQ(o.at(2, 2, 0), 0.0f);
}

TEST(LayerWash, WetOnWetBorderIsWiderThanWetOnDry) {
    const ImageF d = disk(96, 96, 48, 48, 30);
    const ImageF* layers[4] = {&d, nullptr, nullptr, nullptr};
    auto band = [&](float width) {
        LayerWashParams p = flat_wash();
        p.shape.width = width;
        p.shape.edge = 0;
        ImageF o;
        layer_wash(o, layers, nullptr, 96, 96, p, Exec::reference());
        int n = 0;
        for (int y = 0; y < 96; ++y)
            for (int x = 0; x < 96; ++x) n += o.at(x, y, 0) > 0.05f && o.at(x, y, 0) < 0.95f;
        return n;
    };
    EXPECT_GT(band(0.5f), 2 * band(0.05f));
}

TEST(LayerWash, SmallShapesFadeBelowTheKernelSize) {
    // LD06 §4.3 automatic level of detail: a 2-pixel detail vanishes under the blur, a big shape stays.
    ImageF d = disk(64, 64, 44, 32, 14);
    d.at(10, 10, 0) = d.at(11, 10, 0) = d.at(10, 11, 0) = d.at(11, 11, 0) = 1.0f;
    const ImageF* layers[4] = {&d, nullptr, nullptr, nullptr};
    LayerWashParams p = flat_wash();
    p.shape.edge = 0;
    ImageF o;
    layer_wash(o, layers, nullptr, 64, 64, p, Exec::reference());
    float small = 0;
    for (int y = 5; y < 17; ++y)
        for (int x = 5; x < 17; ++x) small = std::max(small, o.at(x, y, 0));
    EXPECT_EQ(small, 0.0f);
    EXPECT_NEAR(o.at(44, 32, 0), 1.0f, 1e-5);
}

TEST(LayerWash, AdditiveEdgePaintsThinLinesTheMultiplicativeOneDrops) {
    ImageF d(64, 64, 1, 0.0f);
    for (int y = 10; y < 54; ++y) d.at(32, y, 0) = 1.0f;  // a 1-pixel line: ρ stays far below κ
    const ImageF* layers[4] = {&d, nullptr, nullptr, nullptr};
    LayerWashParams p = flat_wash();
    ImageF mul, add;
    layer_wash(mul, layers, nullptr, 64, 64, p, Exec::reference());
    p.shape.additive_edge = true;
    layer_wash(add, layers, nullptr, 64, 64, p, Exec::reference());
    EXPECT_EQ(mul.at(32, 32, 0), 0.0f);
    EXPECT_GT(add.at(32, 32, 0), 0.5f);
}

TEST(LayerWash, GranulationPutsMorePigmentInPaperValleys) {
    const ImageF full(8, 8, 1, 1.0f);
    const ImageF* layers[4] = {&full, nullptr, nullptr, nullptr};
    ImageF paper(8, 8, 3, 0.5f);
    paper.at(1, 1, 2) = 0.0f;  // valley
    paper.at(5, 5, 2) = 1.0f;  // ridge
    LayerWashParams p;
    p.shape.border = 0;
    ImageF o;
    layer_wash(o, layers, &paper, 8, 8, p, Exec::reference());
    EXPECT_FLOAT_EQ(o.at(1, 1, 0), 1.0f + p.shape.granulation);
    EXPECT_FLOAT_EQ(o.at(5, 5, 0), 1.0f - p.shape.granulation);
    EXPECT_FLOAT_EQ(o.at(3, 3, 0), 1.0f);
}

TEST(LayerWash, ResamplesIntermediatesToTheOutputSize) {
    const ImageF d = disk(52, 52, 26, 26, 15);
    const ImageF* layers[4] = {&d, &d, nullptr, nullptr};
    ImageF r, f;
    layer_wash(r, layers, nullptr, 72, 72, flat_wash(), Exec::reference());
    layer_wash(f, layers, nullptr, 72, 72, flat_wash(), Exec::fast(2));
    ASSERT_EQ(r.width(), 72);
    ASSERT_EQ(0, std::memcmp(r.data(), f.data(), r.num_values() * sizeof(float)));
    EXPECT_NEAR(r.at(36, 36, 1), 1.0f, 1e-5);
    EXPECT_THROW(layer_wash(r, layers, nullptr, 0, 72, flat_wash()), Error);
    const ImageF other(10, 10, 1, 1.0f);
    const ImageF* bad[4] = {&d, &other, nullptr, nullptr};
    EXPECT_THROW(layer_wash(r, bad, nullptr, 72, 72, flat_wash()), Error);
}

TEST(LayerWash, EmptyLayersAreSkippedWithTheSameBytes) {
    // An empty slot of an ID pack is skipped by the fast schedule only when it provably washes to
    // 0; with a border lift above κ - w it is not (the paper alone raises ρ'), and both schedules agree.
    const ImageF d = disk(52, 52, 26, 26, 15), none(52, 52, 1, 0.0f);
    ImageF paper(72, 72, 3, 0.5f);
    for (int y = 0; y < 72; ++y)
        for (int x = 0; x < 72; ++x) paper.at(x, y, 2) = float((x * 7 + y * 13) % 11) / 10.0f;
    const ImageF* layers[4] = {&none, &d, &none, &none};
    for (float border : {0.3f, 1.8f}) {
        LayerWashParams p;
        p.shape.border = border;
        ImageF r, f;
        layer_wash(r, layers, &paper, 72, 72, p, Exec::reference());
        layer_wash(f, layers, &paper, 72, 72, p, Exec::fast(2));
        ASSERT_EQ(0, std::memcmp(r.data(), f.data(), r.num_values() * sizeof(float))) << "border " << border;
        float empty_max = 0;
        for (int y = 0; y < 72; ++y)
            for (int x = 0; x < 72; ++x) empty_max = std::max(empty_max, r.at(x, y, 0));
        if (border < 0.5f) EXPECT_EQ(empty_max, 0.0f);
        else EXPECT_GT(empty_max, 0.0f) << "a large border lift paints the paper's ridges even without pigment";
    }
    // A NaN paper height: the empty layer is never provably 0, so nothing is skipped; both
    // schedules agree bit for bit (NaN included).
    paper.at(40, 41, 2) = std::numeric_limits<float>::quiet_NaN();
    LayerWashParams p;
    ImageF r, f;
    layer_wash(r, layers, &paper, 72, 72, p, Exec::reference());
    layer_wash(f, layers, &paper, 72, 72, p, Exec::fast(2));
    ASSERT_EQ(0, std::memcmp(r.data(), f.data(), r.num_values() * sizeof(float))) << "NaN paper";
    // The spread a pipeline run computes once and hands in gives the same bytes.
    layer_wash(f, layers, &paper, 72, 72, p, Exec::fast(2), paper_height_spread(paper));
    ASSERT_EQ(0, std::memcmp(r.data(), f.data(), r.num_values() * sizeof(float))) << "NaN paper, spread given";
}

TEST(Paper, HeightSpreadIsTheMaximumDistanceFromOneHalf) {
    // Against the plain definition: max |h - 1/2| over the height channel (the other channels are
    // ignored), NaN when a height is NaN, infinite for an infinite height; any traversal.
    for (int channels : {3, 4}) {
        ImageF paper(37, 23, channels, 0.5f);
        for (int y = 0; y < 23; ++y)
            for (int x = 0; x < 37; ++x) {
                paper.at(x, y, 2) = float((x * 7 + y * 13) % 17) / 20.0f;  // 0 .. 0.8
                paper.at(x, y, 0) = 9.0f;                                 // not a height
            }
        paper.at(30, 20, 2) = -0.25f;  // |h - 1/2| = 0.75, the maximum
        double want = 0;
        for (int y = 0; y < 23; ++y)
            for (int x = 0; x < 37; ++x) want = std::max(want, std::abs(double(paper.at(x, y, 2)) - 0.5));
        for (const Exec& ex : {Exec::reference(), Exec::fast(1), Exec::fast(2), Exec::fast(8)}) {
            EXPECT_EQ(paper_height_spread(paper, ex), float(want));
            ImageF p2 = paper;
            p2.at(3, 17, 2) = std::numeric_limits<float>::infinity();
            EXPECT_EQ(paper_height_spread(p2, ex), std::numeric_limits<float>::infinity());
            p2.at(36, 0, 2) = std::numeric_limits<float>::quiet_NaN();
            EXPECT_TRUE(std::isnan(paper_height_spread(p2, ex)));
        }
    }
}

TEST(ColorRamp, GoochEndsAndAlpha) {
    ImageF light(3, 1, 1);
    light.at(0, 0, 0) = 0.0f, light.at(1, 0, 0) = 1.0f, light.at(2, 0, 0) = 0.5f;
    ColorRampParams p;
    p.hue.cool = {0.0f, 0.0f, 0.4f};
    p.hue.warm = {0.4f, 0.4f, 0.0f};
    p.hue.cool_mix = 0.2f;
    p.hue.warm_mix = 0.6f;
    p.hue.keep_hue = 0.0f;  // Gooch's additive shift on every colour
    p.layer[2] = {{0.5f, 0.6f, 0.2f}, {0.1f, 0.2f, 0.05f}, 0.7f, 1.0f};
    ImageF o[4];
    ImageF* out[4] = {&o[0], &o[1], &o[2], &o[3]};
    color_ramp(out, light, p, Exec::reference());
    // t = 0: k_cool = cool + 0.2 dark; t = 1: k_warm = warm + 0.6 colour (Gooch et al. 1998).
    const float cool[3] = {0.0f + 0.2f * 0.1f, 0.0f + 0.2f * 0.2f, 0.4f + 0.2f * 0.05f};
    const float warm[3] = {0.4f + 0.6f * 0.5f, 0.4f + 0.6f * 0.6f, 0.0f + 0.6f * 0.2f};
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(o[2].at(0, 0, c), cool[c], 1e-6);
        EXPECT_NEAR(o[2].at(1, 0, c), warm[c], 1e-6);
    }
    EXPECT_EQ(o[2].at(2, 0, 3), 0.7f);
    // t = 0.5: halfway between the two ends of a ramp whose object colour is itself halfway.
    const float mid_obj_r = 0.5f * (0.1f + 0.5f);
    EXPECT_NEAR(o[2].at(2, 0, 0), 0.5f * (0.2f * mid_obj_r) + 0.5f * (0.4f + 0.6f * mid_obj_r), 1e-6);
}

// keep_hue (issue 46 item 4): the cool/warm shift is weighted by 1 - keep_hue x saturation. A grey
// ramp gets the whole shift; a fully saturated one (a zero channel) none, so its hue is the object
// colour's at every t; halfway saturation gets half.
TEST(ColorRamp, KeepHueFadesTheShiftWithSaturation) {
    ImageF light(3, 1, 1);
    light.at(0, 0, 0) = 0.0f, light.at(1, 0, 0) = 1.0f, light.at(2, 0, 0) = 0.5f;
    ColorRampParams p;  // defaults: cool (0, 0, b), warm (b, b, 0) with b = kRampCoolWarm, 0.8 / 1.0, keep_hue 1
    ASSERT_EQ(p.hue.keep_hue, 1.0f);
    p.layer[0] = {{0.5f, 0.5f, 0.5f}, {0.25f, 0.25f, 0.25f}, 1.0f, 1.0f};  // grey
    p.layer[1] = {{0.8f, 0.0f, 0.1f}, {0.4f, 0.0f, 0.05f}, 1.0f, 1.0f};   // saturated red
    p.layer[2] = {{0.8f, 0.4f, 0.4f}, {0.8f, 0.4f, 0.4f}, 1.0f, 1.0f};    // saturation 1/2
    ImageF o[4];
    ImageF* out[4] = {&o[0], &o[1], &o[2], &o[3]};
    color_ramp(out, light, p, Exec::reference());
    constexpr float b = kRampCoolWarm;
    EXPECT_NEAR(o[0].at(0, 0, 2), b + 0.8f * 0.25f, 1e-6) << "grey: the full cool shift";
    EXPECT_NEAR(o[0].at(1, 0, 0), b + 1.0f * 0.5f, 1e-6) << "grey: the full warm shift";
    for (int x = 0; x < 3; ++x) {
        EXPECT_EQ(o[1].at(x, 0, 1), 0.0f) << "saturated: no shift added to its empty channel";
        EXPECT_NEAR(o[1].at(x, 0, 2) / o[1].at(x, 0, 0), 0.1f / 0.8f, 1e-5) << "saturated: channel ratios (hue) kept";
    }
    EXPECT_NEAR(o[2].at(1, 0, 1), 0.5f * b + 0.4f, 1e-6) << "half saturated: half the warm shift";
    p.hue.keep_hue = 0.0f;  // Gooch: the shift everywhere
    color_ramp(out, light, p, Exec::reference());
    EXPECT_NEAR(o[1].at(1, 0, 1), b, 1e-6);
}

TEST(Glaze, ZeroWashKeepsThePictureAndFullWashMultiplies) {
    const int w = 6, h = 4;
    ImageF base(w, h, 4, 0.8f), wash(w, h, 4, 0.0f), ramp(w, h, 4);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            ramp.at(x, y, 0) = 0.5f, ramp.at(x, y, 1) = 0.25f, ramp.at(x, y, 2) = 1.0f, ramp.at(x, y, 3) = 1.0f;
        }
    const ImageF* ramps[4] = {&ramp, &ramp, &ramp, &ramp};
    ImageF o;
    glaze(o, &base, wash, ramps, glm::vec3(1.0f), true, Exec::reference());
    for (int c = 0; c < 3; ++c) EXPECT_EQ(o.at(2, 2, c), 0.8f);
    EXPECT_EQ(o.at(2, 2, 3), 1.0f);
    wash.at(2, 2, 1) = 1.0f;  // one full layer: dst * c
    glaze(o, &base, wash, ramps, glm::vec3(1.0f), true, Exec::reference());
    EXPECT_FLOAT_EQ(o.at(2, 2, 0), 0.8f * 0.5f);
    EXPECT_FLOAT_EQ(o.at(2, 2, 1), 0.8f * 0.25f);
    EXPECT_FLOAT_EQ(o.at(2, 2, 2), 0.8f);
    // No picture yet: glazed over the paper colour.
    glaze(o, nullptr, wash, ramps, glm::vec3(0.9f, 0.8f, 0.7f), true, Exec::reference());
    EXPECT_FLOAT_EQ(o.at(2, 2, 0), 0.9f * 0.5f);
    EXPECT_FLOAT_EQ(o.at(0, 0, 2), 0.7f);
}

TEST(Glaze, LayersWithoutWashAreSkippedWithTheSameBytes) {
    // Wash only in layer 1 (an ID pack with empty slots); ramps at another size (resampled). The
    // fast schedule skips the empty multiplicative layers; a NaN in an empty layer's ramp must not
    // be skipped (it poisons the product in the plain loop too).
    const int w = 37, h = 23;
    ImageF base(w, h, 4), wash(w, h, 4, 0.0f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            for (int c = 0; c < 4; ++c) base.at(x, y, c) = 0.2f + 0.6f * float((x * 3 + y * 5 + c) % 7) / 7.0f;
            wash.at(x, y, 1) = float((x + 2 * y) % 9) / 6.0f;
        }
    ImageF r[4];
    for (int k = 0; k < 4; ++k) {
        r[k] = ImageF(19, 11, 4);
        for (int y = 0; y < 11; ++y)
            for (int x = 0; x < 19; ++x)
                for (int c = 0; c < 4; ++c) r[k].at(x, y, c) = float((x * (k + 1) + y + c) % 5) / 4.0f;
    }
    const ImageF* ramps[4] = {&r[0], &r[1], &r[2], &r[3]};
    for (bool poison : {false, true}) {
        if (poison) r[3].at(4, 4, 0) = std::numeric_limits<float>::quiet_NaN();
        for (bool mul : {true, false}) {
            ImageF ref, fast;
            glaze(ref, &base, wash, ramps, glm::vec3(1.0f), mul, Exec::reference());
            glaze(fast, &base, wash, ramps, glm::vec3(1.0f), mul, Exec::fast(2));
            ASSERT_EQ(0, std::memcmp(ref.data(), fast.data(), ref.num_values() * sizeof(float))) << "mul " << mul << " poison " << poison;
        }
    }
}

// The fast schedule also skips a multiplicative layer in each row where its wash is 0, when the
// ramp texels that row lerps lie within the skip bound: rows of zero wash next to painted rows,
// and ramps holding a NaN, an infinity or huge opposite values (whose lerp overflows) in some rows,
// where the layer must not be skipped. Every case: the plain loop's bytes, at 1, 2 and 8 threads.
TEST(Glaze, LayersAreSkippedRowByRowWhereTheirWashIsZeroWithTheSameBytes) {
    const int w = 41, h = 29;
    ImageF base(w, h, 4), wash(w, h, 4, 0.0f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            for (int c = 0; c < 4; ++c) base.at(x, y, c) = 0.1f + 0.8f * float((x * 5 + y * 3 + c) % 9) / 9.0f;
            for (int k = 0; k < 4; ++k)  // layer k painted in a band of rows only
                if (y >= 4 * k && y < 4 * k + 9 && (x + k) % 3 != 0) wash.at(x, y, k) = float((x + y + k) % 7) / 5.0f;
        }
    wash.at(7, 20, 2) = -0.0f;  // -0 counts as no wash
    const float poisons[] = {0.0f, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(), 3e38f};
    for (float poison : poisons) {
        ImageF r[4];
        for (int k = 0; k < 4; ++k) {
            r[k] = ImageF(21, 15, 4);
            for (int y = 0; y < 15; ++y)
                for (int x = 0; x < 21; ++x)
                    for (int c = 0; c < 4; ++c) r[k].at(x, y, c) = float((x * (k + 2) + y + c) % 6) / 5.0f;
        }
        if (poison != 0.0f) {
            r[1].at(3, 12, 0) = poison;  // a row where layer 1 has no wash
            r[2].at(10, 1, 3) = poison;
            if (poison == 3e38f) r[2].at(11, 1, 3) = -3e38f;  // lerps to an infinity
        }
        const ImageF* ramps[4] = {&r[0], &r[1], &r[2], &r[3]};
        ImageF ref;
        glaze(ref, &base, wash, ramps, glm::vec3(1.0f), true, Exec::reference());
        for (int threads : {1, 2, 8}) {
            ImageF fast;
            glaze(fast, &base, wash, ramps, glm::vec3(1.0f), true, Exec::fast(threads));
            ASSERT_EQ(0, std::memcmp(ref.data(), fast.data(), ref.num_values() * sizeof(float)))
                << "poison " << poison << ", " << threads << " threads";
        }
    }
}

TEST(Glaze, OverPaintsBackToFrontTheLastLayerOnTop) {
    const int w = 2, h = 2;
    ImageF base(w, h, 4, 1.0f), wash(w, h, 4, 1.0f), r0(w, h, 4), r3(w, h, 4);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 4; ++c) {
                r0.at(x, y, c) = c == 3 ? 1.0f : 0.2f;
                r3.at(x, y, c) = c == 3 ? 1.0f : 0.7f;
            }
    const ImageF* ramps[4] = {&r0, &r0, &r0, &r3};
    ImageF o;
    glaze(o, &base, wash, ramps, glm::vec3(1.0f), false, Exec::reference());
    EXPECT_FLOAT_EQ(o.at(1, 1, 0), 0.7f);
    glaze(o, &base, wash, ramps, glm::vec3(1.0f), true, Exec::reference());
    EXPECT_NEAR(o.at(1, 1, 0), 0.2f * 0.2f * 0.2f * 0.7f, 1e-7);
}

// Rows without shadow keep the picture exactly (multiplicative: a factor of exactly 1), and every
// case — a shadowed band, rows without shadow, NaN and -0 in the picture, both variants — has the
// plain loop's bytes on every traversal.
TEST(ShadowLayer, RowsWithoutShadowKeepThePictureOnEveryTraversal) {
    const int w = 37, h = 31;
    ImageF color(w, h, 4), shadow(26, 22, 1, 0.0f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 4; ++c) color.at(x, y, c) = 0.05f + 0.03f * float((x * 3 + y + c) % 29);
    color.at(4, 2, 1) = std::numeric_limits<float>::quiet_NaN();
    color.at(6, 28, 0) = -0.0f;
    for (int y = 9; y < 14; ++y)
        for (int x = 5; x < 20; ++x) shadow.at(x, y, 0) = 1.0f;
    for (bool mul : {true, false}) {
        ImageF ref;
        shadow_layer(ref, color, shadow, nullptr, ShadowLayerParams{}, mul, Exec::reference());
        int unchanged_rows = 0;
        for (int y = 0; y < h; ++y)
            unchanged_rows += std::memcmp(&ref.at(0, y, 0), &color.at(0, y, 0), std::size_t(w) * 4 * sizeof(float)) == 0;
        if (mul) {
            EXPECT_GT(unchanged_rows, 3) << "rows without shadow keep the picture";
        }
        EXPECT_LT(unchanged_rows, h) << "the band is shadowed";
        for (int threads : {1, 2, 8}) {
            ImageF fast;
            shadow_layer(fast, color, shadow, nullptr, ShadowLayerParams{}, mul, Exec::fast(threads));
            ASSERT_EQ(0, std::memcmp(ref.data(), fast.data(), ref.num_values() * sizeof(float))) << "mul " << mul << ", " << threads;
        }
    }
}

TEST(ShadowLayerAndInk, NothingToPaintLeavesThePictureUnchanged) {
    ImageF color(30, 20, 4);
    for (int y = 0; y < 20; ++y)
        for (int x = 0; x < 30; ++x)
            for (int c = 0; c < 4; ++c) color.at(x, y, c) = 0.1f + 0.02f * float((x + y + c) % 30);
    const ImageF none(22, 15, 1, 0.0f);
    ImageF s, k;
    shadow_layer(s, color, none, nullptr, ShadowLayerParams{}, true, Exec::fast(2));
    stroke_ink(k, color, none, StrokeInkParams{}, Exec::fast(2));
    ASSERT_EQ(0, std::memcmp(s.data(), color.data(), color.num_values() * sizeof(float)));
    ASSERT_EQ(0, std::memcmp(k.data(), color.data(), color.num_values() * sizeof(float)));
    // Full shadow: every colour channel darkened towards the shadow colour, alpha kept.
    const ImageF full(22, 15, 1, 1.0f);
    shadow_layer(s, color, full, nullptr, ShadowLayerParams{}, true, Exec::reference());
    const ShadowLayerParams sp;
    for (int c = 0; c < 3; ++c)
        EXPECT_FLOAT_EQ(s.at(10, 10, c), color.at(10, 10, c) * (1.0f - sp.alpha * (1.0f - sp.color[c])));
    EXPECT_EQ(s.at(10, 10, 3), color.at(10, 10, 3));
    // Full ink at alpha 1: the ink colour.
    StrokeInkParams ip;
    ip.alpha = 1.0f;
    stroke_ink(k, color, full, ip, Exec::reference());
    for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(k.at(5, 5, c), ip.color[c]);
}

// In place (the pipeline hands stroke_ink one image as colour and output): only inked pixels are
// written, with the bytes of the run on separate images — also for -0, inf and NaN colours (kept
// exactly where the opacity is 0, sat(alpha * coverage) == 0: coverage 0, -0 or negative), NaN and
// partial coverage, a resampled ink map and widths that are not a multiple of 8.
TEST(ShadowLayerAndInk, InkInPlaceHasTheBytesOfInkOnSeparateImages) {
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    for (const auto& [w, h, iw, ih] : {std::array<int, 4>{37, 11, 37, 11}, {29, 9, 17, 6}, {64, 5, 64, 5}}) {
        ImageF color(w, h, 4);
        const float odd[5] = {-0.0f, inf, nan, -inf, 0.0f};
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                for (int c = 0; c < 4; ++c)
                    color.at(x, y, c) = (x + 3 * y + c) % 7 == 0 ? odd[(x + y + c) % 5] : 0.05f * float((x * 5 + y + c) % 19);
        ImageF ink(iw, ih, 1, 0.0f);
        const float cov[8] = {0.0f, -0.0f, -0.5f, 0.3f, 1.0f, 2.0f, nan, 0.0f};
        for (int y = 0; y < ih; ++y)
            for (int x = 0; x < iw; ++x)
                if ((x / 3 + y) % 4 == 1) ink.at(x, y, 0) = cov[(x + 2 * y) % 8];
        for (const Exec& ex : {Exec::reference(), Exec::fast(1), Exec::fast(2), Exec::fast(8)}) {
            ImageF separate;
            stroke_ink(separate, color, ink, StrokeInkParams{}, ex);
            ImageF in_place = color;
            stroke_ink(in_place, in_place, ink, StrokeInkParams{}, ex);
            ASSERT_EQ(0, std::memcmp(separate.data(), in_place.data(), color.num_values() * sizeof(float))) << w << "x" << h;
            // Uninked pixels keep every bit (-0 included); inked ones change.
            int kept = 0, changed = 0;
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    const bool same = std::memcmp(&separate.at(x, y, 0), &color.at(x, y, 0), 4 * sizeof(float)) == 0;
                    kept += same, changed += !same;
                    if (iw == w && ih == h && ink.at(x, y, 0) <= 0.0f) {
                        EXPECT_TRUE(same) << x << "," << y;
                    }
                }
            EXPECT_GT(kept, w * h / 2);
            EXPECT_GT(changed, 0);
        }
    }
    ImageF ink(4, 4, 1, 1.0f);
    EXPECT_THROW(stroke_ink(ink, ImageF(4, 4, 4, 0.5f), ink, StrokeInkParams{}), Error) << "output over the ink";
}

}  // namespace
}  // namespace aq::stylize
