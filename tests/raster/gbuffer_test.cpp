// tests/raster/gbuffer_test.cpp — G-buffer contents: perspective-correct interpolation against an
// analytic answer, depth ordering, normals, IDs, controls, SSAA resolve, tiled == reference on
// real models, determinism across threads and runs, hand tremor, size validation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "core/io.h"
#include "raster/material.h"
#include "raster/raster.h"
#include "scenes/gltf_loader.h"
#include "tests/raster/raster_test_util.h"
#include "tests/test_support.h"

using namespace aq;
using aq::test::px;

namespace {

void expect_same_targets(const Targets& a, const Targets& b, const std::string& what) {
    ASSERT_EQ(a.names(), b.names()) << what;
    for (const auto& [name, img] : a.all()) {
        const std::string ha = sha256_hex(img), hb = sha256_hex(b.get(name));
        if (ha != hb) {
            const std::string dir = test::output_dir();
            write_image(dir + "/" + what + "_a_" + safe_file_name(name) + ".exr", img);
            write_image(dir + "/" + what + "_b_" + safe_file_name(name) + ".exr", b.get(name));
            ADD_FAILURE() << what << ": target " << name << " differs (images in " << dir << ")";
        }
    }
}

// A tilted plane with uv (0..1) and a 256x1 ramp texture whose red = u: colour red is u.
struct TiltedPlane {
    scene::Scene scene;
    glm::vec3 p0{-2.0f, -1.0f, -2.0f}, pu{4.0f, 0, 0}, pv{0, 2.5f, -9.0f};  // P = p0 + u pu + v pv
};
TiltedPlane tilted_plane() {
    TiltedPlane t;
    scene::Material m = test::flat_material();
    scene::Texture tex;
    tex.image = ImageF(256, 1, 4);
    for (int i = 0; i < 256; ++i) {
        tex.image.at(i, 0, 0) = (float(i) + 0.5f) / 256.0f;
        tex.image.at(i, 0, 3) = 1.0f;
    }
    t.scene.textures.push_back(tex);
    m.base_color_texture.texture = 0;
    m.base_color_texture.sampler.wrap_s = scene::Wrap::ClampToEdge;
    scene::Primitive p = test::make_prim({t.p0, t.p0 + t.pu, t.p0 + t.pu + t.pv, t.p0 + t.pv}, {0, 1, 2, 0, 2, 3});
    p.uv0 = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    // The same (u, v) in the pigment control (R = 2u - 1, G = 2v - 1): a second, texture-free check.
    p.control[scene::kCtrlPigment] = {{-1, -1, 0, 0}, {1, -1, 0, 0}, {1, 1, 0, 0}, {-1, 1, 0, 0}};
    t.scene = test::scene_of({p}, m);
    t.scene.textures.push_back(tex);
    return t;
}

}  // namespace

TEST(Interpolation, PerspectiveCorrectOnTiltedTexturedPlane) {
    const int W = 96, H = 72;
    const TiltedPlane tp = tilted_plane();
    const float fov = 0.9f;
    const scene::Camera cam = test::look_at({0, 0, 1}, {0, 0, -1}, fov);  // view = translate(0,0,-1)
    raster::RenderSettings st = test::plain_settings(W, H);
    const Targets t = raster::render_gbuffer(tp.scene, cam, st);
    const ImageF& col = t.get(target::kColor);
    const ImageF& ctl = t.get(target::kCtrlPigment);
    const double th = std::tan(0.5 * fov), aspect = double(W) / H;
    const glm::dvec3 eye(0, 0, 1), p0(tp.p0), pu(tp.pu), pv(tp.pv);
    const glm::dvec3 n = glm::cross(pu, pv);
    int checked = 0;
    double max_affine_gap = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const glm::dvec3 dir((2.0 * (x + 0.5) / W - 1.0) * th * aspect, (1.0 - 2.0 * (y + 0.5) / H) * th, -1.0);
            const double s = glm::dot(p0 - eye, n) / glm::dot(dir, n);
            const glm::dvec3 q = eye + dir * s - p0;
            // Solve q = u pu + v pv (pu along x, pv in the y-z plane).
            const double u = q.x / pu.x, v = q.y / pv.y;
            if (u < 0.01 || u > 0.99 || v < 0.01 || v > 0.99) continue;
            ASSERT_EQ(col.at(x, y, 3), 1.0f) << x << "," << y;
            // Texture: red = u (linear ramp; bilinear is exact on it away from the clamp band).
            if (u > 0.01 && u < 0.99) { ASSERT_NEAR(col.at(x, y, 0), u, 2e-4) << x << "," << y; }
            ASSERT_NEAR(ctl.at(x, y, 0), 2 * u - 1, 4e-4) << x << "," << y;
            ASSERT_NEAR(ctl.at(x, y, 1), 2 * v - 1, 4e-4) << x << "," << y;
            // Linear eye depth = -(view-space z) of the hit point.
            ASSERT_NEAR(t.get(target::kDepthLinear).at(x, y, 0), s, s * 1e-4);
            ++checked;
            // How far screen-affine interpolation would be off: v at the pixel vs the v of the
            // screen-space lerp between the projected near and far edges (big: the test has teeth).
            const double y_near = (p0.y - eye.y) / -(p0.z - eye.z), y_far = (p0.y + pv.y) / -(p0.z + pv.z - eye.z);
            const double sy = dir.y / th * th;  // screen y of this pixel in tan units
            const double v_affine = (sy - y_near) / (y_far - y_near);
            max_affine_gap = std::max(max_affine_gap, std::abs(v_affine - v));
        }
    EXPECT_GT(checked, 1000);
    EXPECT_GT(max_affine_gap, 0.05) << "plane not tilted enough to tell perspective from affine";
}

