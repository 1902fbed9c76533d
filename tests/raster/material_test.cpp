// tests/raster/material_test.cpp — the pure maths of the watercolor material and vertex stage
// against values computed by hand from WC17 eq. 1-6 (Figure 7: C = (194, 94, 0)/255, dA = 1).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "core/color.h"
#include "raster/material.h"
#include "raster/vertex.h"

using namespace aq;
using namespace aq::raster;

namespace {
const glm::vec3 kC(194.0f / 255.0f, 94.0f / 255.0f, 0.0f);  // WC17 Figure 7
const glm::vec3 kPaper(1.0f);
void expect_vec(glm::vec3 got, glm::vec3 want, float tol, const char* what) {
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(got[i], want[i], tol) << what << " channel " << i;
}
}  // namespace

TEST(Reflectance, Wc17Figure7HandComputed) {
    // Fully lit (L.N = 1, DA = 1).
    expect_vec(reflectance(kC, 1.0f, 1.0f, 0.0f, 0.0f, kPaper), kC, 1e-7f, "c=0 d=0");
    // Cangiante 0.2: C + 0.2 = (0.960784, 0.568627, 0.2).
    expect_vec(reflectance(kC, 1.0f, 1.0f, 0.2f, 0.0f, kPaper), {0.960784f, 0.568627f, 0.2f}, 1e-6f, "c=0.2 d=0");
    // Dilution 0.5: 0.5 (1 - C) + C = (0.880392, 0.684314, 0.5).
    expect_vec(reflectance(kC, 1.0f, 1.0f, 0.0f, 0.5f, kPaper), {0.880392f, 0.684314f, 0.5f}, 1e-6f, "c=0 d=0.5");
    // MNPR defaults c = 0.2, d = 0.8: Cc = (0.960784, 0.568627, 0.2), Cd = 0.8 (1 - Cc) + Cc.
    expect_vec(reflectance(kC, 1.0f, 1.0f, 0.2f, 0.8f, kPaper), {0.992157f, 0.913725f, 0.84f}, 1e-6f, "c=0.2 d=0.8");
    // Half lit (L.N = 0.5 -> DA = 0.5): Cc = C + 0.1, Cd = 0.4 (1 - Cc) + Cc.
    expect_vec(reflectance(kC, 0.5f, 1.0f, 0.2f, 0.8f, kPaper), {0.916471f, 0.681176f, 0.46f}, 1e-6f, "L.N=0.5");
    // Terminator and dark side: DA = 0, the colour is untouched.
    expect_vec(reflectance(kC, 0.0f, 1.0f, 0.2f, 0.8f, kPaper), kC, 1e-7f, "L.N=0");
    expect_vec(reflectance(kC, -0.7f, 1.0f, 0.2f, 0.8f, kPaper), kC, 1e-7f, "L.N<0");
    // Dilute area dA = 0.5: DA = (0.75 - 0.5) / 0.5 = 0.5 at L.N = 0.75.
    EXPECT_NEAR(dilute_area(0.75f, 0.5f), 0.5f, 1e-7f);
    EXPECT_NEAR(dilute_area(0.4f, 0.5f), 0.0f, 1e-7f);
    // Coloured paper: dilution goes towards Cp.
    expect_vec(dilution({0.2f, 0.4f, 0.6f}, 1.0f, 1.0f, {0.9f, 0.8f, 0.7f}), {0.9f, 0.8f, 0.7f}, 1e-6f, "d=1");
    expect_vec(cangiante({0.1f, 0.2f, 0.3f}, 0.5f, 0.4f), {0.3f, 0.4f, 0.5f}, 1e-6f, "cangiante");
}

TEST(Reflectance, DiffuseFactorAndWrap) {
    EXPECT_FLOAT_EQ(diffuse_factor(0.3f, 0.0f, 0.0f), 1.0f);   // k = 0: no shading
    EXPECT_FLOAT_EQ(diffuse_factor(0.3f, 0.0f, 1.0f), 0.3f);   // k = 1: Lambert
    EXPECT_FLOAT_EQ(diffuse_factor(-0.5f, 0.0f, 1.0f), 0.0f);
    EXPECT_FLOAT_EQ(diffuse_factor(0.5f, 0.0f, 0.2f), 0.9f);   // MNPR default k = 0.2
    EXPECT_FLOAT_EQ(diffuse_factor(0.0f, 1.0f, 1.0f), 0.5f);   // wrap 1: (0 + 1) / 2
}

