// tests/reference/pass_reference_test.cpp — every LD06 triangle-pass mode (raster/pass.h) against its
// GLSL twin (reference/pass_twin.h) drawn by OpenGL (llvmpipe here, a real GPU where one is lent):
// depth from the camera and the light, the lighting map, the shadow intensity with the three
// tests, intensity masks with the blurred tests and the three blend modes, on a plant with
// alpha-masked leaves and on a known occluder. Tolerances and their reasons below; the table of
// errors is printed (ctest -L reference -V).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "raster/foliage.h"
#include "raster/particles.h"
#include "raster/pass.h"
#include "raster/strokes.h"
#include "scenes/procedural.h"
#include "reference/gl_context.h"
#include "reference/pass_twin.h"
#include "scenes/gltf_loader.h"
#include "stylize/stages/gaussian_blur.h"
#include "tests/raster/raster_test_util.h"
#include "tests/test_support.h"

namespace aq::ref {
namespace {

using namespace aq::raster;

// A value differing by more than kValueTol counts as "off". Both rasterizers use 8 subpixel bits
// and the top-left rule, but they snap and interpolate differently (raster/ evaluates attributes at
// its own snapped vertices, llvmpipe at its own), and llvmpipe's bilinear filtering quantises its
// weights to 8 bits: a depth map sampled at a steep edge, or the smoothstep band of the blurred
// test, turns those small differences into visible ones on a few pixels. Bounds:
// Measured on llvmpipe (2026-11-26): at most 0.09 % of the pixels off (the bush's lighting map, at
// alpha-tested leaf edges), mean |error| at most 1.5e-4; the abstracted oak's opaque surfaces agree
// to 1e-5. The bounds leave about 5x margin for other GL implementations.
constexpr double kValueTol = 1.0 / 255.0;
constexpr double kMaxOffFraction = 0.005;  //!< of all pixels (silhouettes, leaf edges, shadow borders)
constexpr double kMaxMeanAbs = 1e-3;       //!< over all pixels
// Intensity textures (LD06 §4.3) are a photograph's texels written as values: the two rasterizers'
// UVs differ by ~1e-4 of a texel and llvmpipe's bilinear weights are 8-bit, which on the leaf
// photo's texel-scale contrast moves 1.7 % of the pixels by more than 1/255 (max 0.63, mean 3.7e-4,
// measured on llvmpipe). Bound for the fraction of such pixels:
constexpr double kMaxTextureOffFraction = 0.03;
// Particles, measured on llvmpipe: at most 0.12 % of pixels off by > 1/255 (max 0.011, at sprite
// borders), mean <= 1.9e-5; bounds with margin:
constexpr double kMaxParticleOffFraction = 0.005;
constexpr double kMaxParticleMeanAbs = 2e-4;
// Strokes: coverage is decided per pixel centre against the projected segment by the same formula
// on both sides, so only pixels whose centre lies within float rounding of a capsule's border (or
// of a tie between two segments, which GL's depth test resolves on a quantised key) may differ.
constexpr double kMaxStrokeOffFraction = 0.002;
constexpr double kMaxStrokeMeanAbs = 2e-4;

struct Case {
    std::string name;
    TrianglePass pass;
};

void compare(const std::string& scene, const PassScene& ps, const Case& c) {
    ImageF cpp;
    render_triangle_pass(cpp, ps, c.pass, Exec::fast(2));
    const ImageF gl = render_triangle_pass_gl(ps, c.pass);
    ASSERT_EQ(cpp.width(), gl.width());
    ASSERT_EQ(cpp.height(), gl.height());
    long long off = 0, nonfinite = 0;
    double sum = 0, mx = 0, nonzero = 0;
    const long long n = (long long)cpp.width() * cpp.height();
    for (int y = 0; y < cpp.height(); ++y)
        for (int x = 0; x < cpp.width(); ++x) {
            const double a = cpp.at(x, y, 0), b = gl.at(x, y, 0);
            if (!std::isfinite(a) || !std::isfinite(b)) {
                ++nonfinite;
                continue;
            }
            const double d = std::abs(a - b);
            sum += d;
            mx = std::max(mx, d);
            off += d > kValueTol;
            nonzero += a != (c.pass.value == PassValue::Depth ? 1.0 : 0.0);
        }
    const double frac = double(off) / double(n), mean = sum / double(n);
    std::printf("  %-10s %-34s mean %.2e max %.3f off %.4f (of %lld px)\n", scene.c_str(), c.name.c_str(), mean, mx, frac, n);
    EXPECT_EQ(nonfinite, 0) << c.name;
    EXPECT_GT(nonzero, 0.01 * double(n)) << c.name << ": the C++ pass drew (almost) nothing: the comparison would prove nothing";
    const bool textured = c.pass.value == PassValue::IntensityTexture;
    EXPECT_LE(frac, textured ? kMaxTextureOffFraction : kMaxOffFraction) << scene << " " << c.name;
    EXPECT_LE(mean, kMaxMeanAbs) << scene << " " << c.name;
}

std::vector<Case> cases(const ImageF* light_blur, const ImageF* depth_blur, bool intensity_textures) {
    std::vector<Case> out;
    TrianglePass p;
    p.value = PassValue::Depth;
    p.scale = 0.75f;
    out.push_back({"depth camera", p});
    p.view = PassView::Light;
    out.push_back({"depth light", p});
    p = {};
    p.value = PassValue::Lighting;
    out.push_back({"lighting", p});
    for (DepthTest t : {DepthTest::Blurred, DepthTest::BlurredRgba8, DepthTest::Binary}) {
        p = {};
        p.value = PassValue::Shadow;
        p.shadow_map = light_blur;
        p.shadow_test = t;
        p.shadow_delta = 0.02f;  // narrower than the defaults: the small bush casts visible shadows
        p.shadow_beta = 0.005f;
        out.push_back({"shadow test " + std::to_string(int(t)), p});
    }
    for (int c = 0; c < (intensity_textures ? 3 : 0); ++c) {
        p = {};
        p.value = PassValue::IntensityTexture;
        p.channel = c;
        out.push_back({"intensity texture channel " + std::to_string(c), p});
    }
    for (DepthTest t : {DepthTest::Blurred, DepthTest::BlurredRgba8})
        for (Blend b : {Blend::Replace, Blend::Add, Blend::Over}) {
            p = {};
            p.value = PassValue::Coverage;
            p.test = t;
            p.depth_map = depth_blur;
            p.delta = 0.05f;
            p.beta = 0.0f;  // inside the band for much of the plant: exercises f_v, not only 1
            p.blend = b;
            p.alpha = 0.35f;
            out.push_back({"intensity test " + std::to_string(int(t)) + " blend " + std::to_string(int(b)), p});
        }
    return out;
}

void run_all(const std::string& name, const PassScene& ps, bool intensity_textures) {
    TrianglePass lp;
    lp.value = PassValue::Depth;
    lp.view = PassView::Light;
    ImageF light, light_blur, depth, depth_blur;
    render_triangle_pass(light, ps, lp, Exec::fast(2));
    stylize::GaussianBlurParams bp;
    bp.radius = 4;
    bp.sigma = 2;
    stylize::gaussian_blur(light_blur, light, bp, Exec::fast(2));
    TrianglePass dp;
    dp.value = PassValue::Depth;
    render_triangle_pass(depth, ps, dp, Exec::fast(2));
    stylize::gaussian_blur(depth_blur, depth, bp, Exec::fast(2));
    for (const Case& c : cases(&light_blur, &depth_blur, intensity_textures)) {
        SCOPED_TRACE(c.name);
        compare(name, ps, c);
    }
}

class PassReference : public ::testing::Test {
protected:
    void SetUp() override {
        std::string why;
        if (!GlContext::shared(&why)) GTEST_FAIL() << "no OpenGL context (docs/reference.md): " << why;
    }
};

TEST_F(PassReference, PlantWithAlphaMaskedLeavesMatchesTheGlslTwin) {
    scene::Scene bush = scene::load_gltf(test::asset("plants/ez-tree/ez_bush2.glb"));
    // A light from above and behind: the branches shadow the lower leaves (the default key light,
    // from the camera's side, leaves almost no shadow to compare).
    bush.lights.push_back({glm::normalize(glm::vec3(0.3f, 1.0f, -0.6f)), glm::vec3(1), 1.0f});
    // Intensity textures (LD06 §4.3): the leaves' own texture serves as one (any RGB image does).
    for (scene::Material& m : bush.materials)
        if (m.alpha_mode == scene::AlphaMode::Mask) m.intensity_texture = m.base_color_texture;
    const scene::Camera cam = test::frame_scene(bush);
    run_all("bush", make_pass_scene(bush, cam, 240, 200), true);
}

TEST_F(PassReference, AbstractedOakMatchesTheGlslTwin) {
    const scene::Scene oak = scene::load_gltf(test::asset("plants/ez-tree/ez_oak_large_dense.glb"));
    const auto a = abstract_foliage(oak, FoliageParams{}, Exec::fast(2));
    const scene::Camera cam = test::frame_scene(a->scene);
    run_all("oak", make_pass_scene(a->scene, cam, 260, 260), false);
}

// Particles (LD06 eq. 8-12): 17,000 on the abstracted oak, three tests; GL draws them as points
// with eq. 10's size computed in the vertex shader and sums them with additive blending. Sprite
// borders differ where GL's point rule and raster/'s snapped [c - s/2, c + s/2) disagree, but the
// round blotch is ~0 there.
TEST_F(PassReference, ParticlesMatchTheGlslTwin) {
    const scene::Scene oak = scene::load_gltf(test::asset("plants/ez-tree/ez_oak_large_dense.glb"));
    const auto a = abstract_foliage(oak, FoliageParams{}, Exec::fast(2));
    const scene::Camera cam = test::frame_scene(a->scene);
    const PassScene ps = make_pass_scene(a->scene, cam, 260, 260);
    TrianglePass dp;
    dp.value = PassValue::Depth;
    ImageF depth, depth_blur;
    render_triangle_pass(depth, ps, dp, Exec::fast(2));
    stylize::gaussian_blur(depth_blur, depth, {}, Exec::fast(2));
    ParticleParams p;
    p.depth_map = &depth_blur;
    const std::vector<Particle> qs = place_particles(a->surface, a->height, ps.light_dir, p);
    for (DepthTest t : {DepthTest::Blurred, DepthTest::BlurredRgba8, DepthTest::Binary}) {
        p.test = t;
        ImageF m[3];
        render_particles(m[0], m[1], m[2], ps, qs, p, Exec::fast(2));
        const std::array<ImageF, 3> g = render_particles_gl(ps, qs, p);
        for (int k = 0; k < 3; ++k) {
            long long off = 0, drawn = 0;
            double sum = 0, mx = 0;
            const long long n = (long long)m[k].width() * m[k].height();
            for (int y = 0; y < m[k].height(); ++y)
                for (int x = 0; x < m[k].width(); ++x) {
                    const double d = std::abs(double(m[k].at(x, y, 0)) - g[std::size_t(k)].at(x, y, 0));
                    sum += d;
                    mx = std::max(mx, d);
                    off += d > kValueTol;
                    drawn += m[k].at(x, y, 0) > 0.0f;
                }
            std::printf("  oak        particles test %d class %d            mean %.2e max %.3f off %.4f (of %lld px)\n", int(t), k,
                        sum / double(n), mx, double(off) / double(n), n);
            EXPECT_GT(drawn, n / 100) << "class " << k << " drew (almost) nothing";
            EXPECT_LE(double(off) / double(n), kMaxParticleOffFraction) << "test " << int(t) << " class " << k;
            EXPECT_LE(sum / double(n), kMaxParticleMeanAbs) << "test " << int(t) << " class " << k;
        }
    }
}

// Strokes (LD06 §4.4): the procedural tree's trunk contours (hundreds of polylines) and hand-made
// strokes with normals and hatching, each depth test; GL draws each stroke's segments as quads
// (nearest segment by the depth test) and composites the strokes "over" in order.
TEST_F(PassReference, StrokesMatchTheGlslTwin) {
    const scene::Scene tree = scene::make_procedural("tree");
    const scene::Camera cam = test::frame_scene(tree);
    const PassScene ps = make_pass_scene(tree, cam, 220, 200);
    TrianglePass dp;
    dp.value = PassValue::Depth;
    ImageF depth, depth_blur;
    render_triangle_pass(depth, ps, dp, Exec::fast(2));
    stylize::gaussian_blur(depth_blur, depth, {}, Exec::fast(2));
    std::vector<Stroke> strokes = contour_strokes(ps);
    ASSERT_GT(strokes.size(), 20u);
    // Hand-made: a zig-zag across the crown with normals facing the camera, a hatching stroke.
    const scene::Bounds b = tree.world_bounds();
    const glm::vec3 c = 0.5f * (b.min + b.max), e = b.max - b.min;
    Stroke zig, hatch;
    for (int i = 0; i < 7; ++i) {
        zig.points.push_back(c + glm::vec3((float(i) / 6.0f - 0.5f) * e.x, (i % 2 ? 0.15f : -0.15f) * e.y, 0.3f * e.z));
        zig.normals.push_back(glm::normalize(glm::vec3(0.2f * float(i % 3), 0.3f, 1.0f)));
        hatch.points.push_back(c + glm::vec3(-0.3f * e.x, (float(i) / 6.0f - 0.5f) * 0.6f * e.y, 0.2f * e.z));
        hatch.normals.push_back(glm::normalize(glm::vec3(-0.5f, 0.2f * float(i), 0.7f)));
    }
    hatch.light_dependent = true;
    strokes.push_back(zig);
    strokes.push_back(hatch);
    for (DepthTest t : {DepthTest::Blurred, DepthTest::BlurredRgba8, DepthTest::Binary}) {
        StrokeParams p;
        p.test = t;
        p.width_px = 3.0f;
        p.depth_map = t == DepthTest::Binary ? &depth : &depth_blur;
        ImageF cpu;
        render_strokes(cpu, ps, strokes, p, Exec::fast(2));
        const ImageF gl = render_strokes_gl(ps, strokes, p);
        ASSERT_EQ(gl.width(), cpu.width());
        long long off = 0, drawn = 0;
        double sum = 0, mx = 0;
        const long long n = (long long)cpu.width() * cpu.height();
        for (int y = 0; y < cpu.height(); ++y)
            for (int x = 0; x < cpu.width(); ++x) {
                const double d = std::abs(double(cpu.at(x, y, 0)) - gl.at(x, y, 0));
                sum += d;
                mx = std::max(mx, d);
                off += d > kValueTol;
                drawn += cpu.at(x, y, 0) > 0.0f;
            }
        std::printf("  tree       strokes test %d (%zu strokes)        mean %.2e max %.3f off %.4f (of %lld px)\n", int(t),
                    strokes.size(), sum / double(n), mx, double(off) / double(n), n);
        EXPECT_GT(drawn, n / 200) << "the strokes drew (almost) nothing";
        EXPECT_LE(double(off) / double(n), kMaxStrokeOffFraction) << "test " << int(t);
        EXPECT_LE(sum / double(n), kMaxStrokeMeanAbs) << "test " << int(t);
    }
}

}  // namespace
}  // namespace aq::ref