TEST(GBuffer, DepthOrderingIdsAndNormals) {
    const int W = 48, H = 48;
    // Far quad (id 1) submitted first, near quad (id 2) second, then a third far one (id 3)
    // overlapping the near one: the nearest wins regardless of order.
    auto quad = [&](float x0, float y0, float x1, float y1, float z) {
        return test::make_prim({px(W, H, x0, y0, z), px(W, H, x0, y1, z), px(W, H, x1, y1, z), px(W, H, x1, y0, z)},
                               {0, 1, 2, 0, 2, 3});
    };
    scene::Scene s = test::scene_of({quad(4, 4, 30, 30, -10), quad(16, 16, 44, 44, -5), quad(20, 20, 40, 40, -20)});
    // A tilted triangle (id 4): normal given by the vertex normals.
    scene::Primitive tilt = test::make_prim({px(W, H, 2, 40, -3), px(W, H, 12, 40, -3), px(W, H, 2, 47, -3)}, {0, 2, 1});
    const glm::vec3 nt = glm::normalize(glm::vec3(0.3f, -0.4f, 0.866f));
    tilt.normals.assign(3, nt);
    s.meshes.push_back({"tilt", {tilt}});
    s.instances.push_back({3, glm::mat4(1.0f), 4, "tilt"});
    for (Traversal tr : {Traversal::Fast, Traversal::Reference}) {
        raster::RenderSettings st = test::plain_settings(W, H);
        st.exec.traversal = tr;
        const Targets t = raster::render_gbuffer(s, test::pixel_camera(W, H), st);
        const ImageF& id = t.get(target::kObjectId);
        const ImageF& d = t.get(target::kDepthLinear);
        const ImageF& n = t.get(target::kNormal);
        EXPECT_EQ(id.at(8, 8, 0), 1.0f);
        EXPECT_FLOAT_EQ(d.at(8, 8, 0), 10.0f);
        EXPECT_EQ(id.at(25, 25, 0), 2.0f);  // near quad over both far ones
        EXPECT_FLOAT_EQ(d.at(25, 25, 0), 5.0f);
        EXPECT_EQ(id.at(42, 42, 0), 2.0f);
        EXPECT_EQ(id.at(46, 2, 0), 0.0f);  // background
        EXPECT_EQ(d.at(46, 2, 0), 100.0f); // background depth = zfar
        EXPECT_EQ(t.get(target::kColor).at(46, 2, 3), 0.0f);
        EXPECT_EQ(t.get(target::kColor).at(25, 25, 3), 1.0f);
        EXPECT_EQ(id.at(4, 44, 0), 4.0f);
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(n.at(25, 25, c), c == 2 ? 1.0f : 0.0f, 1e-6);
            EXPECT_NEAR(n.at(4, 44, c), nt[c], 1e-5);
        }
    }
}

TEST(GBuffer, ControlTargetsCombineVertexMaterialAndClamp) {
    const int W = 16, H = 16;
    scene::Primitive p = test::make_prim({px(W, H, 0, 0), px(W, H, 0, 16), px(W, H, 16, 16), px(W, H, 16, 0)},
                                         {0, 1, 2, 0, 2, 3});
    p.control[scene::kCtrlEdge].assign(4, glm::vec4(0.25f, -0.5f, 0.75f, 0));
    scene::Material m;
    m.wc.control[scene::kCtrlEdge] = glm::vec4(0.5f, 0.0f, 0.5f, 0);
    m.wc.control[scene::kCtrlSubstrate] = glm::vec4(-0.3f, 0.2f, 0.1f, 0);
    const Targets t = raster::render_gbuffer(test::scene_of({p}, m), test::pixel_camera(W, H), test::plain_settings(W, H));
    const ImageF& e = t.get(target::kCtrlEdge);
    EXPECT_FLOAT_EQ(e.at(5, 5, 0), 0.75f);
    EXPECT_FLOAT_EQ(e.at(5, 5, 1), -0.5f);
    EXPECT_FLOAT_EQ(e.at(5, 5, 2), 1.0f);  // 1.25 clamped to [-1, 1]
    EXPECT_FLOAT_EQ(e.at(5, 5, 3), 1.0f);  // coverage
    const ImageF& su = t.get(target::kCtrlSubstrate);
    EXPECT_FLOAT_EQ(su.at(9, 3, 0), -0.3f);
    EXPECT_FLOAT_EQ(su.at(9, 3, 1), 0.2f);
    EXPECT_FLOAT_EQ(t.get(target::kCtrlPigment).at(9, 3, 0), 0.0f);
    EXPECT_EQ(t.get(target::kCtrlPigment).channels(), 4);
}