TEST(Turbulence, Wc17Eq6) {
    const glm::vec3 C(0.5f, 0.25f, 0.8f);
    expect_vec(turbulence(C, 0.0f, kPaper), {0.125f, 0.015625f, 0.512f}, 1e-6f, "ctrl 0: C^3");
    expect_vec(turbulence(C, 0.25f, kPaper), {0.25f, 0.0625f, 0.64f}, 1e-6f, "ctrl 0.25: C^2");
    expect_vec(turbulence(C, 0.5f, kPaper), C, 0.0f, "ctrl 0.5: C");
    expect_vec(turbulence(C, 0.75f, kPaper), {0.75f, 0.625f, 0.9f}, 1e-6f, "ctrl 0.75: halfway to paper");
    expect_vec(turbulence(C, 1.0f, {0.9f, 0.9f, 0.8f}), {0.9f, 0.9f, 0.8f}, 1e-6f, "ctrl 1: paper");
    EXPECT_FLOAT_EQ(wc17_turbulence_ctrl(0.0f), 0.5f);
    EXPECT_FLOAT_EQ(wc17_turbulence_ctrl(1.0f), 0.0f);
    EXPECT_FLOAT_EQ(wc17_turbulence_ctrl(-1.0f), 1.0f);
}

TEST(Texture, WrapModesAndFilters) {
    using scene::Wrap;
    EXPECT_EQ(wrap_texel(-1, 4, Wrap::Repeat), 3);
    EXPECT_EQ(wrap_texel(9, 4, Wrap::Repeat), 1);
    EXPECT_EQ(wrap_texel(-3, 4, Wrap::ClampToEdge), 0);
    EXPECT_EQ(wrap_texel(7, 4, Wrap::ClampToEdge), 3);
    EXPECT_EQ(wrap_texel(4, 4, Wrap::MirroredRepeat), 3);   // GL: 0 1 2 3 3 2 1 0 0 1 ...
    EXPECT_EQ(wrap_texel(7, 4, Wrap::MirroredRepeat), 0);
    EXPECT_EQ(wrap_texel(-1, 4, Wrap::MirroredRepeat), 0);
    EXPECT_EQ(wrap_texel(-5, 4, Wrap::MirroredRepeat), 3);
    ImageF img(2, 1, 4);
    img.at(0, 0, 0) = 0.0f;
    img.at(1, 0, 0) = 1.0f;
    scene::Sampler s;
    s.wrap_s = Wrap::ClampToEdge;
    EXPECT_FLOAT_EQ(sample_texture(img, s, {0.5f, 0.5f}).x, 0.5f);   // between the two centres
    EXPECT_FLOAT_EQ(sample_texture(img, s, {0.25f, 0.5f}).x, 0.0f);  // on texel 0's centre
    EXPECT_FLOAT_EQ(sample_texture(img, s, {0.375f, 0.5f}).x, 0.25f);
    s.wrap_s = Wrap::Repeat;
    EXPECT_FLOAT_EQ(sample_texture(img, s, {0.0f, 0.5f}).x, 0.5f);   // wraps between texel 1 and 0
    s.mag = scene::Filter::Nearest;
    EXPECT_FLOAT_EQ(sample_texture(img, s, {0.49f, 0.5f}).x, 0.0f);
    EXPECT_FLOAT_EQ(sample_texture(img, s, {0.51f, 0.5f}).x, 1.0f);
    EXPECT_FLOAT_EQ(sample_texture(img, s, {std::nanf(""), 1e30f}).w, 0.0f);  // no crash
}

// Bilinear sampling equals its definition (texels wrapped one by one with wrap_texel, then the two
// lerps) bit for bit, for every wrap mode, inside and outside the texture, on odd and 1-texel sizes.
TEST(Texture, BilinearSampleEqualsTheDefinitionInEveryWrapMode) {
    using scene::Wrap;
    for (const auto& [tw, th] : {std::pair{5, 3}, std::pair{1, 1}, std::pair{2, 7}}) {
        ImageF img(tw, th, 4);
        for (std::size_t i = 0; i < img.num_values(); ++i) img.data()[i] = float((i * 37u) % 101u) / 100.0f;
        auto texel = [&](int x, int y) {
            return glm::vec4(img.at(x, y, 0), img.at(x, y, 1), img.at(x, y, 2), img.at(x, y, 3));
        };
        for (Wrap ws : {Wrap::Repeat, Wrap::ClampToEdge, Wrap::MirroredRepeat})
            for (Wrap wt : {Wrap::Repeat, Wrap::ClampToEdge, Wrap::MirroredRepeat}) {
                scene::Sampler s;
                s.wrap_s = ws;
                s.wrap_t = wt;
                for (int k = 0; k < 2000; ++k) {
                    const glm::vec2 uv(-2.5f + 0.00277f * float(k), 3.1f - 0.00311f * float(k));
                    const float fx = uv.x * float(tw) - 0.5f, fy = uv.y * float(th) - 0.5f;
                    const float flx = std::floor(fx), fly = std::floor(fy);
                    const float tx = fx - flx, ty = fy - fly;
                    const int x0 = wrap_texel(int(flx), tw, ws), x1 = wrap_texel(int(flx) + 1, tw, ws);
                    const int y0 = wrap_texel(int(fly), th, wt), y1 = wrap_texel(int(fly) + 1, th, wt);
                    const glm::vec4 top = texel(x0, y0) + (texel(x1, y0) - texel(x0, y0)) * tx;
                    const glm::vec4 bot = texel(x0, y1) + (texel(x1, y1) - texel(x0, y1)) * tx;
                    const glm::vec4 want = top + (bot - top) * ty;
                    const glm::vec4 got = sample_texture(img, s, uv);
                    for (int c = 0; c < 4; ++c)
                        ASSERT_EQ(got[c], want[c]) << tw << "x" << th << " uv " << uv.x << "," << uv.y << " channel " << c;
                }
            }
    }
}

