// tests/stylize/ryb_test.cpp — Gossett & Chen RYB cube, its inverse, and the Chen et al. 2015
// brightness-preserving mix used by WC18 overlaps.
#include "stylize/ryb.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace aq::stylize {
namespace {

void expect_vec_near(glm::vec3 a, glm::vec3 b, float tol) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

TEST(Ryb, PrimariesAndCornersMapToGossettChenColours) {
    expect_vec_near(ryb_to_rgb({0, 0, 0}), {1.0f, 1.0f, 1.0f}, 0);      // no pigment: white paper
    expect_vec_near(ryb_to_rgb({1, 0, 0}), {1.0f, 0.0f, 0.0f}, 0);      // red
    expect_vec_near(ryb_to_rgb({0, 1, 0}), {1.0f, 1.0f, 0.0f}, 0);      // yellow
    expect_vec_near(ryb_to_rgb({0, 0, 1}), {0.163f, 0.373f, 0.6f}, 1e-6f);  // blue
    expect_vec_near(ryb_to_rgb({1, 1, 0}), {1.0f, 0.5f, 0.0f}, 0);      // orange
    expect_vec_near(ryb_to_rgb({1, 0, 1}), {0.5f, 0.0f, 0.5f}, 0);      // purple
    expect_vec_near(ryb_to_rgb({0, 1, 1}), {0.0f, 0.66f, 0.2f}, 1e-6f);  // green
    expect_vec_near(ryb_to_rgb({1, 1, 1}), {0.2f, 0.094f, 0.0f}, 1e-6f);  // black
}

TEST(Ryb, TrilinearAtCubeCentreIsTheCornerAverage) {
    glm::vec3 avg(0.0f);
    for (auto& c : kRybCorners) avg += c;
    avg /= 8.0f;
    expect_vec_near(ryb_to_rgb({0.5f, 0.5f, 0.5f}), avg, 1e-6f);
}

TEST(Ryb, InverseRecoversCornersAndRoundTrips) {
    expect_vec_near(rgb_to_ryb({1, 1, 1}), {0, 0, 0}, 1e-4f);
    expect_vec_near(rgb_to_ryb({1, 0, 0}), {1, 0, 0}, 1e-4f);
    expect_vec_near(rgb_to_ryb({1, 1, 0}), {0, 1, 0}, 1e-4f);
    expect_vec_near(rgb_to_ryb({0.163f, 0.373f, 0.6f}), {0, 0, 1}, 1e-4f);
    // Every colour the cube produces comes back to itself through RGB -> RYB -> RGB.
    for (int i = 0; i <= 6; ++i)
        for (int j = 0; j <= 6; ++j)
            for (int k = 0; k <= 6; ++k) {
                const glm::vec3 ryb(i / 6.0f, j / 6.0f, k / 6.0f);
                const glm::vec3 rgb = ryb_to_rgb(ryb);
                const glm::vec3 back = ryb_to_rgb(rgb_to_ryb(rgb));
                expect_vec_near(back, rgb, 2e-4f);
                const glm::vec3 inv = rgb_to_ryb(rgb);
                for (int c = 0; c < 3; ++c) {
                    EXPECT_GE(inv[c], 0.0f);
                    EXPECT_LE(inv[c], 1.0f);
                }
            }
}

TEST(Ryb, YellowPlusBlueIsGreen) {
    const glm::vec3 yellow = ryb_to_rgb({0, 1, 0}), blue = ryb_to_rgb({0, 0, 1});
    const glm::vec3 m = mix_ryb(yellow, blue);
    EXPECT_GT(m.g, m.r);
    EXPECT_GT(m.g, m.b);
    // Additive RGB averaging would give a grey-ish (0.58, 0.69, 0.3); RYB keeps red well below green.
    EXPECT_LT(m.r, 0.9f * m.g);
}

TEST(Ryb, RedPlusYellowIsOrange) {
    const glm::vec3 m = mix_ryb({1, 0, 0}, {1, 1, 0});
    EXPECT_GT(m.r, m.g);
    EXPECT_GT(m.g, m.b);
    // The cube gives RYB (0.5, 0.5, 0) -> RGB (1, 0.625, 0.25); the brightness rescale then clips r.
    EXPECT_GT(m.g, 0.5f * m.r);
    EXPECT_LT(m.g, 0.75f * m.r);
    EXPECT_LT(m.b, 0.3f * m.r);
}

TEST(Ryb, RedPlusBlueIsPurple) {
    const glm::vec3 m = mix_ryb({1, 0, 0}, ryb_to_rgb({0, 0, 1}));
    EXPECT_GT(m.r, m.g);
    EXPECT_GT(m.b, m.g);
}

TEST(Ryb, MixPreservesMeanBrightness) {
    const glm::vec3 a(0.8f, 0.3f, 0.1f), b(0.2f, 0.4f, 0.7f);
    const glm::vec3 m = mix_ryb(a, b);
    EXPECT_NEAR(ryb_brightness(m), 0.5f * (ryb_brightness(a) + ryb_brightness(b)), 1e-5f);
    // brightness_scale scales the target (MNPR's 0.9).
    const glm::vec3 m9 = mix_ryb(a, b, 0.5f, 0.9f);
    EXPECT_NEAR(ryb_brightness(m9), 0.9f * 0.5f * (ryb_brightness(a) + ryb_brightness(b)), 1e-5f);
}

TEST(Ryb, MixOfAColourWithItselfIsItself) {
    for (glm::vec3 c : {glm::vec3(1, 0, 0), glm::vec3(1, 1, 0), glm::vec3(1, 0.5f, 0), ryb_to_rgb({0.3f, 0.6f, 0.2f})})
        expect_vec_near(mix_ryb(c, c), c, 5e-4f);
}

TEST(Ryb, NonFiniteInputsDoNotCrash) {
    const float nan = std::nanf(""), inf = INFINITY;
    const glm::vec3 r = rgb_to_ryb({nan, inf, -inf});
    for (int c = 0; c < 3; ++c) EXPECT_TRUE(r[c] >= 0.0f && r[c] <= 1.0f);
    const glm::vec3 m = mix_ryb({nan, 0, 0}, {0, 0, 1});
    for (int c = 0; c < 3; ++c) EXPECT_FALSE(std::isinf(m[c]));
}

// rgb_to_ryb_many is rgb_to_ryb's schedule in four lanes: every result must have the scalar
// bits, whatever the other lanes do (colours that need 2 to 12 steps, or none, share the lanes).
TEST(Ryb, LaneInverseHasTheScalarBitsForEveryColour) {
    std::mt19937 rng(20261204);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f), wide(-0.5f, 1.5f);
    const float nan = std::nanf(""), inf = INFINITY;
    std::vector<glm::vec3> colours = {{0, 0, 0}, {1, 1, 1}, {nan, inf, -inf}, {nan, 0.5f, 0.5f}, {-1, 2, 0.5f},
                                      {1e30f, -1e30f, 0}, {0.2f, 0.094f, 0.0f}};
    for (const glm::vec3& c : kRybCorners) colours.push_back(c);
    for (int i = 0; i < 20000; ++i)
        colours.push_back(i % 4 == 3 ? glm::vec3(wide(rng), wide(rng), wide(rng))
                                     : ryb_to_rgb({unit(rng), unit(rng), unit(rng)}) * (i % 4 == 1 ? unit(rng) : 1.0f));
    std::shuffle(colours.begin(), colours.end(), rng);
    // Every count up to 9 (empty, partly filled lanes) and the whole set.
    for (std::size_t n : {std::size_t(0), std::size_t(1), std::size_t(2), std::size_t(3), std::size_t(4),
                          std::size_t(5), std::size_t(9), colours.size()}) {
        std::vector<glm::vec3> out(n + 1, glm::vec3(-7.0f));
        rgb_to_ryb_many(colours.data(), out.data(), n);
        std::size_t mismatches = 0;
        for (std::size_t i = 0; i < n; ++i) {
            const glm::vec3 s = rgb_to_ryb(colours[i]);
            mismatches += std::memcmp(&s, &out[i], sizeof s) != 0;
        }
        EXPECT_EQ(mismatches, 0u) << n << " colours";
        EXPECT_EQ(out[n], glm::vec3(-7.0f)) << "written past the end, " << n << " colours";
    }
}

}  // namespace
}  // namespace aq::stylize