// The base colour (material step 1) per fragment where COLOR_0 or a texture varies it, and the
// draw's constant otherwise (computed once per draw): both traversals, both working spaces.
TEST(GBuffer, BaseColourFollowsVertexColoursAndIsTheMaterialsColourWithout) {
    const int W = 16, H = 16;
    auto quad = [&](float x0, float x1) {
        return test::make_prim({px(W, H, x0, 0), px(W, H, x0, 16), px(W, H, x1, 16), px(W, H, x1, 0)},
                               {0, 1, 2, 0, 2, 3});
    };
    scene::Primitive ramp = quad(0, 8), plain = quad(8, 16);
    ramp.colors = {{1, 0, 0, 1}, {1, 0, 0, 1}, {0, 0, 1, 1}, {0, 0, 1, 1}};  // red at x = 0, blue at 8
    plain.uv0 = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};  // uv, but the texture index names no texture
    plain.material = 1;
    scene::Scene s = test::scene_of({ramp, plain}, test::flat_material(glm::vec4(1.0f)));
    scene::Material m = test::flat_material(glm::vec4(0.2f, 0.4f, 0.6f, 1.0f));
    m.base_color_texture.texture = 7;
    s.materials.push_back(m);
    for (const WorkingSpace ws : {WorkingSpace::Display, WorkingSpace::Linear})
        for (const Traversal tr : {Traversal::Fast, Traversal::Reference}) {
            raster::RenderSettings st = test::plain_settings(W, H);
            st.exec.traversal = tr;
            st.working_space = ws;
            const Targets t = raster::render_gbuffer(s, test::pixel_camera(W, H), st);
            const ImageF& c = t.get(target::kColor);
            EXPECT_GT(c.at(1, 8, 0), c.at(1, 8, 2));  // reddish near x = 0
            EXPECT_LT(c.at(6, 8, 0), c.at(6, 8, 2));  // bluish near x = 8
            EXPECT_GT(c.at(3, 8, 0), c.at(4, 8, 0));  // red falls along the ramp
            const glm::vec3 want = raster::base_color_to_working(glm::vec3(m.base_color), m.linear_color, ws);
            for (const int x : {9, 12, 15})
                for (int k = 0; k < 3; ++k) EXPECT_EQ(c.at(x, 8, k), want[k]) << x << " " << k;
        }
}

TEST(GBuffer, AlphaMaskDiscards) {
    const int W = 16, H = 16;
    auto quad = [&](float z) {
        return test::make_prim({px(W, H, 0, 0, z), px(W, H, 0, 16, z), px(W, H, 16, 16, z), px(W, H, 16, 0, z)},
                               {0, 1, 2, 0, 2, 3});
    };
    scene::Primitive front = quad(-2), back = quad(-8);
    front.colors = {{1, 1, 1, 0.2f}, {1, 1, 1, 0.2f}, {1, 1, 1, 0.9f}, {1, 1, 1, 0.9f}};  // alpha ramp
    front.material = 1;
    scene::Scene s = test::scene_of({front, back});
    scene::Material mask;
    mask.alpha_mode = scene::AlphaMode::Mask;
    mask.alpha_cutoff = 0.5f;
    s.materials.push_back(mask);
    for (Traversal tr : {Traversal::Fast, Traversal::Reference}) {
        raster::RenderSettings st = test::plain_settings(W, H);
        st.exec.traversal = tr;
        const Targets t = raster::render_gbuffer(s, test::pixel_camera(W, H), st);
        const ImageF& id = t.get(target::kObjectId);
        EXPECT_EQ(id.at(1, 8, 0), 2.0f);   // alpha ~0.25: discarded, the back quad shows
        EXPECT_EQ(id.at(14, 8, 0), 1.0f);  // alpha ~0.85: kept
    }
}

