// tests/raster/pass_test.cpp — LD06 raster passes (raster/pass.h): the blurred depth test against
// LD06 eq. 1-4 written out independently, blend modes against their definitions, a soft shadow
// where the geometry puts it, views, bad input, and every pass bit-identical across traversals
// and thread counts.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "core/hash.h"
#include "raster/foliage.h"
#include "raster/pass.h"
#include "raster/vertex.h"
#include "scenes/gltf_loader.h"
#include "tests/test_support.h"
#include "tests/raster/raster_test_util.h"

namespace aq::raster {
namespace {

// LD06 eq. 1 in double precision, written from the paper (not from the implementation).
double eq1(double l, double u, double v) {
    double t = (v - l) / (u - l);
    t = t < 0 ? 0 : (t > 1 ? 1 : t);
    return 3 * t * t - 2 * t * t * t;
}

TEST(BlurredDepthTest, VisibilityEqualsEquation2AtSampledDepthDifferences) {
    for (float delta : {0.01f, 0.05f, 0.2f, 1.0f})
        for (float beta : {-0.1f, 0.0f, 0.05f, 0.3f})
            for (int k = -40; k <= 40; ++k) {
                const float fd = 0.5f;
                const float D = fd + float(k) * 0.01f;
                const double want = eq1(-delta, delta, double(D) - fd + beta);
                EXPECT_NEAR(blurred_visibility(D, fd, delta, beta), want, 2e-6)
                    << "delta " << delta << " beta " << beta << " D - fd " << D - fd;
            }
}

TEST(BlurredDepthTest, BetaEqualDeltaKeepsAnObjectJustInFrontFullyVisible) {
    // LD06 §2: with β = δ an object A in front of B (A_d <= B_d) stays fully visible.
    for (float delta : {0.001f, 0.02f, 0.1f, 0.5f})
        for (float gap : {0.0f, 1e-4f, 0.01f, 0.2f}) {
            const float B = 0.6f, A = B - gap;  // the map holds B, the fragment is A
            EXPECT_EQ(blurred_visibility(B, A, delta, delta), 1.0f) << delta << " " << gap;
        }
    // Without the shift the same fragment is only half visible at zero gap.
    EXPECT_FLOAT_EQ(blurred_visibility(0.6f, 0.6f, 0.1f, 0.0f), 0.5f);
}

TEST(BlurredDepthTest, DeltaZeroIsTheBinaryTest) {
    EXPECT_EQ(blurred_visibility(0.5f, 0.5f, 0.0f, 0.0f), 1.0f);   // equal depth: visible
    EXPECT_EQ(blurred_visibility(0.5f, 0.5001f, 0.0f, 0.0f), 0.0f);  // behind: hidden
    EXPECT_EQ(blurred_visibility(0.5f, 0.4f, 0.0f, 0.0f), 1.0f);   // in front: visible
    EXPECT_EQ(ld06_step(0.3f, 0.3f, 0.29f), 0.0f);
    EXPECT_EQ(ld06_step(0.3f, 0.3f, 0.3f), 1.0f);
}

TEST(BlurredDepthTest, Rgba8CodingHasAboutTenBitsAndIsExactAtTheBreaks) {
    // LD06 eq. 3-4: four 8-bit channels over [0, .25, .5, .75, 1]; the error is at most half a
    // step of one channel, 0.5 / 255 / 4.
    std::set<float> levels;
    float prev = -1;
    for (int i = 0; i <= 100000; ++i) {
        const float d = float(i) / 100000.0f;
        const float q = quantize_depth_rgba8(d);
        EXPECT_LE(std::abs(q - d), 0.5f / 255.0f / 4.0f + 1e-6f) << d;
        EXPECT_GE(q, prev) << "not monotone at " << d;
        prev = q;
        levels.insert(q);
    }
    EXPECT_EQ(levels.size(), 4u * 255u + 1u);  // 1021 levels: log2 ~ 10 bits
    for (float d : {0.0f, 0.25f, 0.5f, 0.75f, 1.0f}) EXPECT_EQ(quantize_depth_rgba8(d), d);
    EXPECT_EQ(quantize_depth_rgba8(-3.0f), 0.0f);
    EXPECT_EQ(quantize_depth_rgba8(7.0f), 1.0f);
}

// ---- Scenes built in code --------------------------------------------------------------------

// A horizontal quad at height y, half size s, normal +Y (CCW seen from above).
scene::Primitive quad_y(float y, float s) {
    return test::make_prim({{-s, y, -s}, {-s, y, s}, {s, y, s}, {s, y, -s}}, {0, 1, 2, 0, 2, 3});
}

scene::Scene with_up_normals(std::vector<scene::Primitive> prims) {
    for (auto& p : prims) p.normals.assign(p.positions.size(), glm::vec3(0, 1, 0));
    scene::Scene s = test::scene_of(std::move(prims));
    s.materials[0].double_sided = true;
    return s;
}

// Pixel of a world point in a camera pass of size w x h (the rasterizer's mapping).
glm::vec2 pixel_of(const scene::Camera& cam, glm::vec3 world, int w, int h) {
    const glm::vec4 c = projection_matrix(cam, float(w) / float(h)) * cam.view * glm::vec4(world, 1.0f);
    return {(c.x / c.w + 1.0f) * 0.5f * float(w), (1.0f - c.y / c.w) * 0.5f * float(h)};
}

float at(const ImageF& img, glm::vec2 p) { return img.at(int(p.x), int(p.y), 0); }

TEST(RasterPass, SoftShadowLandsWhereTheGeometrySays) {
    // Ground (half size 2) at y = 0, occluder (half size 0.5) at y = 1, light straight down: the
    // shadow is the occluder's square on the ground. The camera is below the occluder's plane, so
    // it sees the ground under it.
    scene::Scene sc = with_up_normals({quad_y(0.0f, 2.0f), quad_y(1.0f, 0.5f)});
    sc.lights.push_back({glm::vec3(0, 1, 0), glm::vec3(1), 1.0f});
    const scene::Camera cam = test::look_at({0.0f, 0.6f, 4.0f}, {0, 0, 0});
    const int W = 200, H = 160;
    const PassScene ps = make_pass_scene(sc, cam, W, H);

    TrianglePass light;
    light.view = PassView::Light;
    light.value = PassValue::Depth;
    ImageF light_depth;
    render_triangle_pass(light_depth, ps, light, Exec::fast(2));
    ASSERT_EQ(light_depth.width(), 200);
    ASSERT_EQ(light_depth.height(), 200);

    TrianglePass sh;
    sh.value = PassValue::Shadow;
    sh.shadow_map = &light_depth;
    sh.shadow_delta = 0.02f;
    sh.shadow_beta = 0.025f;  // β >= δ: a lit surface against its own depth stays fully lit
    ImageF shadow;
    render_triangle_pass(shadow, ps, sh, Exec::fast(2));
    ASSERT_EQ(shadow.width(), W);
    ASSERT_EQ(shadow.height(), H);
    int n = 0;
    for (float x = -0.4f; x <= 0.41f; x += 0.1f)
        for (float z = -0.3f; z <= 0.31f; z += 0.15f, ++n)
            EXPECT_EQ(at(shadow, pixel_of(cam, {x, 0.0f, z}, W, H)), 1.0f) << "ground under the occluder " << x << "," << z;
    EXPECT_GT(n, 30);
    for (glm::vec3 lit : {glm::vec3(1.5f, 0, 0.8f), glm::vec3(-1.2f, 0, 1.5f), glm::vec3(0.0f, 0, 1.2f)})
        EXPECT_EQ(at(shadow, pixel_of(cam, lit, W, H)), 0.0f) << "lit ground " << lit.x << "," << lit.z;
    EXPECT_EQ(at(shadow, pixel_of(cam, {0.0f, 1.0f, 0.3f}, W, H)), 0.0f) << "the occluder itself";
    EXPECT_EQ(shadow.at(0, 0, 0), 0.0f) << "background";
}

TEST(RasterPass, ConstantDepthMapGivesTheVisibilityOfEachFragmentAndAddSaturates) {
    // k copies of one quad drawn with additive blending: the pixel is the ordered, clamped sum of
    // the same f_v k times (LD06 eq. 12), f_v from eq. 2 with the fragment's depth.
    const scene::Camera cam = test::look_at({0.0f, 3.0f, 0.01f}, {0, 0, 0});
    const int W = 64, H = 48;
    for (int copies : {1, 2, 3, 5}) {
        std::vector<scene::Primitive> prims;
        for (int k = 0; k < copies; ++k) prims.push_back(quad_y(0.0f, 1.0f));
        prims.push_back(quad_y(-1.0f, 0.01f));  // extends the depth range so the quad is mid-range
        prims.push_back(quad_y(1.0f, 0.01f));
        const scene::Scene sc = with_up_normals(std::move(prims));
        const PassScene ps = make_pass_scene(sc, cam, W, H);
        TrianglePass dp;
        dp.value = PassValue::Depth;
        ImageF depth;
        render_triangle_pass(depth, ps, dp, Exec::reference());
        const ImageF constant(W, H, 1, 0.45f);
        TrianglePass ip;
        ip.test = DepthTest::Blurred;
        ip.depth_map = &constant;
        ip.delta = 0.2f;
        ip.beta = 0.0f;
        ip.blend = Blend::Add;
        ImageF acc;
        render_triangle_pass(acc, ps, ip, Exec::fast(2));
        const int x = W / 2 + 3, y = H / 2 + 2;
        const float fd = depth.at(x, y, 0);
        ASSERT_GT(fd, 0.2f);
        ASSERT_LT(fd, 0.8f);
        const float fv = blurred_visibility(0.45f, fd, 0.2f, 0.0f);
        ASSERT_GT(fv, 0.05f);
        ASSERT_LT(fv, 0.95f);
        float want = 0;
        for (int k = 0; k < copies; ++k) want = std::min(std::max(want + fv, 0.0f), 1.0f);
        EXPECT_EQ(acc.at(x, y, 0), want) << copies << " copies";
        if (copies >= 5) {
            EXPECT_EQ(acc.at(x, y, 0), 1.0f) << "saturates at 1";
        }
    }
}

TEST(RasterPass, BlendModesFollowTheirDefinitions) {
    const scene::Camera cam = test::look_at({0.0f, 3.0f, 0.01f}, {0, 0, 0});
    const scene::Scene sc = with_up_normals({quad_y(0.0f, 1.0f), quad_y(0.5f, 0.3f)});
    const PassScene ps = make_pass_scene(sc, cam, 40, 40);
    const ImageF far(40, 40, 1, 1.0f);  // nothing occludes: f_v = 1 with β = δ
    TrianglePass p;
    p.test = DepthTest::Blurred;
    p.depth_map = &far;
    p.delta = p.beta = 0.05f;
    p.blend = Blend::Over;
    p.alpha = 0.25f;
    ImageF over;
    render_triangle_pass(over, ps, p, Exec::reference());
    // Centre: both quads, in submission order: 0.25, then 1·0.25 + 0.25·0.75.
    EXPECT_FLOAT_EQ(over.at(20, 20, 0), 0.25f + 0.25f * 0.75f);
    EXPECT_FLOAT_EQ(over.at(8, 20, 0), 0.25f);  // only the large quad
    EXPECT_EQ(over.at(0, 0, 0), 0.0f);          // background
    p.blend = Blend::Replace;
    ImageF rep;
    render_triangle_pass(rep, ps, p, Exec::reference());
    EXPECT_EQ(rep.at(20, 20, 0), 1.0f);
    // Binary test: the small quad is nearer the camera (y = 0.5) and wins wherever it covers.
    TrianglePass dp;
    dp.value = PassValue::Depth;
    ImageF depth;
    render_triangle_pass(depth, ps, dp, Exec::reference());
    EXPECT_LT(depth.at(20, 20, 0), depth.at(8, 20, 0));
    EXPECT_EQ(depth.at(0, 0, 0), 1.0f);  // background is far
}

TEST(RasterPass, LightingMapIsHalfLambertOfTheLight) {
    const scene::Camera cam = test::look_at({0.0f, 3.0f, 0.01f}, {0, 0, 0});
    for (glm::vec3 l : {glm::vec3(0, 1, 0), glm::vec3(1, 1, 0), glm::vec3(0, -1, 0), glm::vec3(1, 0, 0)}) {
        scene::Scene sc = with_up_normals({quad_y(0.0f, 1.0f)});
        sc.lights.push_back({l, glm::vec3(1), 1.0f});
        const PassScene ps = make_pass_scene(sc, cam, 32, 32);
        TrianglePass p;
        p.value = PassValue::Lighting;
        ImageF lit;
        render_triangle_pass(lit, ps, p, Exec::reference());
        const float want = (1.0f + glm::normalize(l).y) * 0.5f;  // n = +Y, facing the camera
        EXPECT_NEAR(lit.at(16, 16, 0), want, 1e-6f) << l.x << "," << l.y << "," << l.z;
    }
}

TEST(RasterPass, IntensityTextureChannelsAreSampledOnTheFrontMostSurface) {
    // A quad with UVs over the view carrying a 2 x 2 intensity texture (nearest), and a smaller
    // quad in front without one: it occludes and writes 0 (LD06 §4.3).
    const scene::Camera cam = test::look_at({0.0f, 3.0f, 0.01f}, {0, 0, 0});
    scene::Scene sc = with_up_normals({quad_y(0.0f, 1.0f), quad_y(0.5f, 0.2f)});
    sc.meshes[0].primitives[0].uv0 = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};
    scene::Material textured = sc.materials[0];
    ImageF img(2, 2, 3);
    const float texels[2][2][3] = {{{0.1f, 0.2f, 0.3f}, {0.4f, 0.5f, 0.6f}}, {{0.7f, 0.8f, 0.9f}, {0.15f, 0.25f, 0.35f}}};
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 2; ++x)
            for (int c = 0; c < 3; ++c) img.at(x, y, c) = texels[y][x][c];
    sc.textures.push_back({"intensity", img, false, {}});
    textured.intensity_texture.texture = 0;
    textured.intensity_texture.sampler.mag = scene::Filter::Nearest;
    sc.materials.push_back(textured);
    sc.meshes[0].primitives[0].material = 1;
    const PassScene ps = make_pass_scene(sc, cam, 48, 48);
    ImageF ch[3];
    for (int c = 0; c < 3; ++c) {
        TrianglePass p;
        p.value = PassValue::IntensityTexture;
        p.channel = c;
        render_triangle_pass(ch[c], ps, p, Exec::fast(2));
        ImageF ref;
        render_triangle_pass(ref, ps, p, Exec::reference());
        EXPECT_EQ(sha256_hex(ref), sha256_hex(ch[c])) << "channel " << c;
    }
    // Each texel's quadrant of the quad shows that texel's channel values, and the occluder 0.
    int seen = 0;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 48; ++x) {
            const float r = ch[0].at(x, y, 0);
            if (r == 0.0f) continue;
            bool found = false;
            for (const auto& row : texels)
                for (const auto& t : row)
                    found = found || (r == t[0] && ch[1].at(x, y, 0) == t[1] && ch[2].at(x, y, 0) == t[2]);
            EXPECT_TRUE(found) << x << "," << y;
            ++seen;
        }
    EXPECT_GT(seen, 48 * 48 / 3);
    EXPECT_EQ(ch[0].at(24, 24, 0), 0.0f) << "the occluder has no intensity texture";
    TrianglePass bad;
    bad.value = PassValue::IntensityTexture;
    bad.channel = 3;
    ImageF out;
    EXPECT_THROW(render_triangle_pass(out, ps, bad), Error);
}

