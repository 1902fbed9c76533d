// tests/stylize/bleed_test.cpp — colour bleeding (WC16 naive, WC17 Algorithm 1, MNPR) and the
// bleeding blend (WC17 eq. 7): constants stay constant, the naive impulse response is the
// normalised Gaussian, zero control changes nothing, and the two bleeding rules of WC17 Figure 9
// on small synthetic G-buffers.
#include <cmath>
#include <cstring>
#include <limits>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "stylize/kernels.h"
#include "stylize/stages/bleed.h"
#include "stylize/stages/bleed_blend.h"

namespace aq::stylize {
namespace {

constexpr BleedRule kRules[] = {BleedRule::Naive, BleedRule::JointBilateral, BleedRule::Mnpr};

struct Scene {
    ImageF color, depth, ctrl;
    Scene(int w, int h) : color(w, h, 4), depth(w, h, 1), ctrl(w, h, 4, 0.0f) {}
    void set(int x, int y, glm::vec3 c, float z, float bleed) {
        for (int k = 0; k < 3; ++k) color.at(x, y, k) = c[k];
        color.at(x, y, 3) = 1.0f;
        depth.at(x, y, 0) = z;
        ctrl.at(x, y, 2) = bleed;  // ctrl.abstraction.b
    }
};

BleedParams full_res() {
    BleedParams p;
    p.half_res = false;
    return p;
}

TEST(Bleed, ConstantColourStaysConstantForEveryVariantAndControl) {
    Scene s(31, 23);
    for (int y = 0; y < 23; ++y)
        for (int x = 0; x < 31; ++x)
            s.set(x, y, {0.3f, 0.6f, 0.9f}, 0.2f + 0.01f * float((x * 7 + y * 3) % 5), float((x + y) % 3) * 0.5f);
    for (BleedRule rule : kRules)
        for (bool half : {false, true}) {
            BleedParams p = full_res();
            p.half_res = half;
            ImageF b;
            bleed(b, s.color, s.depth, s.ctrl, rule, p, Exec::reference());
            for (int y = 0; y < b.height(); ++y)
                for (int x = 0; x < b.width(); ++x) {
                    EXPECT_EQ(b.at(x, y, 0), 0.3f);
                    EXPECT_EQ(b.at(x, y, 1), 0.6f);
                    EXPECT_EQ(b.at(x, y, 2), 0.9f);
                }
        }
}

TEST(Bleed, HalfResolutionRoundsUp) {
    Scene s(31, 22);
    ImageF b;
    BleedParams p;
    p.half_res = true;
    bleed(b, s.color, s.depth, s.ctrl, BleedRule::JointBilateral, p);
    EXPECT_EQ(b.width(), 16);
    EXPECT_EQ(b.height(), 11);
}

TEST(Bleed, NaiveImpulseReproducesTheNormalisedGaussian) {
    const int n = 31, c = 15;
    Scene s(n, n);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) s.set(x, y, {0, 0, 0}, 0.5f, 1.0f);
    s.color.at(c, c, 0) = 1.0f;
    ImageF b;
    bleed(b, s.color, ImageF(), s.ctrl, BleedRule::Naive, full_res(), Exec::reference());
    // Independent kernel: exp(-i^2 / (2 sigma^2)), normalised over 21 taps, outer product.
    double g[kBleedTaps], sum = 0;
    for (int i = -kBleedRadius; i <= kBleedRadius; ++i) sum += g[i + kBleedRadius] = std::exp(-double(i * i) / (2.0 * 400.0));
    for (int dy = -kBleedRadius; dy <= kBleedRadius; ++dy)
        for (int dx = -kBleedRadius; dx <= kBleedRadius; ++dx)
            EXPECT_NEAR(b.at(c + dx, c + dy, 0), g[dx + kBleedRadius] / sum * g[dy + kBleedRadius] / sum, 2e-6);
    EXPECT_EQ(b.at(c + kBleedRadius + 1, c, 0), 0.0f);
    EXPECT_EQ(b.at(c, c, 3), 1.0f);  // naive: the mask is the painted control, not blurred
}

TEST(Bleed, ZeroControlLeavesColourUnchangedAndBlendIsIdentity) {
    Scene s(29, 19);
    for (int y = 0; y < 19; ++y)
        for (int x = 0; x < 29; ++x)
            s.set(x, y, {0.05f * float(x % 13), 0.9f - 0.03f * float(y), 0.5f}, x < 14 ? 0.2f : 0.7f, 0.0f);
    for (BleedRule rule : {BleedRule::JointBilateral, BleedRule::Mnpr}) {
        ImageF b, o;
        bleed(b, s.color, s.depth, s.ctrl, rule, full_res(), Exec::reference());
        for (int y = 0; y < 19; ++y)
            for (int x = 0; x < 29; ++x) {
                for (int k = 0; k < 3; ++k) EXPECT_EQ(b.at(x, y, k), s.color.at(x, y, k));
                EXPECT_EQ(b.at(x, y, 3), 0.0f);
            }
        bleed_blend(o, s.color, b, BleedBlendParams{}, Exec::reference());
        EXPECT_EQ(o, s.color);
    }
}

// WC17 Figure 9 (a-c): a bled background behind an un-bled foreground line. Naive bleeding leaks
// the line into the background; Algorithm 1 keeps the background free of it and the line crisp.
TEST(Bleed, Figure9UnbledForegroundLineDoesNotLeakIntoBledBackground) {
    const int w = 48, h = 20, lx = 24;
    Scene s(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const bool line = x == lx || x == lx + 1;
            s.set(x, y, line ? glm::vec3(0.0f) : glm::vec3(0.9f, 0.8f, 0.3f), line ? 0.2f : 0.8f, line ? 0.0f : 1.0f);
        }
    for (BleedRule rule : {BleedRule::JointBilateral, BleedRule::Mnpr}) {
        ImageF b;
        bleed(b, s.color, s.depth, s.ctrl, rule, full_res(), Exec::reference());
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                for (int k = 0; k < 3; ++k) EXPECT_EQ(b.at(x, y, k), s.color.at(x, y, k)) << x << "," << y;
    }
    ImageF naive, out;
    bleed(naive, s.color, s.depth, s.ctrl, BleedRule::Naive, full_res(), Exec::reference());
    EXPECT_LT(naive.at(lx - 3, h / 2, 0), 0.85f) << "the naive variant should show the leak (problem case 1)";
    bleed_blend(out, s.color, naive, BleedBlendParams{}, Exec::reference());
    EXPECT_LT(out.at(lx - 3, h / 2, 0), 0.85f);
}

// WC17 Figure 9 (d-f): a bled foreground square over an un-bled background. Algorithm 1 bleeds the
// square into the background (and expands the mask there); the naive variant clips at the mask.
TEST(Bleed, Figure9BledForegroundBleedsIntoUnbledBackground) {
    const int w = 40, h = 40;
    Scene s(w, h);
    auto inside = [](int x, int y) { return x >= 14 && x < 26 && y >= 14 && y < 26; };
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            s.set(x, y, inside(x, y) ? glm::vec3(0.9f, 0.1f, 0.1f) : glm::vec3(1.0f), inside(x, y) ? 0.2f : 0.8f,
                  inside(x, y) ? 1.0f : 0.0f);
    const int bx = 12, by = 20;  // background, two pixels left of the square
    for (BleedRule rule : {BleedRule::JointBilateral, BleedRule::Mnpr}) {
        ImageF b, out;
        bleed(b, s.color, s.depth, s.ctrl, rule, full_res(), Exec::reference());
        EXPECT_GT(b.at(bx, by, 3), 0.0f) << "mask expanded into the background";
        bleed_blend(out, s.color, b, BleedBlendParams{kBleedBlendGainMnpr}, Exec::reference());
        EXPECT_LT(out.at(bx, by, 1), 0.99f) << "red bled into the white background";
        EXPECT_EQ(out.at(2, 2, 1), 1.0f) << "far background untouched";
    }
    ImageF naive, out;
    bleed(naive, s.color, s.depth, s.ctrl, BleedRule::Naive, full_res(), Exec::reference());
    bleed_blend(out, s.color, naive, BleedBlendParams{}, Exec::reference());
    EXPECT_EQ(out.at(bx, by, 1), 1.0f) << "naive bleeding is clipped at the painted mask (problem case 2)";
}

// Larger images (many row blocks on several workers) and concurrent callers: the fast traversal
// keeps per-calling-thread scratch planes, which worker threads must never confuse with their own.
TEST(Bleed, FastEqualsReferenceOnLargerImagesAndConcurrentCallers) {
    const int w = 517, h = 301;
    Scene s(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const bool fg = (x - 240) * (x - 240) + (y - 150) * (y - 150) < 10000;
            s.set(x, y, {0.1f + 0.003f * float(x % 200), 0.5f + 0.002f * float(y), fg ? 0.2f : 0.9f}, fg ? 0.2f : 0.7f,
                  fg ? 0.5f + 0.5f * std::sin(0.1f * float(x)) : (x > 400 ? 0.7f : 0.0f));
        }
    for (BleedRule rule : kRules)
        for (bool half : {false, true}) {
            BleedParams p = full_res();
            p.half_res = half;
            ImageF ref;
            bleed(ref, s.color, s.depth, s.ctrl, rule, p, Exec::reference());
            ImageF a, b;
            std::thread t1([&] { bleed(a, s.color, s.depth, s.ctrl, rule, p, Exec{4, Traversal::Fast, 16}); });
            std::thread t2([&] { bleed(b, s.color, s.depth, s.ctrl, rule, p, Exec{3, Traversal::Fast, 32}); });
            t1.join();
            t2.join();
            ASSERT_TRUE(ref.same_size(a) && ref.same_size(b));
            EXPECT_EQ(std::memcmp(ref.data(), a.data(), ref.num_values() * sizeof(float)), 0) << int(rule) << half;
            EXPECT_EQ(std::memcmp(ref.data(), b.data(), ref.num_values() * sizeof(float)), 0) << int(rule) << half;
        }
}

// The fast passes skip 256-pixel column chunks whose taps read no positive control (written as
// s + 0). Bleeding control (1: MNPR's outermost tap needs it) only in single columns exactly at
// the reach of a chunk (its first tap on the left, its last on the right) and in one short row
// (the vertical pass's reach), with -0, NaN and infinite colours in the skipped parts: the fast
// traversal must still equal the reference bit for bit (fails when a reach is one pixel short).
TEST(Bleed, FastSkipsColumnChunksWithoutControlExactly) {
    const int w = 1100, h = 90;
    Scene s(w, h);
    const int r = full_res().radius;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const bool band = x == 256 - r ||                      // chunk 1's first tap only (x 256, a = -r)
                              x == 767 + r ||                          // chunk 2's last tap only (x 767, a = r)
                              (x >= 1030 && x < 1034 && y == 40);      // one row: the V pass's reach
            const float c = x % 97 == 5 ? -0.0f : 0.2f + 0.001f * float((x * 13 + y * 7) % 500);
            s.set(x, y, {c, x % 211 == 17 ? std::nanf("") : 0.5f, x % 307 == 1 ? INFINITY : 0.25f},
                  0.3f + 0.002f * float((x + 3 * y) % 100), band ? 1.0f : (x % 5 == 0 ? -0.5f : 0.0f));
        }
    for (BleedRule rule : {BleedRule::JointBilateral, BleedRule::Mnpr})
        for (bool half : {false, true}) {
            BleedParams p = full_res();
            p.half_res = half;
            ImageF ref, fast;
            bleed(ref, s.color, s.depth, s.ctrl, rule, p, Exec::reference());
            bleed(fast, s.color, s.depth, s.ctrl, rule, p, Exec{2, Traversal::Fast, 8});
            ASSERT_TRUE(ref.same_size(fast));
            EXPECT_EQ(std::memcmp(ref.data(), fast.data(), ref.num_values() * sizeof(float)), 0) << int(rule) << half;
        }
}