// SSAA 2: a quad edge at x = 10.5 px covers the left sample column of pixel 10 only.
TEST(GBuffer, SsaaResolve) {
    const int W = 24, H = 8;
    scene::Material m = test::flat_material({0.2f, 0.4f, 0.6f, 1.0f});
    const scene::Scene s = test::scene_of(
        {test::make_prim({px(W, H, 2, 0, -4), px(W, H, 2, 8, -4), px(W, H, 10.5f, 8, -4), px(W, H, 10.5f, 0, -4)},
                         {0, 1, 2, 0, 2, 3})},
        m);
    raster::RenderSettings st = test::plain_settings(W, H);
    st.ssaa = 2;
    for (Traversal tr : {Traversal::Fast, Traversal::Reference}) {
        st.exec.traversal = tr;
        const Targets t = raster::render_gbuffer(s, test::pixel_camera(W, H), st);
        const ImageF& c = t.get(target::kColor);
        ASSERT_EQ(c.width(), W);
        ASSERT_EQ(c.height(), H);
        EXPECT_FLOAT_EQ(c.at(5, 4, 3), 1.0f);
        EXPECT_FLOAT_EQ(c.at(10, 4, 3), 0.5f);   // half the samples
        EXPECT_FLOAT_EQ(c.at(11, 4, 3), 0.0f);
        EXPECT_NEAR(c.at(10, 4, 0), 0.2f, 1e-6);  // straight (unpremultiplied) colour
        EXPECT_NEAR(c.at(10, 4, 2), 0.6f, 1e-6);
        EXPECT_FLOAT_EQ(t.get(target::kDepthLinear).at(10, 4, 0), 4.0f);  // min over covered samples
        EXPECT_FLOAT_EQ(t.get(target::kDepthLinear).at(11, 4, 0), 100.0f);
        EXPECT_EQ(t.get(target::kObjectId).at(10, 4, 0), 1.0f);  // 2:2 tie, first sample is covered
        EXPECT_FLOAT_EQ(t.get(target::kCtrlEdge).at(10, 4, 3), 0.5f);
        EXPECT_NEAR(t.get(target::kNormal).at(10, 4, 2), 1.0f, 1e-6);
    }
}

// Coverage antialiasing (docs/raster.md): a vertical edge at x = 10.25 covers one column of
// pixel 10's 4x4 samples (at x = 10.125), one at 10.75 three columns; the centre (10.5) decides
// whose values the pixel keeps.
TEST(GBuffer, CoverageAntialiasingGivesTheSamplesShare) {
    const int W = 24, H = 8;
    const scene::Material m = test::flat_material({0.2f, 0.4f, 0.6f, 1.0f});
    for (float edge : {10.25f, 10.75f}) {
        const scene::Scene s = test::scene_of(
            {test::make_prim({px(W, H, 2, 0, -4), px(W, H, 2, 8, -4), px(W, H, edge, 8, -4), px(W, H, edge, 0, -4)},
                             {0, 1, 2, 0, 2, 3})},
            m);
        raster::RenderSettings st = test::plain_settings(W, H);
        st.antialias = raster::RenderSettings::Antialias::Coverage;
        for (Traversal tr : {Traversal::Fast, Traversal::Reference}) {
            st.exec.traversal = tr;
            const Targets t = raster::render_gbuffer(s, test::pixel_camera(W, H), st);
            const ImageF& c = t.get(target::kColor);
            const bool centre = edge > 10.5f;
            EXPECT_FLOAT_EQ(c.at(9, 4, 3), 1.0f);
            EXPECT_FLOAT_EQ(c.at(10, 4, 3), centre ? 0.75f : 0.25f) << edge;
            EXPECT_FLOAT_EQ(c.at(11, 4, 3), 0.0f);
            EXPECT_FLOAT_EQ(c.at(2, 4, 3), 1.0f);  // the left edge at 2.0 covers whole pixels
            EXPECT_FLOAT_EQ(c.at(1, 4, 3), 0.0f);
            EXPECT_NEAR(c.at(10, 4, 0), 0.2f, 1e-6);  // straight colour: the object's
            EXPECT_NEAR(c.at(10, 4, 2), 0.6f, 1e-6);
            EXPECT_FLOAT_EQ(t.get(target::kCtrlEdge).at(10, 4, 3), c.at(10, 4, 3));
            EXPECT_FLOAT_EQ(t.get(target::kDepthLinear).at(10, 4, 0), 4.0f);
            EXPECT_EQ(t.get(target::kObjectId).at(10, 4, 0), centre ? 1.0f : 0.0f);  // majority of the samples
            EXPECT_NEAR(t.get(target::kNormal).at(10, 4, 2), 1.0f, 1e-6);
            st.antialias = raster::RenderSettings::Antialias::None;
            EXPECT_FLOAT_EQ(raster::render_gbuffer(s, test::pixel_camera(W, H), st).get(target::kColor).at(10, 4, 3),
                            centre ? 1.0f : 0.0f);
            st.antialias = raster::RenderSettings::Antialias::Coverage;
        }
    }
}

TEST(Validation, AbsurdSizesAndSettingsThrow) {
    const scene::Scene s = test::scene_of({test::make_prim({{0, 0, -1}, {1, 0, -1}, {0, 1, -1}}, {0, 1, 2})});
    const scene::Camera cam = test::look_at({0, 0, 0}, {0, 0, -1});
    auto with = [&](int w, int h, int ssaa) {
        raster::RenderSettings st = test::plain_settings(w, h);
        st.ssaa = ssaa;
        return raster::render_gbuffer(s, cam, st);
    };
    EXPECT_THROW(with(100000, 100000, 1), Error);
    EXPECT_THROW(with(2000000000, 1, 1), Error);
    EXPECT_THROW(with(0, 10, 1), Error);
    EXPECT_THROW(with(10, 0, 1), Error);
    EXPECT_THROW(with(-5, 10, 1), Error);
    EXPECT_THROW(with(8192, 8192, 4), Error);  // supersampled size above the limit
    EXPECT_THROW(with(64, 64, 0), Error);
    EXPECT_THROW(with(64, 64, 5), Error);
    EXPECT_NO_THROW(with(64, 64, 4));
    raster::RenderSettings st = test::plain_settings(64, 64);
    st.fps = 0;
    EXPECT_THROW(raster::render_gbuffer(s, cam, st), Error);
    scene::Camera bad = cam;
    bad.znear = 0;
    EXPECT_THROW(raster::render_gbuffer(s, bad, test::plain_settings(64, 64)), Error);
    bad = cam;
    bad.zfar = bad.znear;
    EXPECT_THROW(raster::render_gbuffer(s, bad, test::plain_settings(64, 64)), Error);
}