TEST(RasterPass, ViewsAndScales) {
    const scene::Scene sc = with_up_normals({quad_y(0.0f, 1.0f), quad_y(1.0f, 0.5f)});
    const scene::Camera cam = test::look_at({0.0f, 4.0f, 4.5f}, {0, 0, 0});
    const PassScene ps = make_pass_scene(sc, cam, 720, 480);
    const PassViewSetup c = pass_view(ps, PassView::Camera, 520.0f / 720.0f);
    EXPECT_EQ(c.width, 520);
    EXPECT_EQ(c.height, 347);
    const PassViewSetup l = pass_view(ps, PassView::Light, 0.5f);
    EXPECT_EQ(l.width, 360);
    EXPECT_EQ(l.height, 360);
    // The light view holds the whole bounding sphere: every corner of the bounds maps inside the
    // map and inside the normalised depth range.
    for (int k = 0; k < 8; ++k) {
        const glm::vec3 p((k & 1) ? 1.0f : -1.0f, (k & 2) ? 1.0f : 0.0f, (k & 4) ? 1.0f : -1.0f);
        const LightSample s = light_space(l, p, l.width, l.height);
        EXPECT_GE(s.x, 0.0f);
        EXPECT_LE(s.x, float(l.width));
        EXPECT_GE(s.y, 0.0f);
        EXPECT_LE(s.y, float(l.height));
        EXPECT_GE(s.depth, 0.0f);
        EXPECT_LE(s.depth, 1.0f);
    }
}

