// tests/stylize/adjust_test.cpp — spec §4.1: depth normalisation, background = substrate colour,
// colour operations; §4.3 pigment density.
#include <cmath>
#include <cstring>
#include <limits>

#include <gtest/gtest.h>

#include "stylize/stages/adjust.h"
#include "stylize/stages/pigment_density.h"

namespace aq::stylize {
namespace {

TEST(Adjust, NormalisesDepthWithMnprRangeUnclamped) {
    ImageF c(5, 1, 4, 1.0f), z(5, 1, 1);
    const float zs[5] = {8.0f, 50.0f, 29.0f, 92.0f, std::numeric_limits<float>::infinity()};
    for (int x = 0; x < 5; ++x) z.at(x, 0, 0) = zs[x];
    ImageF co, zo;
    adjust(co, zo, c, z, {1, 1, 1}, AdjustParams{}, Exec::reference());
    EXPECT_FLOAT_EQ(zo.at(0, 0, 0), 0.0f);
    EXPECT_FLOAT_EQ(zo.at(1, 0, 0), 1.0f);
    EXPECT_FLOAT_EQ(zo.at(2, 0, 0), 0.5f);
    EXPECT_FLOAT_EQ(zo.at(3, 0, 0), 2.0f);  // unclamped: (92 - 8) / 42
    EXPECT_FLOAT_EQ(zo.at(4, 0, 0), 1.0f);  // no geometry -> far
}

TEST(Adjust, BackgroundIsTheSubstrateColourAndCoveredColourIsKept) {
    ImageF c(2, 1, 4), z(2, 1, 1, 20.0f);
    const float col[4] = {0.25f, 0.5f, 0.75f, 1.0f};
    for (int k = 0; k < 4; ++k) c.at(0, 0, k) = col[k];
    for (int k = 0; k < 3; ++k) c.at(1, 0, k) = 0.3f;  // alpha 0: background
    ImageF co, zo;
    const glm::vec3 paper{0.9f, 0.85f, 0.8f};
    adjust(co, zo, c, z, paper, AdjustParams{}, Exec::reference());
    for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(co.at(1, 0, k), paper[k]) << "alpha 0 must give exactly the substrate colour";
        EXPECT_NEAR(co.at(0, 0, k), col[k], 1e-6f) << "neutral colour operations keep the colour";
    }
    EXPECT_EQ(co.at(0, 0, 3), 1.0f);
    EXPECT_EQ(co.at(1, 0, 3), 0.0f);
}

TEST(Adjust, ZeroSaturationGivesLuma) {
    ImageF c(1, 1, 4, 1.0f), z(1, 1, 1, 20.0f);
    c.at(0, 0, 0) = 0.8f;
    c.at(0, 0, 1) = 0.2f;
    c.at(0, 0, 2) = 0.4f;
    AdjustParams p;
    p.saturation = 0.0f;
    ImageF co, zo;
    adjust(co, zo, c, z, {1, 1, 1}, p, Exec::reference());
    const float luma = 0.2126f * 0.8f + 0.7152f * 0.2f + 0.0722f * 0.4f;
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(co.at(0, 0, k), luma, 1e-6f);
}

TEST(Adjust, AtmosphereTintsFarPixels) {
    ImageF c(2, 1, 4, 1.0f), z(2, 1, 1);
    for (int k = 0; k < 3; ++k) c.at(0, 0, k) = c.at(1, 0, k) = 0.2f;
    z.at(0, 0, 0) = 10.0f;   // before the atmosphere
    z.at(1, 0, 0) = 400.0f;  // beyond its end
    AdjustParams p;
    p.atmosphere = true;
    p.tint_r = 0.5f, p.tint_g = 0.6f, p.tint_b = 0.7f;
    ImageF co, zo;
    adjust(co, zo, c, z, {1, 1, 1}, p, Exec::reference());
    EXPECT_NEAR(co.at(0, 0, 0), 0.2f, 1e-6f);
    EXPECT_NEAR(co.at(1, 0, 0), 0.5f, 1e-6f);
    EXPECT_NEAR(co.at(1, 0, 2), 0.7f, 1e-6f);
}

// Large outputs (2 MiB-aligned storage) are written with non-temporal stores, small ones with
// plain stores: both give the reference's bits, NaN and infinite depths and colours included, with
// widths that are and are not a multiple of 8.
TEST(Adjust, LargeAndSmallImagesGiveTheReferenceBits) {
    for (const auto& [w, h] : {std::pair{1024, 640}, std::pair{1023, 641}, std::pair{37, 11}}) {
        ImageF color(w, h, 4), depth(w, h, 1);
        for (std::size_t i = 0; i < color.num_values(); ++i) color.data()[i] = float((i * 2654435761u >> 9) % 1000u) / 999.0f;
        for (std::size_t i = 0; i < depth.num_values(); ++i) depth.data()[i] = 3.0f + float(i % 97);
        color.data()[5] = std::numeric_limits<float>::quiet_NaN();
        depth.data()[7] = std::numeric_limits<float>::infinity();
        AdjustParams p;
        p.depth_near = 1.0f;
        p.depth_far = 100.0f;
        ImageF rc, rz, fc, fz;
        adjust(rc, rz, color, depth, {0.9f, 0.9f, 0.85f}, p, Exec::reference());
        adjust(fc, fz, color, depth, {0.9f, 0.9f, 0.85f}, p, Exec::fast(2));
        EXPECT_EQ(0, std::memcmp(rc.data(), fc.data(), rc.num_values() * sizeof(float))) << w << "x" << h;
        EXPECT_EQ(0, std::memcmp(rz.data(), fz.data(), rz.num_values() * sizeof(float))) << w << "x" << h;
    }
}

TEST(Adjust, SizeMismatchNamesTheTarget) {
    ImageF c(4, 4, 4), z(4, 3, 1), co, zo;
    try {
        adjust(co, zo, c, z, {1, 1, 1}, AdjustParams{});
        FAIL() << "accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("depth"), std::string::npos) << e.what();
    }
}

TEST(PigmentDensity, ZeroControlLeavesColourUnchanged) {
    ImageF c(3, 2, 4), k(3, 2, 4, 0.0f), o;
    for (std::size_t i = 0; i < c.num_values(); ++i) c.data()[i] = 0.1f + 0.07f * float(i % 11);
    pigment_density(o, c, k, {0.9f, 0.9f, 0.9f}, PigmentDensityParams{}, Exec::reference());
    EXPECT_EQ(o, c);
}

TEST(PigmentDensity, FullDilutionGivesSubstrateAndAccumulationSquares) {
    ImageF c(2, 1, 4, 0.5f), k(2, 1, 4, 0.0f), o;
    k.at(0, 0, 2) = -1.0f;  // d = 0: fade to the substrate
    k.at(1, 0, 2) = 1.0f;   // d = 2: c^2
    const glm::vec3 s{0.9f, 0.8f, 0.7f};
    pigment_density(o, c, k, s, PigmentDensityParams{}, Exec::reference());
    for (int ch = 0; ch < 3; ++ch) {
        EXPECT_EQ(o.at(0, 0, ch), s[ch]);
        EXPECT_FLOAT_EQ(o.at(1, 0, ch), 0.25f);
    }
    EXPECT_EQ(o.at(0, 0, 3), 0.5f);  // alpha kept
}

// In place, unpainted chunks of finite non-negative colour are left unwritten (they already hold
// |c|): every other colour value there must still get the bits of the run on separate images
// (-0 and negatives lose their sign, a signalling NaN becomes quiet, an infinite substrate makes
// NaN of the s * 0 term), at chunk sizes that split rows and on 1 and 2 threads.
TEST(PigmentDensity, InPlaceHasTheBitsOfSeparateImagesInUnpaintedChunks) {
    const float inf = std::numeric_limits<float>::infinity();
    const float odd[] = {-0.0f, -0.25f, inf, -inf, std::numeric_limits<float>::quiet_NaN(),
                         std::numeric_limits<float>::signaling_NaN(), -std::numeric_limits<float>::quiet_NaN()};
    const int w = 150, h = 9;  // a row is two 64-pixel chunks and a tail
    for (int variant = 0; variant < 8; ++variant) {
        ImageF c(w, h, 4), k(w, h, 4, 0.0f);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                for (int ch = 0; ch < 4; ++ch) c.at(x, y, ch) = 0.05f + 0.9f * float((x * 7 + y * 3 + ch) % 13) / 13.0f;
        if (variant < 7) c.at(70 + variant, 4, variant % 3) = odd[variant];  // one odd value in an unpainted chunk
        k.at(5, 1, 2) = 0.5f;  // one painted pixel elsewhere
        const glm::vec3 s = variant == 7 ? glm::vec3{0.9f, inf, 0.7f} : glm::vec3{0.9f, 0.8f, 0.7f};
        for (int threads : {1, 2}) {
            ImageF separate, in_place = c;
            pigment_density(separate, c, k, s, PigmentDensityParams{}, Exec::fast(threads));
            pigment_density(in_place, in_place, k, s, PigmentDensityParams{}, Exec::fast(threads));
            EXPECT_EQ(0, std::memcmp(separate.data(), in_place.data(), separate.num_values() * sizeof(float)))
                << "variant " << variant << ", " << threads << " thread(s)";
        }
    }
}

}  // namespace
}  // namespace aq::stylize