TEST(Validation, EmptySceneRendersBackground) {
    const scene::Scene s;
    const Targets t = raster::render_gbuffer(s, test::look_at({0, 0, 0}, {0, 0, -1}), test::plain_settings(8, 8));
    EXPECT_EQ(t.get(target::kColor).at(3, 3, 3), 0.0f);
    EXPECT_EQ(t.get(target::kDepthLinear).at(3, 3, 0), 100.0f);
}

// ---- Real models ---------------------------------------------------------------------------

namespace {
const scene::Scene& suzanne() {
    static const scene::Scene s = scene::load_gltf(test::asset("gltf/Suzanne/glTF/Suzanne.gltf"));
    return s;
}
const scene::Scene& water_bottle() {
    static const scene::Scene s = scene::load_gltf(test::asset("gltf/WaterBottle/glTF/WaterBottle.gltf"));
    return s;
}
const scene::Scene& dragon202k() {
    static const scene::Scene s = scene::load_gltf(test::asset("meshes/stanford_dragon/dragon_202k.glb"));
    return s;
}
const scene::Scene& box_vertex_colors() {  // COLOR_0
    static const scene::Scene s = scene::load_gltf(test::asset("gltf/BoxVertexColors_CC0/glTF-Embedded/BoxVertexColors.gltf"));
    return s;
}
const scene::Scene& orientation_test() {
    static const scene::Scene s = scene::load_gltf(test::asset("gltf/OrientationTest/glTF/OrientationTest.gltf"));
    return s;
}
}  // namespace

TEST(TiledVsReference, BitExactOnRealModels) {
    struct Case { const char* name; const scene::Scene* s; int w, h, ssaa; bool cull; raster::RenderSettings::Turbulence turb; };
    const Case cases[] = {
        {"suzanne", &suzanne(), 320, 240, 1, false, raster::RenderSettings::Turbulence::ImageSpace},
        {"suzanne_ssaa2_cull", &suzanne(), 160, 120, 2, true, raster::RenderSettings::Turbulence::ObjectSpace},
        {"waterbottle", &water_bottle(), 200, 300, 1, false, raster::RenderSettings::Turbulence::ObjectSpace},
        {"orientation", &orientation_test(), 256, 192, 1, false, raster::RenderSettings::Turbulence::ImageSpace},
        {"dragon202k", &dragon202k(), 320, 240, 1, false, raster::RenderSettings::Turbulence::ImageSpace},
        {"box_vertex_colors", &box_vertex_colors(), 240, 180, 1, false, raster::RenderSettings::Turbulence::ImageSpace},
    };
    for (const Case& c : cases) {
        raster::RenderSettings st;
        st.width = c.w;
        st.height = c.h;
        st.ssaa = c.ssaa;
        st.cull_backfaces = c.cull;
        st.turbulence = c.turb;
        st.frame = 3;  // tremor on (defaults), bleeding displacement on
        const scene::Camera cam = test::frame_scene(*c.s);
        st.exec = Exec::fast(2);
        const Targets fast = raster::render_gbuffer(*c.s, cam, st);
        st.exec = Exec::reference();
        const Targets ref = raster::render_gbuffer(*c.s, cam, st);
        expect_same_targets(fast, ref, c.name);
        // The model is actually on screen.
        const ImageF& id = fast.get(target::kObjectId);
        int covered = 0;
        for (std::size_t i = 0; i < id.num_values(); ++i) covered += id.data()[i] != 0.0f;
        EXPECT_GT(covered, c.w * c.h / 20) << c.name;
    }
}