// A texture with 8-bit codes (scene::TextureCodes, what the loaders attach to 8-bit files) is
// sampled through them: the same value as sampling its float image, bit for bit, for 1 to 4
// channels (the widening: grey, missing blue 0, missing alpha 1), every wrap mode and both filters,
// inside and outside; sRGB-decoded values (the look-up table is not v / 255) included.
TEST(Texture, SamplingThroughEightBitCodesEqualsTheFloatImage) {
    using scene::Wrap;
    for (int nc = 1; nc <= 4; ++nc) {
        scene::Texture t;
        t.image = ImageF(7, 5, nc);
        for (std::size_t i = 0; i < t.image.num_values(); ++i) t.image.data()[i] = float((i * 53u) % 256u) / 255.0f;
        t.codes = scene::texture_codes(t.image);
        for (std::size_t i = 0; i < t.image.num_values(); ++i)
            if (i % std::size_t(nc) < 3) t.image.data()[i] = srgb_to_linear(t.image.data()[i]);
        scene::texture_codes_finish(t.codes, t.image);
        ASSERT_FALSE(t.codes.empty()) << nc << " channels";
        for (Wrap w : {Wrap::Repeat, Wrap::ClampToEdge, Wrap::MirroredRepeat})
            for (scene::Filter f : {scene::Filter::Linear, scene::Filter::Nearest}) {
                scene::Sampler s;
                s.wrap_s = s.wrap_t = w;
                s.mag = f;
                for (int k = 0; k < 1500; ++k) {
                    const glm::vec2 uv(-1.7f + 0.00291f * float(k), 2.3f - 0.00237f * float(k));
                    const glm::vec4 want = sample_texture(t.image, s, uv), got = sample_texture(t, s, uv);
                    ASSERT_EQ(0, std::memcmp(&want, &got, sizeof want)) << nc << " channels, uv " << uv.x << "," << uv.y;
                }
            }
    }
}

// The codes exist only where they stand for the image exactly: values that are not a function of
// their code (two floats rounding to one code), NaN, values outside [0, 1] leave none.
TEST(Texture, EightBitCodesOnlyForEightBitValues) {
    ImageF img(3, 2, 1, 0.5f);
    scene::TextureCodes c = scene::texture_codes(img);
    scene::texture_codes_finish(c, img);
    EXPECT_FALSE(c.empty());
    img.at(1, 1, 0) = 0.5001f;  // rounds to the code of 0.5
    c = scene::texture_codes(img);
    scene::texture_codes_finish(c, img);
    EXPECT_TRUE(c.empty());
    img.at(1, 1, 0) = std::nanf("");
    EXPECT_TRUE(scene::texture_codes(img).empty());
    img.at(1, 1, 0) = 1.5f;
    EXPECT_TRUE(scene::texture_codes(img).empty());
}

// Mip levels (scene::texture_mip_level): GL's sizes max(1, n / 2) down to 1 x 1, and each level
// is the area average of the one above: an even size averages texel pairs exactly; for odd sizes
// (the three-tap box) the mean over the level is kept, and a constant stays that constant.
TEST(Texture, MipLevelsHaveGlSizesAndKeepTheAreaAverage) {
    std::mt19937 rng(5);
    scene::Texture t;
    t.image = ImageF(13, 6, 3);
    for (std::size_t i = 0; i < t.image.num_values(); ++i) t.image.data()[i] = float(rng() % 1000) / 999.0f;
    scene::finish_texture(t);
    ASSERT_EQ(t.mips.size(), 3u);  // 13x6 -> 6x3 -> 3x1 -> 1x1
    const int sizes[3][2] = {{6, 3}, {3, 1}, {1, 1}};
    for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(t.mips[k].width(), sizes[k][0]);
        EXPECT_EQ(t.mips[k].height(), sizes[k][1]);
        EXPECT_EQ(t.mips[k].channels(), 3);
    }
    auto mean = [](const ImageF& im, int c) {
        double s = 0;
        for (int y = 0; y < im.height(); ++y)
            for (int x = 0; x < im.width(); ++x) s += im.at(x, y, c);
        return s / (double(im.width()) * im.height());
    };
    for (int c = 0; c < 3; ++c)
        for (const ImageF& m : t.mips) EXPECT_NEAR(mean(m, c), mean(t.image, c), 2e-6) << "channel " << c;
    // Rows: 13 is odd, so texel 0 of level 1 weighs source texels 0, 1, 2 by 6/13, 6/13, 1/13;
    // columns: 6 is even, rows 0 and 1 by 1/2 each.
    auto row = [&](int y, int c) {
        return (6.0f / 13.0f) * t.image.at(0, y, c) + (6.0f / 13.0f) * t.image.at(1, y, c) + (1.0f / 13.0f) * t.image.at(2, y, c);
    };
    EXPECT_NEAR(t.mips[0].at(0, 0, 1), 0.5f * row(0, 1) + 0.5f * row(1, 1), 1e-6f);
    ImageF flat(7, 9, 4, 0.3f);
    for (ImageF lv = flat; lv.width() > 1 || lv.height() > 1;) {
        lv = scene::texture_mip_level(lv);
        for (std::size_t i = 0; i < lv.num_values(); ++i) ASSERT_NEAR(lv.data()[i], 0.3f, 1e-6f);
    }
    scene::Texture one;
    one.image = ImageF(1, 1, 4, 0.5f);
    scene::finish_texture(one);
    EXPECT_TRUE(one.mips.empty());
}