// Even sizes halve exactly: the fast traversal resamples the colour, control and depth into
// planes eight outputs at a time (halve_into_planes), the reference through the tabled rows. Every
// channel of every input differs (a wrong colour or control channel, a swapped row or a dropped
// depth shows), with NaN, infinities and -0 among them; 74 x 46 gives 37 half-resolution columns
// (four blocks of eight and a tail). Zero control passes the resampled colour straight out; the
// naive rule also runs without a depth image.
TEST(Bleed, HalvingEvenSizesGivesTheTabledResampleBits) {
    const int w = 74, h = 46;
    for (bool painted : {false, true}) {
        Scene s(w, h);
        std::uint32_t q = 12345;
        auto rnd = [&] { return float((q = q * 1664525u + 1013904223u) >> 8) / 16777216.0f; };
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                for (int c = 0; c < 4; ++c) s.color.at(x, y, c) = rnd();
                for (int c = 0; c < 4; ++c) s.ctrl.at(x, y, c) = painted ? rnd() - 0.3f : (c == 2 ? 0.0f : rnd());
                s.depth.at(x, y, 0) = 0.3f + 0.0001f * float(int(5.0f * rnd()));  // steps near T: the rules see them
            }
        s.color.at(3, 5, 0) = std::nanf("");
        s.color.at(40, 7, 1) = INFINITY;
        s.color.at(73, 45, 2) = -INFINITY;
        s.color.at(16, 20, 0) = s.color.at(17, 20, 0) = s.color.at(16, 21, 0) = s.color.at(17, 21, 0) = -0.0f;
        s.depth.at(9, 9, 0) = std::nanf("");
        for (BleedRule rule : kRules)
            for (bool with_depth : {true, false}) {
                if (!with_depth && rule != BleedRule::Naive) continue;
                const ImageF none;
                const ImageF& z = with_depth ? s.depth : none;
                BleedParams p;
                p.half_res = true;
                p.radius = 3;
                ImageF ref;
                bleed(ref, s.color, z, s.ctrl, rule, p, Exec::reference());
                ASSERT_EQ(ref.width(), w / 2);
                for (int threads : {1, 3}) {
                    ImageF fast;
                    bleed(fast, s.color, z, s.ctrl, rule, p, Exec{threads, Traversal::Fast, 4});
                    ASSERT_TRUE(ref.same_size(fast));
                    EXPECT_EQ(std::memcmp(ref.data(), fast.data(), ref.num_values() * sizeof(float)), 0)
                        << "rule " << int(rule) << " painted " << painted << " depth " << with_depth << " threads " << threads;
                }
            }
    }
}