// Coverage antialiasing on real models: the alpha of every pixel is the share of ssaa 4's samples
// covered (the same 4x4 positions), up to the vertex snapping of the 4x finer grid (and, for
// alpha-tested leaves, the alpha test of the finer grid's triangles); colour is untouched where the single sample
// already covered the pixel; the alpha-tested bush's leaves get fractional alpha too; the tiled
// schedule gives the reference's bytes.
TEST(GBuffer, CoverageAlphaIsTheSupersampledCoverage) {
    const scene::Scene bush = scene::load_gltf(test::asset("plants/ez-tree/ez_bush2.glb"));
    struct Case { const char* name; const scene::Scene* s; int w, h; };
    const Case cases[] = {{"suzanne", &suzanne(), 320, 240}, {"dragon202k", &dragon202k(), 320, 240},
                          {"bush", &bush, 240, 240}};
    for (const Case& c : cases) {
        raster::RenderSettings st = test::plain_settings(c.w, c.h);
        st.antialias = raster::RenderSettings::Antialias::Coverage;
        const scene::Camera cam = test::frame_scene(*c.s);
        st.exec = Exec::fast(2);
        const Targets aa = raster::render_gbuffer(*c.s, cam, st);
        st.exec = Exec::reference();
        expect_same_targets(aa, raster::render_gbuffer(*c.s, cam, st), c.name);
        st.exec = Exec::fast(2);
        st.antialias = raster::RenderSettings::Antialias::None;
        const Targets one = raster::render_gbuffer(*c.s, cam, st);
        st.ssaa = 4;
        const Targets ss4 = raster::render_gbuffer(*c.s, cam, st);
        const ImageF &a = aa.get(target::kColor), &o = one.get(target::kColor), &r = ss4.get(target::kColor);
        int fractional = 0, near = 0, n = 0;
        double err_aa = 0, err_one = 0;
        for (int y = 0; y < c.h; ++y)
            for (int x = 0; x < c.w; ++x) {
                const float alpha = a.at(x, y, 3), ref = r.at(x, y, 3);
                if (ref == 0.0f && alpha == 0.0f) continue;
                ++n;
                fractional += alpha > 0.0f && alpha < 1.0f;
                near += std::abs(alpha - ref) <= 1.0f / 16.0f + 1e-6f;
                err_aa += std::abs(alpha - ref);
                err_one += std::abs(o.at(x, y, 3) - ref);
                if (o.at(x, y, 3) == 1.0f) {
                    for (int ch = 0; ch < 3; ++ch) ASSERT_EQ(a.at(x, y, ch), o.at(x, y, ch)) << c.name;
                }
            }
        const std::string what = std::string(c.name) + ": " + std::to_string(n) + " pixels, " +
                                 std::to_string(near) + " within one sample, alpha error " + std::to_string(err_aa) +
                                 " (one sample per pixel: " + std::to_string(err_one) + ")";
        EXPECT_GT(fractional, c.w * c.h / 200) << what;
        // Measured: all pixels of Suzanne and the dragon within one sample (error 0.3 and 0.9 vs
        // 105 and 255), the bush's alpha-tested leaves 96 % (66 vs 1357).
        EXPECT_GT(double(near), 0.95 * n) << what;
        EXPECT_LT(err_aa, 0.1 * err_one) << what;                  // far closer than one sample
    }
}

// The tiled traversal writes fresh targets without filling them first (every pixel, background
// included, is written by its tile). Recycled memory holds old values: with the image pool full of
// NaN-poisoned buffers of the targets' sizes, a fresh render (all targets, and WC18's subset) still
// gives the reference traversal's bytes.
TEST(TiledVsReference, FreshTargetsInRecycledMemoryAreWhollyWritten) {
    const int W = 1024, H = 512;  // a 1-channel target is 2 MiB: every target is pooled memory
    raster::RenderSettings st;
    st.width = W;
    st.height = H;
    st.frame = 2;
    const scene::Camera cam = test::frame_scene(suzanne());
    st.exec = Exec::reference();
    const Targets ref = raster::render_gbuffer(suzanne(), cam, st);
    using namespace target;
    const std::uint32_t wc18 = gbuffer_bit(kColor) | gbuffer_bit(kDepthLinear) | gbuffer_bit(kCtrlPigment) |
                               gbuffer_bit(kCtrlSubstrate) | gbuffer_bit(kCtrlEdge) | gbuffer_bit(kCtrlAbstraction);
    for (std::uint32_t mask : {kAllGBufferTargets, wc18}) {
        {
            std::vector<ImageF> poison;
            for (const GBufferTarget& t : kGBufferLayout) poison.emplace_back(W, H, t.channels, std::nanf(""));
        }  // freed into the pool, taken again by the render below
        st.exec = Exec::fast(2);
        st.targets = mask;
        const Targets fast = raster::render_gbuffer(suzanne(), cam, st);
        for (const GBufferTarget& t : kGBufferLayout) {
            if (!(mask & gbuffer_bit(t.name))) continue;
            const ImageF& a = fast.get(t.name);
            const ImageF& b = ref.get(t.name);
            ASSERT_EQ(a.num_values(), b.num_values());
            EXPECT_EQ(std::memcmp(a.data(), b.data(), a.num_values() * sizeof(float)), 0) << t.name << " mask " << mask;
        }
    }
}

TEST(Determinism, SameHashesForThreads1_2_8AndAcrossRuns) {
    raster::RenderSettings st;
    st.width = 333;  // not a multiple of the tile size
    st.height = 211;
    st.frame = 7;
    const scene::Camera cam = test::frame_scene(water_bottle());
    st.exec = Exec::fast(1);
    const Targets t1 = raster::render_gbuffer(water_bottle(), cam, st);
    EXPECT_EQ(t1.names().size(), 10u);
    for (int threads : {2, 8, 1}) {
        st.exec = Exec::fast(threads);
        expect_same_targets(t1, raster::render_gbuffer(water_bottle(), cam, st), "threads" + std::to_string(threads));
    }
    st.exec = Exec::fast(0);
    expect_same_targets(t1, raster::render_gbuffer(water_bottle(), cam, st), "threads_all");
}