// Even sizes take a vectorised schedule (scene.cpp MipRows): each texel is still exactly
// (0 + w0 a) + w1 b along x, then the same along y, as the definition's tap-order sums.
TEST(Texture, EvenMipLevelsAreTheTapOrderSumsBitForBit) {
    std::mt19937 rng(3);
    for (int nc : {4, 3}) {
        ImageF img(64, 18, nc, kUninitialized);
        for (std::size_t i = 0; i < img.num_values(); ++i) img.data()[i] = float(rng() % 100000u) / 7919.0f - 3.0f;
        const ImageF got = scene::texture_mip_level(img);
        ASSERT_EQ(got.width(), 32);
        ASSERT_EQ(got.height(), 9);
        for (int y = 0; y < 9; ++y)
            for (int x = 0; x < 32; ++x)
                for (int c = 0; c < nc; ++c) {
                    auto row = [&](int sy) {
                        float s = 0.0f;
                        s += 0.5f * img.at(2 * x, sy, c);
                        s += 0.5f * img.at(2 * x + 1, sy, c);
                        return s;
                    };
                    float want = 0.0f;
                    want += 0.5f * row(2 * y);
                    want += 0.5f * row(2 * y + 1);
                    const float g = got.at(x, y, c);
                    ASSERT_EQ(0, std::memcmp(&g, &want, sizeof g)) << nc << " channels, texel " << x << "," << y << " lane " << c;
                }
    }
}

// A large opaque texture's level 1 is computed where sampled (scene::kComputedLevel1Bytes): each
// texel from level 0 gives texture_mip_level's value bit for bit, level 2 built from level 0
// without level 1 is the plain chain's, and sampling across levels 0-2 (isotropic and anisotropic
// footprints, both mip filters) equals sampling a copy whose level 1 is stored. 8-bit codes and
// floats, even and odd sizes (the 3-tap boxes).
TEST(Texture, ComputedLevelOneIsTheStoredLevelBitForBit) {
    std::mt19937 rng(11);
    for (const auto& [w, h] : {std::pair{2048, 2048}, std::pair{2055, 2049}}) {
        ImageF img(w, h, 4, kUninitialized);
        for (std::size_t i = 0; i < img.num_values(); ++i) img.data()[i] = float(rng() % 256u) / 255.0f;
        std::vector<ImageF> chain{scene::texture_mip_level(img)};
        while (chain.back().width() > 1 || chain.back().height() > 1) chain.push_back(scene::texture_mip_level(chain.back()));
        for (bool codes : {false, true}) {
            const std::string what = std::to_string(w) + "x" + std::to_string(h) + (codes ? " codes" : " floats");
            scene::Texture t;
            t.image = img;
            if (codes) {
                t.codes = scene::texture_codes(t.image);
                scene::texture_codes_finish(t.codes, t.image);
                ASSERT_FALSE(t.codes.empty());
                t.image = ImageF();
            }
            scene::finish_texture(t);
            ASSERT_TRUE(t.level1_computed) << what;
            ASSERT_TRUE(t.mips[0].empty()) << what;
            ASSERT_EQ(t.mips.size(), chain.size()) << what;
            const ImageF& l1 = chain[0];
            for (int y = 0; y < l1.height(); ++y)
                for (int x = 0; x < l1.width(); ++x) {
                    const glm::vec4 v = t.level1_texel(x, y);
                    ASSERT_EQ(0, std::memcmp(&v[0], &l1.data()[(std::size_t(y) * l1.width() + x) * 4], 4 * sizeof(float)))
                        << what << " texel " << x << "," << y;
                }
            for (std::size_t k = 1; k < chain.size(); ++k)
                ASSERT_EQ(0, std::memcmp(t.mips[k].data(), chain[k].data(), chain[k].num_values() * sizeof(float)))
                    << what << " level " << k + 1;
            scene::Texture stored = t;
            stored.mips = t.all_mips();
            stored.level1_computed = false;
            std::uniform_real_distribution<float> u(-0.2f, 1.2f), d(0.2f, 5.0f);
            for (scene::MipFilter mf : {scene::MipFilter::Linear, scene::MipFilter::Nearest}) {
                scene::Sampler s;
                s.mip = mf;
                for (int i = 0; i < 3000; ++i) {
                    const glm::vec2 uv(u(rng), u(rng));
                    const float px = d(rng) / float(w), py = d(rng) / float(h) * (i % 2 ? 1.0f : 4.0f);
                    const raster::UvGrad g{{px, 0.0f}, {0.0f, py}};
                    const glm::vec4 a = raster::sample_texture(t, s, uv, g), b = raster::sample_texture(stored, s, uv, g);
                    ASSERT_EQ(0, std::memcmp(&a[0], &b[0], sizeof a)) << what << " sample " << i;
                }
            }
        }
    }
    scene::Texture small;  // level 1 under the threshold: stored
    small.image = ImageF(512, 512, 4, 0.25f);
    scene::finish_texture(small);
    EXPECT_FALSE(small.level1_computed);
    EXPECT_FALSE(small.mips[0].empty());
}

