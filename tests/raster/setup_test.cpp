// tests/raster/setup_test.cpp — the batched triangle setup (setup_triangles, the fast traversal's
// schedule: a branch-free pre-pass, then the setup of the listed triangles) appends exactly what
// setup_triangle appends triangle by triangle, and counts the same, on a mesh that exercises every
// path: sub-pixel triangles (quick reject), small and large ones, triangles crossing the near plane
// and the guard band (clipper), entirely outside one plane, non-finite vertices, out-of-range
// indices, back faces with culling on and off; for ranges that start and end inside a batch.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "core/image.h"
#include "raster/setup.h"
#include "scenes/scene.h"

namespace aq::raster {
namespace {

struct Mesh {
    scene::Primitive prim;
    scene::Material mat;
    DrawVertices dv;
    Viewport vp;
};

// The viewport (W x H, the full guard band) and room for a gx x gy grid of vertices; returns their count.
std::size_t init_mesh(Mesh& m, int W, int H, int gx, int gy) {
    m.vp.width = W;
    m.vp.height = H;
    m.vp.gb_x = kGuardBandPx / W;
    m.vp.gb_y = kGuardBandPx / H;
    const std::size_t nv = std::size_t(gx) * gy;
    m.prim.positions.resize(nv);
    m.dv.prim = &m.prim;
    m.dv.mat = &m.mat;
    m.dv.clip.resize(nv);
    m.dv.view.resize(nv);
    m.dv.snap.resize(nv);
    return nv;
}

// A jittered grid of vertices over (and beyond) the viewport, some behind the eye or non-finite,
// and triangles of neighbours (small) and of random vertices (large), some indices out of range.
void make_mesh(Mesh& m, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const int gx = 480, gy = 300;  // 0.8 px per grid step: most triangles hold no pixel centre
    const std::size_t nv = init_mesh(m, 320, 200, gx, gy);
    for (int j = 0; j < gy; ++j)
        for (int i = 0; i < gx; ++i) {
            const std::size_t k = std::size_t(j) * gx + i;
            const float w = 0.5f + 2.0f * u(rng);
            float x = (-1.2f + 2.4f * (i + 0.6f * u(rng)) / gx) * w;
            const float y = (-1.2f + 2.4f * (j + 0.6f * u(rng)) / gy) * w;
            float z = (-0.8f + 1.6f * u(rng)) * w;
            const float r = u(rng);
            if (r < 0.01f) z = -1.5f * w;                                  // in front of near
            else if (r < 0.015f) x = std::numeric_limits<float>::quiet_NaN();  // non-finite
            else if (r < 0.02f) x = 3.0e7f * w;                             // beyond the guard band
            const glm::vec4 c(x, y, z, w);
            m.dv.clip[k] = c;
            m.dv.view[k].pos = glm::vec3(0.0f, 0.0f, -w);
            m.dv.view[k].normal = glm::vec3(0.0f, 0.0f, 1.0f);
            const std::uint32_t code = outcode(c, m.vp);
            m.dv.snap[k] = code ? SnapVertex{0, 0, code, 0.0f, 0.0f} : snap_vertex(c, w, m.vp);
        }
    std::uniform_int_distribution<std::uint32_t> any(0, std::uint32_t(nv - 1));
    for (int j = 0; j + 1 < gy; ++j)
        for (int i = 0; i + 1 < gx; ++i) {
            const std::uint32_t a = std::uint32_t(j * gx + i), b = a + 1, c = a + gx, d = c + 1;
            const float r = u(rng);
            std::uint32_t t[6] = {a, c, b, b, c, d};
            if (r < 0.3f) std::swap(t[1], t[2]);                 // back face
            if (r > 0.97f) t[4] = any(rng);                      // a large triangle
            if (r > 0.995f) t[5] = std::uint32_t(nv + any(rng)); // index out of range
            m.prim.indices.insert(m.prim.indices.end(), t, t + 6);
        }
}

void expect_same_setups(const std::vector<TriSetup>& a, const std::vector<TriSetup>& b) {
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t k = 0; k < a.size(); ++k) {
        const TriSetup& s = a[k];
        const TriSetup& t = b[k];
        bool same = s.x0 == t.x0 && s.y0 == t.y0 && s.x1 == t.x1 && s.y1 == t.y1 && s.draw == t.draw &&
                    s.v[0] == t.v[0] && s.v[1] == t.v[1] && s.v[2] == t.v[2] && s.clip == t.clip && s.flags == t.flags;
        for (int i = 0; i < 3; ++i)
            same = same && s.A[i] == t.A[i] && s.B[i] == t.B[i] && s.C[i] == t.C[i] && s.bias(i) == t.bias(i) &&
                   s.inv_w[i] == t.inv_w[i] && s.depth[i] == t.depth[i];
        ASSERT_TRUE(same) << "setup " << k << " (vertex " << s.v[0] << " vs " << t.v[0] << ")";
    }
}

struct SetupRun {
    std::vector<TriSetup> setups;
    std::vector<ClipVerts> clips;
    SetupCounters counters;
};

//! setup_triangle for every triangle of the mesh, in order: the reference of the batched setup.
SetupRun one_by_one(const Mesh& m, std::uint32_t draw, const SetupOptions& opt) {
    SetupRun r;
    const std::uint32_t ntri = std::uint32_t(m.prim.indices.size() / 3);
    for (std::uint32_t t = 0; t < ntri; ++t) setup_triangle(m.dv, draw, t, m.vp, opt, r.setups, r.clips, r.counters);
    return r;
}

TEST(TriangleSetup, TheBatchedSetupAppendsWhatTheSetupOfEachTriangleAppends) {
    for (const std::uint32_t seed : {1u, 2u, 3u}) {
        Mesh m;
        make_mesh(m, seed);
        const std::uint32_t ntri = std::uint32_t(m.prim.indices.size() / 3);
        for (const int mode : {0, 1, 2}) {  // no culling, culling, keeping sub-pixel triangles
            const bool cull = mode == 1;
            SetupOptions opt;
            opt.cull_backfaces = cull;
            opt.keep_subpixel = mode == 2;
            const SetupRun one = one_by_one(m, 5, opt);
            const std::vector<TriSetup>& ref = one.setups;
            const std::vector<ClipVerts>& ref_clips = one.clips;
            const SetupCounters& ref_n = one.counters;
            std::vector<TriSetup> fast;
            std::vector<ClipVerts> fast_clips;
            SetupCounters fast_n;
            // Ranges of odd lengths, so that batches start and end anywhere.
            for (std::uint32_t b = 0; b < ntri;) {
                const std::uint32_t e = std::min(ntri, b + 1 + (b * 7919u) % (3 * kSetupBatch));
                setup_triangles(m.dv, 5, b, e, m.vp, opt, fast, fast_clips, fast_n);
                b = e;
            }
            expect_same_setups(ref, fast);
            ASSERT_EQ(ref_clips.size(), fast_clips.size());
            for (std::size_t k = 0; k < ref_clips.size(); ++k)
                for (int j = 0; j < 3; ++j) EXPECT_EQ(ref_clips[k].beta[j], fast_clips[k].beta[j]);
            EXPECT_EQ(ref_n.non_finite, fast_n.non_finite);
            EXPECT_EQ(ref_n.bad_index, fast_n.bad_index);
            EXPECT_EQ(ref_n.clip_unstable, fast_n.clip_unstable);
            EXPECT_EQ(ref_n.clipped, fast_n.clipped);
            // Each record names its triangle's vertices in the index buffer's order, and the
            // records follow the triangles' order (clipped fans repeat their triangle).
            std::uint32_t next = 0;
            for (const TriSetup& t : ref) {
                const std::uint32_t* ix = m.prim.indices.data();
                while (next < ntri && !(ix[3 * next] == t.v[0] && ix[3 * next + 1] == t.v[1] && ix[3 * next + 2] == t.v[2]))
                    ++next;
                ASSERT_LT(next, ntri) << "a record whose vertices are no later triangle's";
            }
            // The mesh exercises every path: most triangles dropped (or kept as sub-pixel), some
            // clipped, some counted.
            std::size_t subpixel = 0;
            for (const TriSetup& t : ref) subpixel += t.subpixel();
            if (opt.keep_subpixel) {
                EXPECT_GT(subpixel, ntri / 20) << "seed " << seed;  // the front-facing ones
                continue;
            }
            EXPECT_EQ(subpixel, 0u);
            EXPECT_LT(ref.size(), ntri / 4) << "seed " << seed;
            EXPECT_GT(ref.size(), ntri / 100) << "seed " << seed;
            EXPECT_GT(ref_n.clipped, 10u);
            EXPECT_GT(ref_n.non_finite, 10u);
            EXPECT_GT(ref_n.bad_index, 10u);
        }
    }
}

// Vertices on the half-pixel grid (w = 1 on a 256 x 128 raster: exact fixed-point positions), so
// that pixel centres fall exactly on edges and corners: the top-left rule decides most small
// triangles. Neighbours 0.5-1.5 px apart make triangles of 0 to a few pixels, both windings.
void make_half_pixel_mesh(Mesh& m, std::uint32_t seed) {
    std::mt19937 rng(seed);
    const int gx = 300, gy = 160;  // beyond the 256 x 128 raster on the right and at the bottom
    init_mesh(m, 256, 128, gx, gy);
    std::uniform_int_distribution<int> jitter(0, 2);  // half pixels
    for (int j = 0; j < gy; ++j)
        for (int i = 0; i < gx; ++i) {
            const std::size_t k = std::size_t(j) * gx + i;
            const float px = 0.5f * float(2 * i + jitter(rng)) - 8.0f, py = 0.5f * float(2 * j + jitter(rng)) - 8.0f;
            const glm::vec4 c(px / 128.0f - 1.0f, 1.0f - py / 64.0f, 0.0f, 1.0f);
            m.dv.clip[k] = c;
            m.dv.view[k].pos = glm::vec3(0.0f, 0.0f, -1.0f);
            m.dv.view[k].normal = glm::vec3(0.0f, 0.0f, 1.0f);
            const std::uint32_t code = outcode(c, m.vp);
            m.dv.snap[k] = code ? SnapVertex{0, 0, code, 0.0f, 0.0f} : snap_vertex(c, 1.0f, m.vp);
        }
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int j = 0; j + 1 < gy; ++j)
        for (int i = 0; i + 1 < gx; ++i) {
            const std::uint32_t a = std::uint32_t(j * gx + i), b = a + 1, c = a + gx, d = c + 1;
            std::uint32_t t[6] = {a, c, b, b, c, d};
            if (u(rng) < 0.4f) std::swap(t[1], t[2]);  // back face
            m.prim.indices.insert(m.prim.indices.end(), t, t + 6);
        }
}