//! A colour of w x h pixels whose values (in [0, 1]) differ between neighbours and channels.
ImageF blend_colour(int w, int h) {
    ImageF c(w, h, 4);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int k = 0; k < 4; ++k) c.at(x, y, k) = float((x * 7 + y * 13 + k * 5) % 17) / 16.0f;
    return c;
}

//! The fast blend of c with b, on a copy of c in place (the CLI's schedule) or into a new image.
ImageF blend(const ImageF& c, const ImageF& b, float gain, const Exec& ex, bool in_place) {
    ImageF out;
    if (in_place) {
        out = c;
        bleed_blend(out, out, b, BleedBlendParams{gain}, ex);
    } else {
        bleed_blend(out, c, b, BleedBlendParams{gain}, ex);
    }
    return out;
}

TEST(BleedBlend, UpsamplesAHalfResolutionBleedAndRejectsOtherSizes) {
    ImageF c(9, 7, 4, 0.25f), b(5, 4, 4, 0.75f), o;
    for (std::size_t i = 3; i < b.num_values(); i += 4) b.data()[i] = 1.0f;  // mask 1
    bleed_blend(o, c, b, BleedBlendParams{}, Exec::reference());
    for (int y = 0; y < 7; ++y)
        for (int x = 0; x < 9; ++x) EXPECT_EQ(o.at(x, y, 0), 0.75f);
    ImageF wrong(6, 4, 4);
    try {
        bleed_blend(o, c, wrong, BleedBlendParams{});
        FAIL() << "accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("bleed"), std::string::npos);
    }
}