// A colour texture with transparent texels (glTF straight alpha: leaf atlases) averages colour
// weighted by alpha, so the transparent texels' colour (here white) does not pale the leaves as
// they shrink; alpha is the plain average; a footprint with no alpha keeps the plain average; an
// opaque colour texture and a data texture (not sRGB) have the plain levels.
TEST(Texture, ColourLevelsWeighColourByAlpha) {
    scene::Texture t;
    t.srgb = true;
    t.image = ImageF(4, 1, 4);
    const float texels[4][4] = {{0.8f, 0.2f, 0.1f, 1.0f}, {1, 1, 1, 0}, {0.4f, 0.6f, 0.2f, 0.5f}, {1, 1, 1, 0}};
    for (int x = 0; x < 4; ++x)
        for (int c = 0; c < 4; ++c) t.image.at(x, 0, c) = texels[x][c];
    scene::finish_texture(t);
    ASSERT_EQ(t.mips.size(), 2u);
    EXPECT_FLOAT_EQ(t.mips[0].at(0, 0, 0), 0.8f);  // the leaf's colour, not halfway to white
    EXPECT_FLOAT_EQ(t.mips[0].at(0, 0, 1), 0.2f);
    EXPECT_FLOAT_EQ(t.mips[0].at(0, 0, 3), 0.5f);
    EXPECT_FLOAT_EQ(t.mips[0].at(1, 0, 0), 0.4f);
    EXPECT_FLOAT_EQ(t.mips[0].at(1, 0, 3), 0.25f);
    // Level 2: (0.8 * 1 + 0.4 * 0.5) / 1.5 = 0.6667 in red.
    EXPECT_NEAR(t.mips[1].at(0, 0, 0), (0.8f + 0.2f) / 1.5f, 1e-6f);
    EXPECT_FLOAT_EQ(t.mips[1].at(0, 0, 3), 0.375f);
    scene::Texture clear = t;
    for (int x = 0; x < 4; ++x) clear.image.at(x, 0, 3) = 0.0f;
    scene::finish_texture(clear);
    EXPECT_FLOAT_EQ(clear.mips[0].at(0, 0, 0), 0.9f);  // (0.8 + 1) / 2
    for (bool srgb : {true, false}) {
        scene::Texture plain = t;
        plain.srgb = srgb;
        if (srgb)
            for (int x = 0; x < 4; ++x) plain.image.at(x, 0, 3) = 1.0f;
        scene::finish_texture(plain);
        for (std::size_t k = 0; k < plain.mips.size(); ++k) {
            const ImageF ref = scene::texture_mip_level(k == 0 ? plain.image : plain.mips[k - 1]);
            EXPECT_EQ(std::memcmp(ref.data(), plain.mips[k].data(), ref.num_values() * sizeof(float)), 0) << srgb << k;
        }
    }
}

