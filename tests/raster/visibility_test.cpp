// tests/raster/visibility_test.cpp — the depth test of one triangle over a block of pixels
// (raster/visibility.h): the fast schedule (eight pixels per step where the edge values fit in
// int32) leaves the depth buffer and the winners bit for bit where the plain per-pixel loop does,
// for triangles from sub-pixel to guard-band size (edge values far beyond int32), shared edges
// (the top-left rule), equal depths (the first stays), blocks at the raster's border and small
// triangles on a block's edges (nothing written outside the block); and the plain loop is the
// reference traversal's test written out (edge_values, inside, perspective_bary).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "raster/setup.h"
#include "raster/visibility.h"
#include "scenes/scene.h"

namespace aq::raster {
namespace {

constexpr int kBlock = 64;

// Sets up the triangles of `verts` (three snapped vertices each) on a W x H raster, as the
// rasterizer does (setup_triangle: bounds, fill rule, culling of empty triangles).
std::vector<TriSetup> set_up(const std::vector<SnapVertex>& verts, int W, int H) {
    scene::Primitive prim;
    for (std::uint32_t i = 0; i < verts.size(); ++i) prim.indices.push_back(i);
    prim.positions.resize(verts.size());
    scene::Material mat;
    mat.double_sided = true;
    DrawVertices dv;
    dv.prim = &prim;
    dv.mat = &mat;
    dv.clip.resize(verts.size());
    dv.view.resize(verts.size());
    dv.snap.resize(verts.size());
    for (std::size_t i = 0; i < verts.size(); ++i) dv.snap[i] = verts[i];
    Viewport vp;
    vp.width = W;
    vp.height = H;
    std::vector<TriSetup> out;
    std::vector<ClipVerts> clips;
    SetupCounters counters;
    for (std::uint32_t t = 0; t < verts.size() / 3; ++t) setup_triangle(dv, 0, t, vp, SetupOptions{}, out, clips, counters);
    return out;
}

struct Block {
    std::vector<float> z = std::vector<float>(kBlock * kBlock, std::numeric_limits<float>::infinity());
    std::vector<TileRef> ids = std::vector<TileRef>(kBlock * kBlock, TileRef{~0u, ~0u});
};

// Draws every setup into the block at (X0, Y0) with `schedule`, in order (ref = its index).
Block draw(const std::vector<TriSetup>& tris, int X0, int Y0, VisibilitySchedule schedule) {
    Block b;
    for (std::uint32_t i = 0; i < tris.size(); ++i) {
        const TriSetup& t = tris[i];
        const int x0 = std::max<int>(t.x0, X0), x1 = std::min<int>(t.x1, X0 + kBlock - 1);
        const int y0 = std::max<int>(t.y0, Y0), y1 = std::min<int>(t.y1, Y0 + kBlock - 1);
        depth_test_triangle(t, X0, Y0, kBlock, x0, x1, y0, y1, b.z.data(), b.ids.data(), {7, i}, schedule);
    }
    return b;
}

void expect_same(const Block& a, const Block& b, const char* what) {
    int diff = 0;
    for (int i = 0; i < kBlock * kBlock; ++i) {
        std::uint32_t za, zb;
        std::memcpy(&za, &a.z[i], 4);
        std::memcpy(&zb, &b.z[i], 4);
        if (za != zb || a.ids[i].chunk != b.ids[i].chunk || a.ids[i].tri != b.ids[i].tri) ++diff;
    }
    EXPECT_EQ(diff, 0) << what;
}

SnapVertex vertex(std::int64_t x, std::int64_t y, float inv_w, float depth) {
    return {std::int32_t(x), std::int32_t(y), 0u, inv_w, depth};
}

TEST(Visibility, PlainLoopIsTheReferenceTest) {
    // One triangle, every pixel of the block by the definition: inside by the edge functions,
    // depth by perspective_bary.
    const std::vector<TriSetup> tris =
        set_up({vertex(3 * 256 + 17, 5 * 256, 1.0f, 2.0f), vertex(60 * 256, 9 * 256 + 200, 0.5f, 4.0f),
                vertex(20 * 256, 61 * 256 + 3, 0.25f, 8.0f)},
               kBlock, kBlock);
    ASSERT_EQ(tris.size(), 1u);
    const Block b = draw(tris, 0, 0, VisibilitySchedule::Plain);
    int covered = 0;
    for (int y = 0; y < kBlock; ++y)
        for (int x = 0; x < kBlock; ++x) {
            std::int64_t e[3];
            edge_values(tris[0], x, y, e);
            const int i = y * kBlock + x;
            if (inside(tris[0], e)) {
                ++covered;
                EXPECT_EQ(b.z[i], perspective_bary(tris[0], e).depth);
                EXPECT_EQ(b.ids[i].tri, 0u);
            } else {
                EXPECT_EQ(b.z[i], std::numeric_limits<float>::infinity());
                EXPECT_EQ(b.ids[i].chunk, ~0u);
            }
        }
    EXPECT_GT(covered, 500);
}

TEST(Visibility, FastScheduleHasThePlainLoopsBytes) {
    std::mt19937 rng(20261127);
    const int W = 4096, H = 4096;
    // Sizes from sub-pixel to guard-band scale (edge values up to ~2^58: the plain fallback).
    const double sizes_px[] = {0.7, 1.5, 2.5, 3.5, 9, 40, 150, 600, 5000, 400000};
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (const double size : sizes_px)
        for (int rep = 0; rep < 6; ++rep) {
            std::vector<SnapVertex> verts;
            const int X0 = kBlock * int(unit(rng) * (W / kBlock)), Y0 = kBlock * int(unit(rng) * (H / kBlock));
            for (int k = 0; k < 300; ++k) {
                // Centres in and around the block; depths in few distinct values (ties).
                const double cx = X0 - size * 0.5 + unit(rng) * (kBlock + size), cy = Y0 - size * 0.5 + unit(rng) * (kBlock + size);
                for (int v = 0; v < 3; ++v) {
                    const double x = (cx + (unit(rng) - 0.5) * size) * 256, y = (cy + (unit(rng) - 0.5) * size) * 256;
                    const float depth = float(1 + int(unit(rng) * 4));
                    verts.push_back(vertex(std::llround(std::clamp(x, -5e8, 5e8)), std::llround(std::clamp(y, -5e8, 5e8)),
                                           float(0.2 + unit(rng)), depth));
                }
            }
            const std::vector<TriSetup> tris = set_up(verts, W, H);
            ASSERT_FALSE(tris.empty());
            expect_same(draw(tris, X0, Y0, VisibilitySchedule::Fast), draw(tris, X0, Y0, VisibilitySchedule::Plain),
                        ("size " + std::to_string(size)).c_str());
        }
}

TEST(Visibility, SharedEdgesAndBorderBlocksMatchThePlainLoop) {
    // A fan of triangles around a centre (every edge shared by two of them: each pixel is covered
    // once by the top-left rule), in a block that the raster's border cuts (W, H not multiples of
    // the block), all at one depth (the first writer stays).
    const int W = 100, H = 90;
    std::vector<SnapVertex> verts;
    const std::int64_t cx = 83 * 256 + 64, cy = 70 * 256 + 128;
    const int n = 23;
    for (int k = 0; k < n; ++k) {
        const double a0 = 2 * M_PI * k / n, a1 = 2 * M_PI * (k + 1) / n;
        verts.push_back(vertex(cx, cy, 1.0f, 3.0f));
        verts.push_back(vertex(cx + std::llround(std::cos(a0) * 40 * 256), cy + std::llround(std::sin(a0) * 40 * 256), 1.0f, 3.0f));
        verts.push_back(vertex(cx + std::llround(std::cos(a1) * 40 * 256), cy + std::llround(std::sin(a1) * 40 * 256), 1.0f, 3.0f));
    }
    const std::vector<TriSetup> tris = set_up(verts, W, H);
    ASSERT_EQ(tris.size(), std::size_t(n));
    const Block fast = draw(tris, 64, 64, VisibilitySchedule::Fast);
    expect_same(fast, draw(tris, 64, 64, VisibilitySchedule::Plain), "fan");
    // Each covered pixel belongs to exactly one triangle of the fan.
    std::vector<int> hits(kBlock * kBlock, 0);
    for (const TriSetup& t : tris)
        for (int y = std::max<int>(t.y0, 64); y <= std::min<int>(t.y1, H - 1); ++y)
            for (int x = std::max<int>(t.x0, 64); x <= std::min<int>(t.x1, W - 1); ++x) {
                std::int64_t e[3];
                edge_values(t, x, y, e);
                hits[(y - 64) * kBlock + (x - 64)] += inside(t, e);
            }
    int covered = 0;
    for (int i = 0; i < kBlock * kBlock; ++i) {
        EXPECT_LE(hits[i], 1);
        covered += fast.ids[i].chunk != ~0u;
    }
    EXPECT_GT(covered, 300);
}

TEST(Visibility, SmallBlocksMatchThePlainLoopAndStayInTheirBlock) {
    // Triangles of 0.5 to 8 px piled around the four edges and corners of a block, most at one of
    // two constant depths (ties: the first stays), drawn into a buffer twice the block's size so
    // that a write outside the block shows.
    std::mt19937 rng(20261203);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const int W = 512, H = 512, X0 = 128, Y0 = 192, S = 2 * kBlock;
    std::vector<SnapVertex> verts;
    for (int k = 0; k < 6000; ++k) {
        const double u = unit(rng), size = 0.5 + 7.5 * u * u;
        // Half of them on the half-pixel grid: edges through pixel centres (the top-left rule).
        const double grid = unit(rng) < 0.5 ? 128 : 1;
        const double cx = X0 + (unit(rng) < 0.5 ? 0 : kBlock) + (unit(rng) - 0.5) * 12;
        const double cy = Y0 + (unit(rng) < 0.5 ? 0 : kBlock) + (unit(rng) - 0.5) * 12;
        const bool flat = unit(rng) < 0.8;
        const float flat_depth = float(1 + int(unit(rng) * 2));
        for (int v = 0; v < 3; ++v)
            verts.push_back(vertex(grid * std::llround((cx + (unit(rng) - 0.5) * size) * 256 / grid),
                                   grid * std::llround((cy + (unit(rng) - 0.5) * size) * 256 / grid), float(0.2 + unit(rng)),
                                   flat ? flat_depth : float(1 + unit(rng))));
    }
    const std::vector<TriSetup> tris = set_up(verts, W, H);
    ASSERT_GT(tris.size(), 2000u);
    auto run = [&](VisibilitySchedule schedule, std::vector<float>& z, std::vector<TileRef>& ids) {
        z.assign(std::size_t(S) * S, std::numeric_limits<float>::infinity());
        ids.assign(std::size_t(S) * S, TileRef{~0u, ~0u});
        for (std::uint32_t i = 0; i < tris.size(); ++i) {
            const TriSetup& t = tris[i];
            const int x0 = std::max<int>(t.x0, X0), x1 = std::min<int>(t.x1, X0 + kBlock - 1);
            const int y0 = std::max<int>(t.y0, Y0), y1 = std::min<int>(t.y1, Y0 + kBlock - 1);
            depth_test_triangle(t, X0, Y0, S, x0, x1, y0, y1, z.data(), ids.data(), {3, i}, schedule);
        }
    };
    std::vector<float> zf, zp;
    std::vector<TileRef> idf, idp;
    run(VisibilitySchedule::Fast, zf, idf);
    run(VisibilitySchedule::Plain, zp, idp);
    int diff = 0, covered = 0, outside = 0;
    for (int y = 0; y < S; ++y)
        for (int x = 0; x < S; ++x) {
            const std::size_t i = std::size_t(y) * S + x;
            diff += std::memcmp(&zf[i], &zp[i], 4) != 0 || idf[i].tri != idp[i].tri || idf[i].chunk != idp[i].chunk;
            covered += idp[i].chunk != ~0u;
            outside += (x >= kBlock || y >= kBlock) && idf[i].chunk != ~0u;
        }
    EXPECT_EQ(diff, 0);
    EXPECT_EQ(outside, 0);
    EXPECT_GT(covered, 100);
}

TEST(Visibility, LargeTrianglesThatCutABlocksCornerMatchThePlainLoop) {
    // Triangles of 70 to 100000 px with one vertex within a few pixels of the block's top-left
    // corner and the others far up and left: the block holds 1 to 8 of their pixels (the fast
    // schedule's one-register blocks) while their edge values there are far beyond 2^14 px^2.
    std::mt19937 rng(20261203);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const int W = 16384, H = 16384, X0 = 8192, Y0 = 8192;
    std::vector<SnapVertex> verts;
    for (int k = 0; k < 3000; ++k) {
        const double far = 70 * std::pow(1500.0, unit(rng));
        const double ax = X0 + 1 + (unit(rng) - 0.3) * 4, ay = Y0 + 1 + (unit(rng) - 0.3) * 4;
        const double px[3] = {ax, ax - far * unit(rng), ax - far * (0.2 + unit(rng))};
        const double py[3] = {ay, ay - far * (0.2 + unit(rng)), ay - far * unit(rng)};
        for (int v = 0; v < 3; ++v)
            verts.push_back(vertex(std::llround(px[v] * 256), std::llround(py[v] * 256), float(0.2 + unit(rng)),
                                   float(1 + int(unit(rng) * 3))));
    }
    const std::vector<TriSetup> tris = set_up(verts, W, H);
    int in_block8 = 0;
    for (const TriSetup& t : tris) {
        const int w = std::min<int>(t.x1, X0 + kBlock - 1) - std::max<int>(t.x0, X0) + 1;
        const int h = std::min<int>(t.y1, Y0 + kBlock - 1) - std::max<int>(t.y0, Y0) + 1;
        in_block8 += w > 0 && h > 0 && w * h <= 8;
    }
    EXPECT_GT(in_block8, 1000);
    const Block fast = draw(tris, X0, Y0, VisibilitySchedule::Fast);
    expect_same(fast, draw(tris, X0, Y0, VisibilitySchedule::Plain), "corner");
    int covered = 0;
    for (const TileRef& r : fast.ids) covered += r.chunk != ~0u;
    EXPECT_GE(covered, 6);
}

}  // namespace
}  // namespace aq::raster