TEST(Tremor, FrameIsReproducibleAndFramesDiffer) {
    raster::RenderSettings st;
    st.width = 200;
    st.height = 150;
    st.exec = Exec::fast(2);
    const scene::Camera cam = test::frame_scene(suzanne());
    st.frame = 12;
    const Targets a = raster::render_gbuffer(suzanne(), cam, st);
    const Targets b = raster::render_gbuffer(suzanne(), cam, st);
    expect_same_targets(a, b, "tremor_same_frame");
    st.frame = 13;
    const Targets c = raster::render_gbuffer(suzanne(), cam, st);
    EXPECT_NE(sha256_hex(a.get(target::kColor)), sha256_hex(c.get(target::kColor)));
    EXPECT_NE(sha256_hex(a.get(target::kObjectId)), sha256_hex(c.get(target::kObjectId)));
    // Without tremor, time does not change the image.
    st.tremor.enabled = false;
    st.frame = 12;
    const Targets d = raster::render_gbuffer(suzanne(), cam, st);
    st.frame = 13;
    expect_same_targets(d, raster::render_gbuffer(suzanne(), cam, st), "no_tremor");
}

TEST(BleedDisplacement, GrowsTheSilhouette) {
    const int W = 64, H = 64;
    scene::Primitive sph = test::uv_sphere(24, 16, 1.0f);
    sph.control[scene::kCtrlAbstraction].assign(sph.positions.size(), glm::vec4(0, 0, 1.0f, 0));
    const scene::Scene s = test::scene_of({sph});
    const scene::Camera cam = test::look_at({0, 0, 5}, {0, 0, 0}, 0.8f);
    raster::RenderSettings st = test::plain_settings(W, H);
    auto covered = [&](bool on) {
        st.bleed_displacement = on;
        const Targets t = raster::render_gbuffer(s, cam, st);
        const ImageF& id = t.get(target::kObjectId);
        int n = 0;
        for (std::size_t i = 0; i < id.num_values(); ++i) n += id.data()[i] != 0.0f;
        return n;
    };
    const int off = covered(false), on = covered(true);
    // Radius 1 -> 1 + sat(1 - 0.7) * 0.5 = 1.15: area grows by about 1.15^2.
    EXPECT_GT(double(on) / off, 1.2);
    EXPECT_LT(double(on) / off, 1.45);
}

// Rendering into the targets of a previous (different) frame gives the bytes of a fresh render.
TEST(GBuffer, RenderIntoReusesTargetsWithIdenticalBytes) {
    raster::RenderSettings st;
    st.width = 160;
    st.height = 120;
    const scene::Camera cam = test::frame_scene(suzanne());
    for (Traversal tr : {Traversal::Fast, Traversal::Reference}) {
        st.exec.traversal = tr;
        st.exec.threads = 2;
        Targets out;
        st.frame = 1;
        raster::render_gbuffer_into(out, suzanne(), cam, st);  // allocates
        const float* before = out.get(target::kColor).data();
        st.frame = 2;
        raster::render_gbuffer_into(out, suzanne(), cam, st);  // reuses, overwrites frame 1
        EXPECT_EQ(out.get(target::kColor).data(), before) << "memory not reused";
        expect_same_targets(out, raster::render_gbuffer(suzanne(), cam, st), "render_into");
        // An empty scene into the same targets clears everything to the background.
        raster::render_gbuffer_into(out, scene::Scene{}, cam, st);
        expect_same_targets(out, raster::render_gbuffer(scene::Scene{}, cam, st), "render_into_empty");
    }
}

// Background tiles kept between frames (raster/raster.cpp, docs/raster.md): a render into the
// stamped targets of the previous frame leaves alone the tiles that showed only background then
// and do now. Every frame of a sequence that moves the model across tiles, empties the scene,
// changes the background depth (the camera's far plane) and draws again must have the bytes of a
// fresh render, at 1, 2 and 8 threads; the expected targets are rendered first, so each render
// into `out` follows the one before it (the case where tiles are kept).
TEST(GBuffer, ReusedTargetsKeepOnlyBackgroundTilesThatStayBackground) {
    const scene::Scene& base = suzanne();
    const scene::Camera cam = test::frame_scene(base, 1.2f);  // the model covers part of the frame
    scene::Scene moved = base;
    for (scene::Instance& inst : moved.instances)
        inst.world = glm::translate(glm::mat4(1.0f), glm::vec3(0.6f * (base.world_bounds().max.x - base.world_bounds().min.x), 0, 0)) * inst.world;
    scene::Camera far_cam = cam;
    far_cam.zfar *= 2.0f;
    struct Step {
        const scene::Scene* scene;
        const scene::Camera* camera;
        int frame;
    };
    const scene::Scene empty;
    const std::vector<Step> steps = {{&base, &cam, 1}, {&base, &cam, 2}, {&moved, &cam, 3}, {&empty, &cam, 4},
                                     {&base, &cam, 5}, {&base, &far_cam, 6}, {&moved, &far_cam, 7}};
    for (int threads : {1, 2, 8}) {
        raster::RenderSettings st;
        st.width = 256;
        st.height = 192;
        st.exec.threads = threads;
        std::vector<Targets> expected;
        for (const Step& s : steps) {
            st.frame = s.frame;
            expected.push_back(raster::render_gbuffer(*s.scene, *s.camera, st));
        }
        Targets out;
        for (std::size_t i = 0; i < steps.size(); ++i) {
            st.frame = steps[i].frame;
            raster::render_gbuffer_into(out, *steps[i].scene, *steps[i].camera, st);
            expect_same_targets(out, expected[i], "kept_tiles_t" + std::to_string(threads) + "_step" + std::to_string(i));
        }
    }
}

