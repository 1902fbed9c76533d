// tests/raster/vertex_test.cpp — the vertex stage's schedule (transform_vertices: eight vertices
// per AVX2 step, the rest one by one) gives what its definition (transform_vertex, one vertex)
// gives, value for value, on vertices that exercise every path: inside the view, behind the eye,
// across near/far and the guard band, NaN/Inf/huge positions, zero and NaN normals, with and
// without hand tremor (perspective and orthographic), bleeding displacement, normals, tangents.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "raster/vertex.h"
#include "scenes/scene.h"

namespace aq::raster {
namespace {

// Equal bits, or both NaN (a NaN's payload may come from another operand in a vector lane).
bool same(float a, float b) {
    if (std::isnan(a) && std::isnan(b)) return true;
    return std::memcmp(&a, &b, sizeof a) == 0;
}
template <int N>
bool same(const glm::vec<N, float>& a, const glm::vec<N, float>& b) {
    for (int i = 0; i < N; ++i)
        if (!same(a[i], b[i])) return false;
    return true;
}

struct Case {
    bool tremor, perspective, bleed, normals, ctrl, tangents;
};

void run_case(const Case& cs, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    scene::Primitive prim;
    const std::size_t n = 203;  // not a multiple of 8: a scalar tail
    for (std::size_t i = 0; i < n; ++i) {
        glm::vec3 p(3.0f * u(rng), 2.0f * u(rng), 4.0f * u(rng));
        glm::vec3 nv = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(0.0f, 0.0f, 0.01f));
        switch (i % 23) {
            case 3: p.x = nan; break;
            case 5: p.y = inf; break;
            case 7: p.z = 1e30f; break;
            case 9: p.z = 20.0f; break;               // behind the eye
            case 11: p = glm::vec3(1e6f, 0.0f, -5.0f); break;  // beyond the guard band
            case 13: nv = glm::vec3(0.0f); break;     // zero normal
            case 15: nv.y = nan; break;               // NaN normal
            case 17: p.z = -0.1f; break;              // across near
            default: break;
        }
        prim.positions.push_back(p);
        prim.normals.push_back(nv);
        prim.tangents.push_back(glm::vec4(u(rng), u(rng), u(rng), i % 2 ? 1.0f : -1.0f));
    }
    if (!cs.normals) prim.normals.clear();
    if (!cs.tangents) prim.tangents.clear();
    if (cs.ctrl)
        for (std::size_t i = 0; i < n; ++i) prim.control[scene::kCtrlAbstraction].push_back(glm::vec4(0, 0, u(rng), 0));
    scene::Material mat;
    mat.wc.control[scene::kCtrlAbstraction].b = 0.6f;
    RenderSettings rs;
    rs.width = 640;
    rs.height = 360;
    rs.tremor.enabled = cs.tremor;
    rs.tremor.tremor_px = 6.0f;
    rs.bleed_displacement = cs.bleed;
    FrameParams fp;
    scene::Camera cam;
    cam.orthographic = !cs.perspective;
    cam.xmag = 4.0f;
    cam.ymag = 2.25f;
    cam.yfov = 0.8f;
    cam.znear = 0.5f;
    cam.zfar = 30.0f;
    fp.proj = projection_matrix(cam, 640.0f / 360.0f);
    fp.perspective = cs.perspective;
    fp.vp.width = 640;
    fp.vp.height = 360;
    fp.vp.gb_x = kGuardBandPx / 640;
    fp.vp.gb_y = kGuardBandPx / 360;
    fp.out_width = 640;
    fp.out_height = 360;
    fp.time_s = 0.7f;
    fp.settings = &rs;
    glm::mat4 mv(1.0f);
    mv[0] = glm::vec4(0.8f, 0.1f, -0.6f, 0.0f);
    mv[1] = glm::vec4(0.0f, 0.98f, 0.17f, 0.0f);
    mv[2] = glm::vec4(0.6f, -0.14f, 0.79f, 0.0f);
    mv[3] = glm::vec4(0.3f, -0.2f, -8.0f, 1.0f);
    const glm::mat3 nm = glm::transpose(glm::inverse(glm::mat3(mv)));
    auto make = [&] {
        DrawVertices dv;
        dv.prim = &prim;
        dv.mat = &mat;
        dv.clip.resize(n);
        dv.view.resize(n);
        dv.snap.resize(n);
        if (cs.tangents) dv.view_tangent.resize(n);
        return dv;
    };
    DrawVertices fast = make(), ref = make();
    transform_vertices(fp, mv, nm, fast, 0, 5);  // ranges as the vertex jobs cut them: any start
    transform_vertices(fp, mv, nm, fast, 5, n);
    for (std::size_t i = 0; i < n; ++i) transform_vertex(fp, mv, nm, ref, i);
    int snapped = 0, coded = 0;
    for (std::size_t i = 0; i < n; ++i) {
        SCOPED_TRACE(::testing::Message() << "vertex " << i << " tremor " << cs.tremor << " perspective "
                                          << cs.perspective << " bleed " << cs.bleed);
        EXPECT_TRUE(same(fast.clip[i], ref.clip[i]));
        EXPECT_TRUE(same(fast.view[i].pos, ref.view[i].pos));
        EXPECT_TRUE(same(fast.view[i].normal, ref.view[i].normal));
        if (cs.tangents) {
            EXPECT_TRUE(same(fast.view_tangent[i], ref.view_tangent[i]));
        }
        const SnapVertex& a = fast.snap[i];
        const SnapVertex& b = ref.snap[i];
        EXPECT_EQ(a.code, b.code);
        EXPECT_EQ(a.x, b.x);
        EXPECT_EQ(a.y, b.y);
        EXPECT_TRUE(same(a.inv_w, b.inv_w));
        EXPECT_TRUE(same(a.depth, b.depth));
        snapped += b.code == 0;
        coded += b.code != 0;
    }
    EXPECT_GT(snapped, int(n) / 3);  // both paths of the snap are exercised
    EXPECT_GT(coded, 10);
}

TEST(VertexStage, EightAtATimeGivesWhatOneAtATimeGives) {
    std::uint32_t seed = 1;
    for (const bool tremor : {true, false})
        for (const bool perspective : {true, false})
            for (const bool bleed : {true, false}) {
                run_case({tremor, perspective, bleed, true, bleed, !bleed}, seed++);
                run_case({tremor, perspective, bleed, false, !bleed, bleed}, seed++);
            }
}

}  // namespace
}  // namespace aq::raster