TEST(BleedBlend, GainScalesTheMaskAndSaturates) {
    ImageF c(1, 1, 4, 0.0f), b(1, 1, 4, 1.0f), o;
    b.at(0, 0, 3) = 0.1f;
    bleed_blend(o, c, b, BleedBlendParams{1.0f}, Exec::reference());
    EXPECT_NEAR(o.at(0, 0, 0), 0.1f, 1e-7f);
    bleed_blend(o, c, b, BleedBlendParams{5.0f}, Exec::reference());
    EXPECT_NEAR(o.at(0, 0, 0), 0.5f, 1e-7f);
    bleed_blend(o, c, b, BleedBlendParams{50.0f}, Exec::reference());
    EXPECT_EQ(o.at(0, 0, 0), 1.0f);
}

// The fast traversal keeps the colour of rows where nothing bleeds without blending them (in
// place: without writing them). Its bytes equal the reference's, in place and not, at half and full
// bleed size, for rows at the edges of the shortcut's premise: a mask of -0 (quiet too) or of the
// smallest positive value, a colour with -0 (+0 + -0 is +0), NaN and infinity in the colour or in a
// quiet bleed's colour, values beyond the bound, and gains 0, 1, 5, 100 and NaN.
TEST(BleedBlend, QuietRowsGiveTheReferenceBytes) {
    const int w = 37, h = 24;
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    ImageF c = blend_colour(w, h);
    c.at(5, 2, 1) = -0.0f;
    c.at(6, 3, 0) = nan;
    c.at(7, 4, 2) = inf;
    c.at(8, 5, 1) = 3e37f;
    c.at(9, 6, 3) = -0.0f;  // alpha: copied, never blended
    c.at(5, 14, 1) = -0.0f;  // the same again far from the bleeding row (half size: its rows 0-2)
    c.at(6, 16, 0) = nan;
    c.at(7, 18, 2) = inf;
    c.at(8, 20, 1) = 3e37f;
    for (int half : {1, 0}) {
        const int bw = half ? half_size(w) : w, bh = half ? half_size(h) : h;
        ImageF b(bw, bh, 4, 0.0f);  // quiet: mask +0
        for (int y = 0; y < bh; ++y)
            for (int x = 0; x < bw; ++x)
                for (int k = 0; k < 3; ++k) b.at(x, y, k) = float((x * 3 + y * 11 + k) % 9) / 8.0f;
        b.at(1, bh - 4, 3) = -0.0f;                                  // -0 mask
        b.at(2, bh - 3, 3) = std::numeric_limits<float>::denorm_min();  // bleeds a little
        b.at(3, bh - 2, 0) = nan;                                    // quiet mask, NaN colour
        b.at(4, bh - 1, 2) = -inf;
        for (int x = 0; x < bw; ++x) b.at(x, 1, 3) = 0.5f;  // a bleeding row
        for (float gain : {0.0f, 1.0f, 5.0f, 100.0f, nan}) {
            ImageF ref;
            bleed_blend(ref, c, b, BleedBlendParams{gain}, Exec::reference());
            for (const Exec& ex : {Exec::fast(1), Exec::fast(2)})
                for (bool in_place : {false, true}) {
                    const ImageF out = blend(c, b, gain, ex, in_place);
                    for (std::size_t i = 0; i < ref.num_values(); ++i) {
                        const float r = ref.data()[i], a = out.data()[i];
                        if (r != r) {
                            ASSERT_NE(a, a) << "value " << i << " half " << half << " gain " << gain;
                        } else {
                            ASSERT_EQ(std::memcmp(&a, &r, sizeof r), 0) << "value " << i << ": " << a << " vs " << r
                                                                         << " half " << half << " gain " << gain
                                                                         << " in place " << in_place;
                        }
                    }
                }
        }
    }
}