// Sampling with derivatives is GL's: no derivatives (or magnified, or NaN ones) read level 0 with
// the magnification filter, bit for bit the sample without derivatives; a checkerboard of single
// texels seen 4 texels per pixel reads as its average (it would alias to black or white without
// mip levels); trilinear blends the two nearest levels by the fraction of the level of detail;
// MipFilter::None minifies on level 0; derivatives past the last level read the 1 x 1 average.
TEST(Texture, MinifiedSamplesReadTheMipLevelsAsGlDoes) {
    scene::Texture t;
    t.image = ImageF(64, 64, 1);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) t.image.at(x, y, 0) = float((x + y) % 2);
    scene::finish_texture(t);
    scene::Sampler s;  // trilinear, repeat
    const glm::vec2 uv(0.3f, 0.55f);
    auto same = [](glm::vec4 a, glm::vec4 b) { return std::memcmp(&a, &b, sizeof a) == 0; };
    EXPECT_TRUE(same(sample_texture(t, s, uv, {}), sample_texture(t, s, uv)));
    EXPECT_TRUE(same(sample_texture(t, s, uv, {{0.5f / 64, 0}, {0, 0.5f / 64}}), sample_texture(t, s, uv)));
    EXPECT_TRUE(same(sample_texture(t, s, uv, {{NAN, 0}, {0, 0}}), sample_texture(t, s, uv)));
    EXPECT_FLOAT_EQ(aniso_footprint(64, 64, {{4.0f / 64, 0}, {0, 1.0f / 64}}).iso_lod, 2.0f);
    for (float u = 0.1f; u < 0.9f; u += 0.037f)
        EXPECT_NEAR(sample_texture(t, s, {u, 0.4f}, {{4.0f / 64, 0}, {0, 4.0f / 64}}).r, 0.5f, 1e-6f);
    // lambda = 1.5 on a noise texture: halfway between levels 1 and 2 (read alone at lambda 1, 2).
    scene::Texture n;
    n.image = ImageF(64, 64, 1);
    std::mt19937 rng(9);
    for (std::size_t i = 0; i < n.image.num_values(); ++i) n.image.data()[i] = float(rng() % 256) / 255.0f;
    scene::finish_texture(n);
    const float k15 = std::exp2(1.5f) / 64;
    const UvGrad g15{{k15, 0}, {0, k15}};
    const float l1 = sample_texture(n, s, uv, {{2.0f / 64, 0}, {0, 2.0f / 64}}).r;
    const float l2 = sample_texture(n, s, uv, {{4.0f / 64, 0}, {0, 4.0f / 64}}).r;
    ASSERT_GT(std::abs(l1 - l2), 1e-3f);
    EXPECT_NEAR(sample_texture(n, s, uv, g15).r, 0.5f * (l1 + l2), 1e-5f);
    scene::Sampler none = s;
    none.mip = scene::MipFilter::None;
    none.min = scene::Filter::Nearest;
    const float v = sample_texture(t, none, {0.3f, 0.55f}, {{4.0f / 64, 0}, {0, 4.0f / 64}}).r;
    EXPECT_TRUE(v == 0.0f || v == 1.0f);  // a texel of level 0
    // A gradient image: far past the last level, the 1 x 1 average.
    scene::Texture r;
    r.image = ImageF(8, 4, 1);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x) r.image.at(x, y, 0) = float(x) / 7.0f;
    scene::finish_texture(r);
    EXPECT_NEAR(sample_texture(r, s, uv, {{1e6f, 0}, {0, 1e6f}}).r, 0.5f, 1e-6f);
    EXPECT_NEAR(sample_texture(r, s, uv, {{INFINITY, 0}, {0, INFINITY}}).r, 0.5f, 1e-6f);
}

// Anisotropic footprints (aniso_footprint): a pixel 8 texels long and 1 wide takes 8 probes at
// level 0 along its long axis. Stripes across the long axis average to grey; stripes along it keep
// their contrast (isotropic filtering at lambda = 3 would blur them to grey too). Ratios beyond
// kMaxAnisotropy are capped and the level rises to cover the rest.
TEST(Texture, AnisotropicFootprintsKeepTheDetailAlongTheirShortAxis) {
    auto stripes = [](bool along_x) {
        scene::Texture t;
        t.image = ImageF(64, 64, 1);
        for (int y = 0; y < 64; ++y)
            for (int x = 0; x < 64; ++x) t.image.at(x, y, 0) = float((along_x ? x : y) % 2);
        scene::finish_texture(t);
        return t;
    };
    const scene::Texture vertical = stripes(true), horizontal = stripes(false);
    const UvGrad g{{8.0f / 64, 0}, {0, 1.0f / 64}};
    const AnisoFootprint f = aniso_footprint(64, 64, g);
    EXPECT_EQ(f.samples, 8);
    EXPECT_FLOAT_EQ(f.lod, 0.0f);
    scene::Sampler s;
    for (int k = 0; k < 10; ++k) {
        const float u = 0.1f + 0.07f * float(k);
        const float v = (float(20 + k) + 0.5f) / 64.0f;  // a texel row's centre
        EXPECT_NEAR(sample_texture(vertical, s, {u, v}, g).r, 0.5f, 0.07f) << k;
        const float across = sample_texture(horizontal, s, {u, v}, g).r;
        EXPECT_NEAR(across, float((20 + k) % 2), 1e-5f) << k;
        const UvGrad iso{{8.0f / 64, 0}, {0, 8.0f / 64}};
        EXPECT_NEAR(sample_texture(horizontal, s, {u, v}, iso).r, 0.5f, 1e-5f) << k;
    }
    const AnisoFootprint capped = aniso_footprint(64, 64, {{64.0f / 64, 0}, {0, 1.0f / 64}});
    EXPECT_EQ(capped.samples, kMaxAnisotropy);
    EXPECT_FLOAT_EQ(capped.lod, 2.0f);  // 64 texels / 16 probes = 4 texels each
}

