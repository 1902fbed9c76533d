// tests/raster/particles_test.cpp — LD06 §4.2 particles (raster/particles.h): placement and classes
// against eq. 8, 9 and 11, sprite coverage against eq. 10, additive accumulation against eq. 12,
// bounds, and the same bytes for every traversal and thread count.
#include <gtest/gtest.h>

#include <limits>

#include <cmath>

#include "core/hash.h"
#include "raster/foliage.h"
#include "raster/particles.h"
#include "raster/vertex.h"
#include "scenes/gltf_loader.h"
#include "tests/raster/raster_test_util.h"
#include "tests/test_support.h"

namespace aq::raster {
namespace {

ImplicitSurface unit_sphere_surface() {
    ImplicitSurfaceParams p;
    p.threshold = 0.25f;
    p.radius = 1.0f / std::sqrt(0.5f);  // one point's sphere of radius 1 (r sqrt(1 - sqrt(T)))
    p.cells_per_radius = 8;
    return build_implicit_surface({{0, 0, 0}}, p);
}

TEST(Particles, CountOffsetsAndClassesFollowEquations8To11) {
    const ImplicitSurface s = unit_sphere_surface();
    ParticleParams p;  // LD06: ω_quantity 30, ω_spread 0.07, h 23.8, t0 -0.5, t1 0.1
    const float plant_h = 2.0f;
    const glm::vec3 light(0, 1, 0);
    const std::vector<Particle> ps = place_particles(s, plant_h, light, p);
    EXPECT_EQ(ps.size(), std::size_t(std::llround(30.0 * 23.8 * 23.8)));  // eq. 8: 16,993
    // Eq. 9: |p - v| = ω_spread sqrt(h) in height units, scaled to the plant (v on the unit sphere).
    const float offset = 0.07f * std::sqrt(23.8f) * (plant_h / 23.8f);
    int cls[3] = {0, 0, 0};
    for (const Particle& q : ps) {
        const float r = glm::length(q.position);
        EXPECT_LE(r, 1.0f + offset + 0.02f);
        EXPECT_GE(r, 1.0f - offset - 0.02f);
        const float d = glm::dot(q.normal, light);  // eq. 11
        const int want = d <= -0.5f ? 0 : (d <= 0.1f ? 1 : 2);
        ASSERT_EQ(q.cls, want) << "n.l " << d;
        ++cls[q.cls];
    }
    // On a sphere lit from +Y, the classes' shares are about the areas of the zones: n.l <= -0.5 is
    // 1/4, (-0.5, 0.1] is 0.3, the rest 0.45 (a zone's area is proportional to its height). About:
    // surface-net vertices are denser where the surface runs diagonal to the grid.
    EXPECT_NEAR(cls[0] / double(ps.size()), 0.25, 0.06);
    EXPECT_NEAR(cls[1] / double(ps.size()), 0.30, 0.06);
    EXPECT_NEAR(cls[2] / double(ps.size()), 0.45, 0.06);
    // Seeded: the same placement every call; another seed another one.
    EXPECT_EQ(place_particles(s, plant_h, light, p)[123].position, ps[123].position);
    p.seed = 2;
    EXPECT_NE(place_particles(s, plant_h, light, p)[123].position, ps[123].position);
}

struct OneParticleScene {
    scene::Scene sc = test::scene_of({test::make_prim({{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}}, {0, 1, 2})});
    scene::Camera cam = test::look_at({0, 0, 5}, {0, 0, 0});
    PassScene ps = make_pass_scene(sc, cam, 96, 80);
};

TEST(Particles, ASpriteOfSizeSCoversAnSxSBlockAtItsProjectedCentre) {
    OneParticleScene f;
    const ImageF far(96, 80, 1, 1.0f);  // nothing in front: f_v = 1 with β = δ
    for (int s : {1, 2, 5, 8, 13}) {
        for (glm::vec3 pos : {glm::vec3(0, 0, 0), glm::vec3(0.37f, -0.21f, 0.3f)}) {
            ParticleParams p;
            p.depth_map = &far;
            p.shape = 1;
            p.size_scale = 0;
            p.size_bias = float(s) * 720.0f / 96.0f;  // eq. 10 at 96 px wide: exactly s pixels
            ImageF dark, medium, bright;
            render_particles(dark, medium, bright, f.ps, {{pos, {0, 1, 0}, 2}}, p, Exec::reference());
            int n = 0, x0 = 1 << 20, x1 = -1, y0 = 1 << 20, y1 = -1;
            for (int y = 0; y < 80; ++y)
                for (int x = 0; x < 96; ++x)
                    if (bright.at(x, y, 0) > 0.0f) {
                        ++n;
                        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
                        EXPECT_EQ(bright.at(x, y, 0), 1.0f);
                        EXPECT_EQ(dark.at(x, y, 0), 0.0f);
                    }
            EXPECT_EQ(n, s * s) << "size " << s;
            EXPECT_EQ(x1 - x0 + 1, s);
            EXPECT_EQ(y1 - y0 + 1, s);
            // The block is centred on the projected centre (within half a pixel).
            const PassViewSetup v = pass_view(f.ps, PassView::Camera, 1.0f);
            const glm::vec4 c = projection_matrix(v.camera, 96.0f / 80.0f) * v.camera.view * glm::vec4(pos, 1.0f);
            const float cx = (c.x / c.w + 1.0f) * 48.0f, cy = (1.0f - c.y / c.w) * 40.0f;
            EXPECT_NEAR(0.5f * float(x0 + x1 + 1), cx, 0.5f);
            EXPECT_NEAR(0.5f * float(y0 + y1 + 1), cy, 0.5f);
        }
    }
}

TEST(Particles, AdditiveAccumulationIsTheOrderedClampedSum) {
    OneParticleScene f;
    const glm::vec3 pos(0.1f, 0.05f, 0.2f);
    const PassViewSetup v = pass_view(f.ps, PassView::Camera, 1.0f);
    const float fd = v.normalized(-(v.camera.view * glm::vec4(pos, 1.0f)).z);
    const float D = std::min(1.0f, fd + 0.03f);
    const ImageF map(96, 80, 1, D);
    for (int copies : {1, 2, 3, 4, 7}) {
        ParticleParams p;
        p.depth_map = &map;
        p.delta = 0.1f;
        p.beta = 0.0f;
        p.shape = 1;
        p.size_scale = 0;
        p.size_bias = 6.0f * 720.0f / 96.0f;
        std::vector<Particle> qs(std::size_t(copies), Particle{pos, {0, 1, 0}, 1});
        ImageF dark, medium, bright;
        render_particles(dark, medium, bright, f.ps, qs, p, Exec::fast(2));
        const float fv = blurred_visibility(D, fd, 0.1f, 0.0f);
        ASSERT_GT(fv, 0.1f);
        ASSERT_LT(fv, 0.9f);
        float want = 0;
        for (int k = 0; k < copies; ++k) want = std::min(std::max(fv + want, 0.0f), 1.0f);
        float got = 0;
        for (int y = 0; y < 80; ++y)
            for (int x = 0; x < 96; ++x) got = std::max(got, medium.at(x, y, 0));
        EXPECT_FLOAT_EQ(got, want) << copies << " copies";
        if (copies == 7) {
            EXPECT_EQ(got, 1.0f) << "saturates at 1";
        }
    }
}

TEST(Particles, BoundsAreRefusedBeforeDrawing) {
    OneParticleScene f;
    const ImplicitSurface s = unit_sphere_surface();
    ParticleParams p;
    p.quantity = 10000;
    p.height = 1000;  // 1e10 particles
    EXPECT_THROW(place_particles(s, 1.0f, {0, 1, 0}, p), Error);
    p = {};
    p.t0 = 0.5f;
    p.t1 = 0.1f;
    EXPECT_THROW(place_particles(s, 1.0f, {0, 1, 0}, p), Error);
    const ImageF far(96, 80, 1, 1.0f);
    p = {};
    p.depth_map = &far;
    p.size_scale = 1000;
    p.size_bias = 200;
    p.scale = 4;
    const std::vector<Particle> many(200000, Particle{{0, 0, 0}, {0, 1, 0}, 0});
    ImageF a, b, c;
    EXPECT_THROW(render_particles(a, b, c, f.ps, many, p), Error);  // ~1.4e11 fragments
    p = {};
    EXPECT_THROW(render_particles(a, b, c, f.ps, many, p), Error) << "no depth map";
}

// The shared bush abstracted to its implicit surface, seen at w x h, with its camera depth map.
struct BushView {
    std::shared_ptr<const AbstractedScene> a;
    PassScene ps;
    ImageF depth;
    BushView(int w, int h) {
        static const scene::Scene bush = scene::load_gltf(test::asset("plants/ez-tree/ez_bush2.glb"));
        FoliageParams fp;
        fp.threshold = 4.0f;
        a = abstract_foliage(bush, fp);
        ps = make_pass_scene(a->scene, test::frame_scene(a->scene), w, h);
        TrianglePass dp;
        dp.value = PassValue::Depth;
        render_triangle_pass(depth, ps, dp, Exec::fast(2));
    }
};

TEST(Particles, SameBytesForEveryTraversalAndThreadCount) {
    BushView v(200, 160);
    const PassScene& ps = v.ps;
    ParticleParams p;
    p.depth_map = &v.depth;
    p.quantity = 8;
    const std::vector<Particle> qs = place_particles(v.a->surface, v.a->height, ps.light_dir, p);
    ASSERT_GT(qs.size(), 4000u);
    for (DepthTest t : {DepthTest::Blurred, DepthTest::BlurredRgba8, DepthTest::Binary}) {
        p.test = t;
        ImageF r[3];
        render_particles(r[0], r[1], r[2], ps, qs, p, Exec::reference());
        const std::string want = sha256_hex(r[0]) + sha256_hex(r[1]) + sha256_hex(r[2]);
        float sum = 0;
        for (const ImageF& m : r)
            for (int y = 0; y < m.height(); ++y)
                for (int x = 0; x < m.width(); ++x) sum += m.at(x, y, 0);
        EXPECT_GT(sum, 100.0f);
        for (int threads : {1, 2, 8}) {
            ImageF q[3];
            render_particles(q[0], q[1], q[2], ps, qs, p, Exec::fast(threads));
            EXPECT_EQ(sha256_hex(q[0]) + sha256_hex(q[1]) + sha256_hex(q[2]), want) << int(t) << " " << threads;
        }
    }
}

TEST(Particles, NonFiniteDepthsAndSquareSpritesHaveTheReferenceBytes) {
    // The fast traversal's vector rows keep every early return of the per-fragment function: a
    // saturated pixel, the blotch's corners only where D is finite, NaN and infinite D, square
    // sprites (no corners), and the binary limit δ = 0.
    BushView v(203, 157);
    const PassScene& ps = v.ps;
    ImageF& depth = v.depth;
    const float specials[] = {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                              -std::numeric_limits<float>::infinity()};
    for (int y = 0; y < depth.height(); ++y)
        for (int x = 0; x < depth.width(); ++x)
            if ((x / 9 + y / 7) % 5 == 0) depth.at(x, y, 0) = specials[(x + y) % 3];
    ParticleParams p;
    p.depth_map = &depth;
    p.quantity = 12;  // dense enough to saturate
    const std::vector<Particle> qs = place_particles(v.a->surface, v.a->height, ps.light_dir, p);
    for (int shape : {0, 1})
        for (float delta : {0.0f, 0.05f}) {
            p.shape = shape;
            p.delta = delta;
            p.beta = delta;
            ImageF r[3], q[3];
            render_particles(r[0], r[1], r[2], ps, qs, p, Exec::reference());
            render_particles(q[0], q[1], q[2], ps, qs, p, Exec::fast(2));
            int saturated = 0, nonfinite = 0;
            for (int y = 0; y < r[1].height(); ++y)
                for (int x = 0; x < r[1].width(); ++x) {
                    saturated += r[1].at(x, y, 0) == 1.0f;
                    nonfinite += !std::isfinite(r[1].at(x, y, 0));
                }
            EXPECT_GT(saturated, 50) << shape << " " << delta;
            if (delta > 0) EXPECT_GT(nonfinite, 50) << shape;  // NaN D through eq. 1's smoothstep
            else EXPECT_EQ(nonfinite, 0) << shape;              // the step maps NaN to 0
            for (int m = 0; m < 3; ++m) EXPECT_EQ(sha256_hex(q[m]), sha256_hex(r[m])) << shape << " " << delta << " map " << m;
        }
}

}  // namespace
}  // namespace aq::raster