TEST(RasterPass, BadInputIsRefusedOrReported) {
    const scene::Camera cam = test::look_at({0.0f, 4.0f, 4.5f}, {0, 0, 0});
    const scene::Scene sc = with_up_normals({quad_y(0.0f, 1.0f)});
    const PassScene ps = make_pass_scene(sc, cam, 64, 64);
    ImageF out;
    TrianglePass p;
    p.scale = 0.0f;
    EXPECT_THROW(render_triangle_pass(out, ps, p), Error);
    p.scale = 100.0f;
    EXPECT_THROW(render_triangle_pass(out, ps, p), Error);
    p = {};
    p.test = DepthTest::Blurred;  // no depth map
    EXPECT_THROW(render_triangle_pass(out, ps, p), Error);
    p = {};
    p.delta = std::nanf("");
    EXPECT_THROW(render_triangle_pass(out, ps, p), Error);
    p = {};
    p.value = PassValue::Shadow;  // no shadow map
    EXPECT_THROW(render_triangle_pass(out, ps, p), Error);
    // A foliage selection that matches nothing: an empty map and a warning.
    p = {};
    p.draw = DrawSet::Foliage;
    std::vector<std::string> warnings;
    render_triangle_pass(out, ps, p, Exec::fast(2), &warnings);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("foliage"), std::string::npos);
    for (int i = 0; i < 64 * 64; ++i) ASSERT_EQ(out.data()[i], 0.0f);
    // A scene that is one point has no light frustum.
    const scene::Scene dot = test::scene_of({test::make_prim({{1, 2, 3}, {1, 2, 3}, {1, 2, 3}}, {0, 1, 2})});
    const PassScene pd = make_pass_scene(dot, cam, 64, 64);
    EXPECT_THROW(pass_view(pd, PassView::Light, 1.0f), Error);
    // A scene with nothing finite.
    const scene::Scene nan = test::scene_of({test::make_prim({{NAN, 0, 0}, {0, NAN, 0}, {0, 0, NAN}}, {0, 1, 2})});
    EXPECT_THROW(make_pass_scene(nan, cam, 64, 64), Error);
}