TEST(VertexStage, TremorOffsetAndBleedDisplacement) {
    TremorParams p;  // MNPR defaults: 4 px, front 0.4, speed 10, frequency 10
    const glm::vec3 n(0, 0, 1), v(0, 0, 1);
    // Facing the viewer: weight min(sat(1.2), 0.6) = 0.6; at T = 0 the offset is sin(f*10*x).
    const glm::vec3 pos(0.01f, 0.02f, 0);
    const glm::vec2 o = tremor_offset_px(p, 0.0f, pos, n, v);
    EXPECT_NEAR(o.x, std::sin(1.0f) * 4.0f * 0.6f, 1e-6f);
    EXPECT_NEAR(o.y, std::sin(2.0f) * 4.0f * 0.6f, 1e-6f);
    // Grazing (N.V = 0.25): weight 0.3; T = 0.5 s adds a phase of 0.5 * 10 * 100.
    const glm::vec3 ng(0, std::sqrt(1.0f - 0.0625f), 0.25f);
    const glm::vec2 g = tremor_offset_px(p, 0.5f, pos, ng, v);
    EXPECT_NEAR(g.x, std::sin(500.0f + 1.0f) * 4.0f * 0.3f, 1e-4f);
    // Silhouette (N.V = 0): no tremor in MNPR's form.
    EXPECT_EQ(tremor_offset_px(p, 0.3f, pos, glm::vec3(1, 0, 0), v), glm::vec2(0.0f));
    // Bleeding: sat(ctrl - 0.7) * 0.5 along the normal.
    EXPECT_EQ(bleed_displace({1, 2, 3}, {0, 1, 0}, 0.5f), glm::vec3(1, 2, 3));
    const glm::vec3 b = bleed_displace({1, 2, 3}, {0, 1, 0}, 1.0f);
    EXPECT_NEAR(b.y, 2.15f, 1e-6f);
}

// ---- The batched schedule --------------------------------------------------------------------

namespace {
//! Same bits, except that any NaN equals any NaN (docs/determinism.md: the sign of a NaN made
//! from two NaN operands is not part of the promise between schedules).
bool same_bits(float a, float b) { return (std::isnan(a) && std::isnan(b)) || std::memcmp(&a, &b, sizeof a) == 0; }
}  // namespace