// What the kept tiles rest on: the stamped images hold the previous frame's values. A write
// through the image (a mutable access clears its stamp) makes the next frame write every tile
// again; a write through a pointer taken before the stamped render is not seen (the contract in
// ImageF::stamp) — which shows the tiles are in fact left alone.
TEST(GBuffer, KeptTilesAreThoseOfAStampedFrameOnly) {
    raster::RenderSettings st;
    st.width = 256;
    st.height = 192;
    st.exec.threads = 2;
    const scene::Camera cam = test::frame_scene(suzanne(), 1.2f);
    const Targets expected = raster::render_gbuffer(suzanne(), cam, st);
    ASSERT_EQ(expected.get(target::kColor).at(0, 0, 3), 0.0f) << "pixel (0, 0) must be background";
    Targets out;
    raster::render_gbuffer_into(out, suzanne(), cam, st);
    out.get_mut(target::kColor).at(0, 0, 3) = 0.5f;  // through the image: the stamp is cleared
    raster::render_gbuffer_into(out, suzanne(), cam, st);
    expect_same_targets(out, expected, "after_write_through_image");
    float* early = out.get_mut(target::kColor).data();  // taken before the next (stamped) render
    raster::render_gbuffer_into(out, suzanne(), cam, st);
    early[3] = 0.5f;  // behind the stamp's back
    raster::render_gbuffer_into(out, suzanne(), cam, st);
    EXPECT_EQ(out.get(target::kColor).at(0, 0, 3), 0.5f) << "the background tile was written again";
}

namespace aq {
namespace {

// RenderSettings::targets: the fast single-sample traversal renders only the targets asked for
// (colour and depth always), each with the bytes of a render of all ten, also into the targets of
// a previous frame (reused only when they are exactly that set); the reference traversal and
// supersampling produce all ten.
TEST(GBuffer, ATargetSubsetHasTheBytesOfTheFullRender) {
    raster::RenderSettings st;
    st.width = 160;
    st.height = 120;
    st.exec.threads = 2;
    const scene::Camera cam = test::frame_scene(suzanne());
    const Targets all = raster::render_gbuffer(suzanne(), cam, st);
    raster::RenderSettings sub = st;
    sub.targets = target::gbuffer_bit(target::kCtrlEdge) | target::gbuffer_bit(target::kObjectId);
    const std::vector<std::string> want = {target::kColor, target::kCtrlEdge, target::kDepthLinear, target::kObjectId};
    const Targets part = raster::render_gbuffer(suzanne(), cam, sub);
    std::vector<std::string> names = part.names();
    std::sort(names.begin(), names.end());
    std::vector<std::string> sorted_want = want;
    std::sort(sorted_want.begin(), sorted_want.end());
    EXPECT_EQ(names, sorted_want);
    for (const std::string& n : want) EXPECT_EQ(sha256_hex(part.get(n)), sha256_hex(all.get(n))) << n;

    // Into the subset of a previous frame: memory reused, bytes of a fresh full render.
    Targets out;
    sub.frame = 1;
    raster::render_gbuffer_into(out, suzanne(), cam, sub);
    const float* before = out.get(target::kCtrlEdge).data();
    sub.frame = 2;
    raster::render_gbuffer_into(out, suzanne(), cam, sub);
    EXPECT_EQ(out.get(target::kCtrlEdge).data(), before) << "memory not reused";
    raster::RenderSettings full2 = st;
    full2.frame = 2;
    const Targets all2 = raster::render_gbuffer(suzanne(), cam, full2);
    for (const std::string& n : want) EXPECT_EQ(sha256_hex(out.get(n)), sha256_hex(all2.get(n))) << n;
    // A full render into the subset's targets replaces them with all ten.
    raster::render_gbuffer_into(out, suzanne(), cam, full2);
    expect_same_targets(out, all2, "subset_then_full");

    // Reference traversal and supersampling ignore the subset.
    for (int variant = 0; variant < 2; ++variant) {
        raster::RenderSettings r = sub;
        r.frame = 0;
        if (variant == 0) r.exec = Exec::reference();
        else r.ssaa = 2;
        EXPECT_EQ(raster::render_gbuffer(suzanne(), cam, r).names().size(), std::size(target::kGBufferLayout));
    }
}

}  // namespace
}  // namespace aq