// Every pass kind on a real plant (alpha-masked, double-sided leaves): the reference traversal
// and the tiled one with 1, 2 and 8 threads give the same bytes.
TEST(RasterPass, EveryPassIsBitIdenticalAcrossTraversalsAndThreads) {
    const scene::Scene sc = scene::load_gltf(test::asset("plants/ez-tree/ez_bush2.glb"));
    const scene::Camera cam = test::frame_scene(sc);
    const PassScene ps = make_pass_scene(sc, cam, 180, 150);
    ImageF light_depth, cam_depth;
    {
        TrianglePass p;
        p.view = PassView::Light;
        p.value = PassValue::Depth;
        render_triangle_pass(light_depth, ps, p, Exec::reference());
        p.view = PassView::Camera;
        render_triangle_pass(cam_depth, ps, p, Exec::reference());
    }
    std::vector<std::pair<std::string, TrianglePass>> cases;
    auto add = [&](const std::string& name, TrianglePass p) { cases.emplace_back(name, p); };
    TrianglePass p;
    p.value = PassValue::Depth;
    p.view = PassView::Light;
    add("light depth", p);
    p.view = PassView::Camera;
    p.draw = DrawSet::Foliage;
    add("camera depth, foliage", p);
    p = {};
    p.value = PassValue::Lighting;
    p.scale = 0.72f;
    add("lighting", p);
    p = {};
    p.value = PassValue::Shadow;
    p.shadow_map = &light_depth;
    for (DepthTest t : {DepthTest::Binary, DepthTest::Blurred, DepthTest::BlurredRgba8}) {
        p.shadow_test = t;
        add("shadow " + std::to_string(int(t)), p);
    }
    p = {};
    p.depth_map = &cam_depth;
    p.draw = DrawSet::Foliage;
    for (DepthTest t : {DepthTest::Blurred, DepthTest::BlurredRgba8})
        for (Blend b : {Blend::Replace, Blend::Add, Blend::Over}) {
            p.test = t;
            p.blend = b;
            p.alpha = 0.4f;
            add("intensity " + std::to_string(int(t)) + "/" + std::to_string(int(b)), p);
        }
    for (auto& [name, pass] : cases) {
        ImageF ref;
        render_triangle_pass(ref, ps, pass, Exec::reference());
        float sum = 0;
        for (std::size_t i = 0; i < std::size_t(ref.width()) * ref.height(); ++i) sum += ref.data()[i];
        EXPECT_GT(sum, 1.0f) << name << ": drew nothing";
        const std::string want = sha256_hex(ref);
        for (int threads : {1, 2, 8}) {
            ImageF fast;
            render_triangle_pass(fast, ps, pass, Exec::fast(threads));
            EXPECT_EQ(sha256_hex(fast), want) << name << ", " << threads << " thread(s)";
        }
    }
    // One frame's passes sharing prepared frames (PassFrameCache, as the render job does): every
    // pass gives the bytes it gives alone, in any order, and same-view passes share one entry.
    for (bool reverse : {false, true}) {
        PassFrameCache frames;
        PassScene shared = ps;
        shared.frames = &frames;
        for (std::size_t k = 0; k < cases.size(); ++k) {
            const auto& [name, pass] = cases[reverse ? cases.size() - 1 - k : k];
            ImageF alone, with_cache;
            render_triangle_pass(alone, ps, pass, Exec::fast(2));
            render_triangle_pass(with_cache, shared, pass, Exec::fast(2));
            EXPECT_EQ(sha256_hex(with_cache), sha256_hex(alone)) << name << (reverse ? " (reverse order)" : "");
        }
        // light depth; camera foliage at scale 1 (depth and intensity share it); lighting at 0.72;
        // camera all at scale 1 (the shadows)
        EXPECT_EQ(frames.entries.size(), 4u);
    }
}