TEST(TriangleSetup, TheBatchedSetupKeepsTheTopLeftRuleOnHalfPixelVertices) {
    for (const std::uint32_t seed : {1u, 2u}) {
        Mesh m;
        make_half_pixel_mesh(m, seed);
        const std::uint32_t ntri = std::uint32_t(m.prim.indices.size() / 3);
        for (const bool double_sided : {false, true})
            for (const bool cull : {false, true})
              for (const bool keep : {false, true}) {
                m.mat.double_sided = double_sided;
                SetupOptions opt;
                opt.cull_backfaces = cull;
                opt.keep_subpixel = keep;
                const std::vector<TriSetup> ref = one_by_one(m, 1, opt).setups;
                SetupRun fast;
                setup_triangles(m.dv, 1, 0, ntri, m.vp, opt, fast.setups, fast.clips, fast.counters);
                expect_same_setups(ref, fast.setups);
                // Some triangles kept, many dropped (ties on edges, empty bounds, culled faces).
                EXPECT_GT(ref.size(), ntri / 10) << "seed " << seed;
                EXPECT_LT(ref.size(), ntri) << "seed " << seed;
            }
    }
}

// The record's pixel bounds are 16-bit: on the widest grid make_frame accepts (kMaxImageSide) a
// triangle that runs past the right edge is clamped to the last column, and its winding bits say
// which way it faces and whether vertices 1 and 2 were swapped.
TEST(TriangleSetup, BoundsOnTheWidestGridReachTheLastColumn) {
    Mesh m;
    init_mesh(m, kMaxImageSide, 4, 3, 1);
    const glm::vec2 px[3] = {{kMaxImageSide - 3.8f, 0.2f}, {kMaxImageSide + 6.0f, 0.2f}, {kMaxImageSide - 3.8f, 3.8f}};
    for (int k = 0; k < 3; ++k) {
        const glm::vec4 c(px[k].x / (0.5f * kMaxImageSide) - 1.0f, 1.0f - px[k].y / 2.0f, 0.0f, 1.0f);
        ASSERT_EQ(outcode(c, m.vp), 0u);
        m.dv.clip[k] = c;
        m.dv.snap[k] = snap_vertex(c, 1.0f, m.vp);
    }
    m.prim.indices = {0, 1, 2, 0, 2, 1};  // y-down: positive area (faces away), then negative
    const SetupRun r = one_by_one(m, 0, SetupOptions{});
    ASSERT_EQ(r.setups.size(), 2u);
    for (const TriSetup& t : r.setups) {
        EXPECT_EQ(t.x0, kMaxImageSide - 4);
        EXPECT_EQ(t.x1, kMaxImageSide - 1);
        EXPECT_EQ(t.y0, 0);
        EXPECT_EQ(t.y1, 3);
        std::int64_t e[3];
        edge_values(t, kMaxImageSide - 1, 0, e);
        EXPECT_TRUE(inside(t, e));
    }
    EXPECT_TRUE(r.setups[0].back());
    EXPECT_FALSE(r.setups[0].perm());
    EXPECT_FALSE(r.setups[1].back());
    EXPECT_TRUE(r.setups[1].perm());
}

}  // namespace
}  // namespace aq::raster