// The fast blend skips 128-pixel column chunks whose upsampling taps read only a quiet bleed (mask
// +-0, bounded values) where the colour is bounded and has no -0. One bleeding pixel of the bleed
// at a time, at and around the edges of the chunks' tap ranges (a range one column short fails),
// in rows with -0, NaN and huge colours elsewhere and a NaN bleed colour under a quiet mask: the
// reference's bytes, in place and not, half and full size, odd and even widths.
TEST(BleedBlend, QuietColumnChunksGiveTheReferenceBytes) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (int w : {421, 420}) {
        const int h = 12;
        ImageF c = blend_colour(w, h);
        c.at(300, 5, 1) = -0.0f;
        c.at(10, 6, 0) = nan;
        c.at(200, 7, 2) = 3e37f;
        for (int half : {1, 0}) {
            const int bw = half ? half_size(w) : w, bh = half ? half_size(h) : h;
            const int edges[] = {half ? 63 : 127, half ? 64 : 128, half ? 127 : 255, half ? 128 : 256};
            for (int e : edges)
                for (int d : {-1, 0, 1}) {
                    ImageF b(bw, bh, 4, 0.0f);
                    for (int y = 0; y < bh; ++y)
                        for (int x = 0; x < bw; ++x)
                            for (int k = 0; k < 3; ++k) b.at(x, y, k) = float((x * 3 + y * 11 + k) % 9) / 8.0f;
                    b.at(e + d, bh / 2, 3) = 0.75f;  // the one bleeding pixel
                    b.at(bw - 3, 1, 0) = nan;        // quiet mask, NaN colour: its chunk is blended
                    ImageF ref;
                    bleed_blend(ref, c, b, BleedBlendParams{1.0f}, Exec::reference());
                    for (bool in_place : {false, true}) {
                        const ImageF out = blend(c, b, 1.0f, Exec::fast(in_place ? 2 : 1), in_place);
                        ASSERT_EQ(std::memcmp(ref.data(), out.data(), ref.num_values() * sizeof(float)), 0)
                            << "width " << w << " half " << half << " bleeding column " << e + d << " in place " << in_place;
                    }
                }
        }
    }
}

}  // namespace
}  // namespace aq::stylize