// Layer IDs with foliage_layer off (the ld06 preset's crown painted by the particle layers): the
// implicit surface still occludes the trunk behind it but writes the background; elsewhere the
// IDs are those of the default.
TEST(RasterPass, FoliageCanOccludeAsBackgroundInTheIdMaps) {
    const scene::Scene bush = scene::load_gltf(test::asset("plants/ez-tree/ez_bush2.glb"));
    FoliageParams fp;
    fp.fit = true;
    const auto a = abstract_foliage(bush, fp);
    ASSERT_TRUE(a->abstracted);
    const scene::LayerTable layers = abstracted_layer_table(bush, *a);
    PassScene ps = make_pass_scene(a->scene, test::frame_scene(a->scene), 160, 140);
    ps.layers = &layers;
    const int foliage_id = layers.of(a->surface_object_id, a->surface_material) + 1;
    for (PassValue v : {PassValue::LayerId, PassValue::ObjectId}) {
        TrianglePass p;
        p.value = v;
        ImageF with, without, trunk_only;
        render_triangle_pass(with, ps, p, Exec::fast(2));
        p.foliage_layer = false;
        render_triangle_pass(without, ps, p, Exec::reference());
        ImageF fast;
        render_triangle_pass(fast, ps, p, Exec::fast(2));
        EXPECT_EQ(sha256_hex(fast), sha256_hex(without));
        p.foliage_layer = true;
        p.draw = DrawSet::NonFoliage;
        render_triangle_pass(trunk_only, ps, p, Exec::fast(2));
        const float fid = v == PassValue::LayerId ? float(foliage_id) : float(a->surface_object_id);
        long crown = 0, hidden_trunk = 0;
        for (int y = 0; y < with.height(); ++y)
            for (int x = 0; x < with.width(); ++x) {
                if (with.at(x, y, 0) == fid) {
                    ++crown;
                    EXPECT_EQ(without.at(x, y, 0), 0.0f) << "the surface writes the background";
                    hidden_trunk += trunk_only.at(x, y, 0) != 0.0f;
                } else {
                    EXPECT_EQ(without.at(x, y, 0), with.at(x, y, 0)) << "other IDs unchanged";
                }
            }
        EXPECT_GT(crown, 500);
        EXPECT_GT(hidden_trunk, 10) << "the surface still hides trunk behind it";
    }
}

}  // namespace
}  // namespace aq::raster