namespace aq::raster {
namespace {

// bary_derivatives (the textures' level of detail) is the derivative of perspective_bary: it
// matches the central difference of the weights at the neighbouring pixels, for every setup of a
// perspective mesh (clipped ones included) with enough pixels around. Wrong scale (the sub-pixel
// factor), sign or normaliser would be off by far more than the second-order difference error.
TEST(TriangleSetup, BarycentricDerivativesAreThoseOfThePerspectiveWeights) {
    Mesh m;
    make_mesh(m, 77);
    const SetupRun r = one_by_one(m, 0, {});
    int checked = 0;
    double worst = 0;
    for (const TriSetup& t : r.setups)
        for (int y = t.y0 + 1; y < t.y1; ++y)
            for (int x = t.x0 + 1; x < t.x1; ++x) {
                std::int64_t e[5][3];
                const int off[5][2] = {{0, 0}, {1, 0}, {-1, 0}, {0, 1}, {0, -1}};
                bool all = true;
                for (int k = 0; k < 5; ++k) {
                    edge_values(t, x + off[k][0], y + off[k][1], e[k]);
                    all = all && inside(t, e[k]);
                }
                if (!all) continue;
                const Bary b = perspective_bary(t, e[0]);
                Bary dx, dy;
                bary_derivatives(t, b, dx, dy);
                const Bary px = perspective_bary(t, e[1]), mx = perspective_bary(t, e[2]);
                const Bary py = perspective_bary(t, e[3]), my = perspective_bary(t, e[4]);
                for (int i = 0; i < 3; ++i) {
                    const double fx = 0.5 * (double(px.b[i]) - mx.b[i]), fy = 0.5 * (double(py.b[i]) - my.b[i]);
                    const double ex = std::abs(fx - dx.b[i]) / (1e-4 + std::abs(fx));
                    const double ey = std::abs(fy - dy.b[i]) / (1e-4 + std::abs(fy));
                    worst = std::max({worst, ex, ey});
                    ASSERT_LT(ex, 0.05) << "d/dx of weight " << i << " at " << x << "," << y << ": " << dx.b[i] << " vs " << fx;
                    ASSERT_LT(ey, 0.05) << "d/dy of weight " << i << " at " << x << "," << y << ": " << dy.b[i] << " vs " << fy;
                }
                ++checked;
            }
    EXPECT_GT(checked, 1000);
    RecordProperty("worst_relative_error", std::to_string(worst));
}

}  // namespace
}  // namespace aq::raster