// shade_fragments (eight fragments per vector operation, the fast traversal's shading) gives
// lane i the bits shade_fragment gives in[i], for every material feature (textures, normal maps,
// specular, several lights, double-sided back faces, object-space turbulence, both working
// spaces, orthographic views) and for inputs a vector schedule can get wrong: -0 (a broadcast
// must not turn it into +0), zero-length normals (normalize3 returns them unchanged), infinities
// and NaN, batches of 1-8 fragments and batches whose fragments differ in uv or tangents; base
// colour textures of floats and of 8-bit codes, every wrap mode, both filters, footprints inside
// the texture and across its edges (the batch's sampling in one register, or lane by lane).
TEST(ShadeFragments, EachLaneIsShadeFragment) {
    std::mt19937 rng(20261202);
    auto U = [&](float a, float b) { return std::uniform_real_distribution<float>(a, b)(rng); };
    auto odd = [&](float v) {  // sometimes a value a vector schedule can mishandle
        switch (rng() % 40) {
            case 0: return std::nanf("");
            case 1: return -0.0f;
            case 2: return 0.0f;
            case 3: return INFINITY;
            case 4: return -INFINITY;
            case 5: return 1e30f;
            default: return v;
        }
    };
    scene::Scene sc;
    for (int t = 0; t < 3; ++t) {  // base colour, normal map, control texture
        scene::Texture tx;
        tx.image = ImageF(16, 16, 4);
        for (std::size_t i = 0; i < tx.image.num_values(); ++i) tx.image.data()[i] = U(0, 1);
        sc.textures.push_back(tx);
    }
    {  // texture 3: a base colour of 8-bit values kept as codes (what an 8-bit glTF image loads as)
        scene::Texture tx;
        tx.image = ImageF(13, 11, 4);
        for (std::size_t i = 0; i < tx.image.num_values(); ++i) tx.image.data()[i] = float(rng() % 256) / 255.0f;
        tx.codes = scene::texture_codes(tx.image);
        scene::finish_texture(tx);  // codes and mip levels, as the loaders do
        ASSERT_FALSE(tx.codes.empty());
        sc.textures.push_back(tx);
    }
    scene::finish_texture(sc.textures[0]);  // a float texture with mip levels (1 and 2 have none)
    const scene::Wrap wraps[] = {scene::Wrap::Repeat, scene::Wrap::ClampToEdge, scene::Wrap::MirroredRepeat};
    int fragments = 0, nan_lanes = 0, mixed = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        scene::Material m;
        m.base_color = {U(0, 1.2f), U(0, 1), odd(U(0, 1)), 1};
        m.linear_color = rng() % 2;
        m.double_sided = rng() % 2;
        if (rng() % 2) m.base_color_texture.texture = rng() % 2 ? 0 : 3;
        m.base_color_texture.sampler.wrap_s = wraps[rng() % 3];
        m.base_color_texture.sampler.wrap_t = wraps[rng() % 3];
        if (rng() % 4 == 0) m.base_color_texture.sampler.mag = scene::Filter::Nearest;
        if (rng() % 4 == 0) m.base_color_texture.sampler.min = scene::Filter::Nearest;
        m.base_color_texture.sampler.mip = scene::MipFilter(rng() % 3);
        if (rng() % 2) m.normal_texture.texture = 1, m.normal_texture.scale = U(-1, 2);
        for (int k = 0; k < scene::kNumControlTargets; ++k) {
            m.wc.control[k] = {U(-1, 1), odd(U(-1, 1)), U(-1, 1), 0};
            if (rng() % 3 == 0) m.wc.control_texture[k].texture = 2;
        }
        m.wc.dilute = U(0, 1);
        m.wc.cangiante = U(0, 1);
        m.wc.diffuse_factor = U(0, 1);
        m.wc.dilute_area = U(-0.5f, 1.5f);
        m.wc.shade_wrap = U(0, 1);
        m.wc.shade_color = {U(0, 1), U(0, 1), U(0, 1)};
        m.wc.specular = rng() % 2 ? U(0, 1) : 0.0f;
        m.wc.specular_power = U(1, 64);
        ShadeContext ctx;
        ctx.scene = &sc;
        for (int l = 0, nl = 1 + int(rng() % 3); l < nl; ++l)
            ctx.lights.push_back({normalize3(glm::vec3(U(-1, 1), U(-1, 1), U(-1, 1))), {U(0, 2), U(0, 2), U(0, 2)}});
        ctx.ambient = {odd(U(0, 0.2f)), U(0, 0.2f), -0.0f};
        ctx.perspective = rng() % 2;
        ctx.substrate = {U(0.8f, 1), U(0.8f, 1), U(0.8f, 1)};
        ctx.object_space_turbulence = rng() % 2;
        ctx.working_space = rng() % 2 ? WorkingSpace::Display : WorkingSpace::Linear;
        const bool has_uv = rng() % 4 != 0, has_tangent = rng() % 2, use_base = rng() % 4 == 0;
        const glm::vec3 base(U(0, 1), U(0, 1), U(0, 1));
        const int n = 1 + int(rng() % 8);
        FragmentInput in[FragmentLanes::kLanes];
        for (int i = 0; i < n; ++i) {
            FragmentInput& f = in[i];
            f.view_pos = {odd(U(-5, 5)), odd(U(-5, 5)), odd(U(-20, -1))};
            f.normal = rng() % 30 == 0 ? glm::vec3(0.0f) : glm::vec3(odd(U(-1, 1)), odd(U(-1, 1)), odd(U(-1, 1)));
            f.tangent = {odd(U(-1, 1)), U(-1, 1), U(-1, 1), rng() % 2 ? -1.0f : odd(1.0f)};
            // Mostly inside the texture (a batch's footprints in one register), else anywhere.
            f.uv = rng() % 3 ? glm::vec2(odd(U(0, 1)), U(0, 1)) : glm::vec2(odd(U(-2, 2)), U(-2, 2));
            // Magnified (level 0, the batch's register path), minified (mip levels) or odd.
            const float g = rng() % 2 ? U(0, 0.05f) : U(0, 1.5f);
            f.uv_grad = {{odd(g), U(-g, g)}, {U(-g, g), odd(g)}};
            f.color = {U(0, 1), U(0, 1), odd(U(0, 1)), 1};
            for (int k = 0; k < scene::kNumControlTargets; ++k)
                f.ctrl[k] = {odd(U(-1.5f, 1.5f)), U(-1.5f, 1.5f), U(-1.5f, 1.5f)};
            f.has_uv = trial % 7 == 0 && i == n - 1 && n > 1 ? !has_uv : has_uv;  // a mixed batch
            f.has_tangent = has_tangent;
            f.back = rng() % 2;
            f.base = use_base ? &base : nullptr;
        }
        mixed += trial % 7 == 0 && n > 1;
        FragmentLanes lanes;
        shade_fragments(ctx, m, in, n, lanes);
        for (int i = 0; i < n; ++i) {
            FragmentLanes want;
            want.set(0, shade_fragment(ctx, m, in[i]));
            ++fragments;
            bool any_nan = false;
            auto check = [&](float w, float g, const char* what, int c) {
                any_nan = any_nan || std::isnan(w);
                ASSERT_TRUE(same_bits(w, g)) << what << "[" << c << "] trial " << trial << " lane " << i << ": " << w << " vs " << g;
            };
            for (int c = 0; c < 3; ++c) {
                check(want.color[c][0], lanes.color[c][i], "color", c);
                check(want.normal[c][0], lanes.normal[c][i], "normal", c);
                for (int k = 0; k < scene::kNumControlTargets; ++k) check(want.ctrl[k][c][0], lanes.ctrl[k][c][i], "ctrl", k);
            }
            check(want.diffuse[0], lanes.diffuse[i], "diffuse", 0);
            check(want.specular[0], lanes.specular[i], "specular", 0);
            nan_lanes += any_nan;
        }
    }
    // The cases were exercised: NaN outputs exist, most lanes are finite, mixed batches ran.
    EXPECT_GT(nan_lanes, 50);
    EXPECT_LT(nan_lanes, fragments / 2);
    EXPECT_GT(mixed, 100);
}
