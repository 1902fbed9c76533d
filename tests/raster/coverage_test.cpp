// tests/raster/coverage_test.cpp — fill rule, watertightness, bounds, clipping and bad geometry.
//
// The coverage counts come from raster::debug_coverage_count (every passing coverage test counted,
// no depth test), run through both the tiled and the reference traversal.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "raster/raster.h"
#include "tests/raster/raster_test_util.h"

using namespace aq;
using aq::test::px;

namespace {

ImageF count_both(const scene::Scene& s, const scene::Camera& cam, raster::RenderSettings st,
                  std::vector<std::string>* w = nullptr) {
    st.exec = Exec::fast(2);
    ImageF fast = raster::debug_coverage_count(s, cam, st, w);
    st.exec = Exec::reference();
    ImageF ref = raster::debug_coverage_count(s, cam, st);
    EXPECT_EQ(sha256_hex(fast), sha256_hex(ref)) << "tiled and reference coverage differ";
    return fast;
}

// Point-in-convex-polygon with a margin (pixels): +1 inside by > margin, -1 outside by > margin,
// 0 near an edge. poly is in pixel space, any winding.
int classify(const std::vector<glm::dvec2>& poly, glm::dvec2 p, double margin) {
    double area = 0;
    for (std::size_t i = 0; i < poly.size(); ++i) {
        const glm::dvec2 a = poly[i], b = poly[(i + 1) % poly.size()];
        area += a.x * b.y - a.y * b.x;
    }
    const double s = area > 0 ? 1.0 : -1.0;
    double dmin = 1e300;
    for (std::size_t i = 0; i < poly.size(); ++i) {
        const glm::dvec2 a = poly[i], b = poly[(i + 1) % poly.size()];
        const glm::dvec2 e = b - a;
        const double d = s * (e.x * (p.y - a.y) - e.y * (p.x - a.x)) / glm::length(e);
        dmin = std::min(dmin, d);
    }
    if (dmin > margin) return 1;
    if (dmin < -margin) return -1;
    return 0;
}

}  // namespace

// Pixel centres exactly on the edges of a square split along a diagonal: the left and top edges
// own their centres, the right and bottom edges do not, and the shared diagonal is owned once.
TEST(FillRule, TopLeftOnSquareAndDiagonal) {
    const int W = 16, H = 16;
    for (int variant = 0; variant < 4; ++variant) {
        // Corners on pixel centres (2.5, 2.5) .. (9.5, 9.5): centres x, y in 2..9 lie on or inside.
        const glm::vec3 a = px(W, H, 2.5f, 2.5f), b = px(W, H, 9.5f, 2.5f), c = px(W, H, 9.5f, 9.5f),
                        d = px(W, H, 2.5f, 9.5f);
        std::vector<std::uint32_t> idx;
        if (variant == 0) idx = {0, 1, 2, 0, 2, 3};  // diagonal a-c
        if (variant == 1) idx = {0, 1, 3, 1, 2, 3};  // diagonal b-d
        if (variant == 2) idx = {0, 2, 1, 0, 3, 2};  // opposite winding
        if (variant == 3) idx = {0, 3, 1, 1, 3, 2};
        const scene::Scene s = test::scene_of({test::make_prim({a, b, c, d}, idx)});
        const ImageF cnt = count_both(s, test::pixel_camera(W, H), test::plain_settings(W, H));
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                // Top-left rule: x = 2 (left edge) and y = 2 (top edge) included, 9 excluded.
                const float expect = (x >= 2 && x <= 8 && y >= 2 && y <= 8) ? 1.0f : 0.0f;
                ASSERT_EQ(cnt.at(x, y, 0), expect) << "variant " << variant << " pixel " << x << "," << y;
            }
    }
}

// A lone triangle: only centres strictly inside, or on a top/left edge, are covered.
TEST(FillRule, SingleTriangleEdgesAndBounds) {
    const int W = 32, H = 32;
    // Top edge horizontal at y = 4.5 (centres on it: included); left edge from (4.5, 20.5) up to
    // (4.5, 4.5) vertical (included); hypotenuse is a right/bottom edge (excluded).
    const glm::vec3 a = px(W, H, 4.5f, 4.5f), b = px(W, H, 20.5f, 4.5f), c = px(W, H, 4.5f, 20.5f);
    const scene::Scene s = test::scene_of({test::make_prim({a, b, c}, {0, 2, 1})});
    const ImageF cnt = count_both(s, test::pixel_camera(W, H), test::plain_settings(W, H));
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const double cx = x + 0.5, cy = y + 0.5;
            const double e = (20.5 + 4.5) - (cx + cy);  // > 0 inside the hypotenuse
            const bool in = cx >= 4.5 && cy >= 4.5 && e > 0;
            ASSERT_EQ(cnt.at(x, y, 0), in ? 1.0f : 0.0f) << x << "," << y;
        }
}

// Fan around an off-grid centre with irregular angles: every pixel at most once, interior exactly
// once, nothing outside the polygon.
TEST(Watertight, Fan) {
    const int W = 96, H = 80;
    std::vector<glm::vec3> pos{px(W, H, 47.3f, 40.9f)};
    std::vector<glm::dvec2> rim;
    const int n = 23;
    for (int i = 0; i < n; ++i) {
        const double ang = 2 * M_PI * (i + 0.37 * std::sin(i * 1.7)) / n;
        const glm::dvec2 p(47.3 + 38.1 * std::cos(ang), 40.9 + 33.7 * std::sin(ang));
        rim.push_back(p);
        pos.push_back(px(W, H, float(p.x), float(p.y)));
    }
    std::vector<std::uint32_t> idx;
    for (int i = 0; i < n; ++i) idx.insert(idx.end(), {0u, std::uint32_t(1 + i), std::uint32_t(1 + (i + 1) % n)});
    const scene::Scene s = test::scene_of({test::make_prim(pos, idx)});
    const ImageF cnt = count_both(s, test::pixel_camera(W, H), test::plain_settings(W, H));
    int interior = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const float c = cnt.at(x, y, 0);
            ASSERT_LE(c, 1.0f) << "pixel " << x << "," << y << " covered twice";
            const int k = classify(rim, {x + 0.5, y + 0.5}, 0.01);
            if (k > 0) {
                ASSERT_EQ(c, 1.0f) << "hole at " << x << "," << y;
                ++interior;
            }
            if (k < 0) { ASSERT_EQ(c, 0.0f) << "outside pixel " << x << "," << y << " covered"; }
        }
    EXPECT_GT(interior, 3000);
}

// Jittered grid of shared vertices: all interior pixels exactly once.
TEST(Watertight, JitteredGrid) {
    const int W = 128, H = 96, N = 13;
    std::vector<glm::vec3> pos;
    auto jit = [](int i, int j, int k) { return 2.9 * std::sin(i * 12.9898 + j * 78.233 + k * 3.1); };
    for (int j = 0; j <= N; ++j)
        for (int i = 0; i <= N; ++i) {
            double x = 10.25 + i * 8.0, y = 6.75 + j * 6.0;
            if (i > 0 && i < N) x += jit(i, j, 0);
            if (j > 0 && j < N) y += jit(i, j, 1) * 0.6;
            pos.push_back(px(W, H, float(x), float(y)));
        }
    std::vector<std::uint32_t> idx;
    for (int j = 0; j < N; ++j)
        for (int i = 0; i < N; ++i) {
            const std::uint32_t a = j * (N + 1) + i, b = a + 1, c = a + (N + 1), d = c + 1;
            if ((i + j) % 2) idx.insert(idx.end(), {a, c, b, b, c, d});
            else idx.insert(idx.end(), {a, d, b, a, c, d});
        }
    const scene::Scene s = test::scene_of({test::make_prim(pos, idx)});
    const ImageF cnt = count_both(s, test::pixel_camera(W, H), test::plain_settings(W, H));
    const std::vector<glm::dvec2> outline{{10.25, 6.75}, {10.25 + N * 8.0, 6.75}, {10.25 + N * 8.0, 6.75 + N * 6.0},
                                          {10.25, 6.75 + N * 6.0}};
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const float c = cnt.at(x, y, 0);
            ASSERT_LE(c, 1.0f) << x << "," << y;
            const int k = classify(outline, {x + 0.5, y + 0.5}, 0.01);
            if (k > 0) { ASSERT_EQ(c, 1.0f) << "hole at " << x << "," << y; }
            if (k < 0) { ASSERT_EQ(c, 0.0f) << x << "," << y; }
        }
}

// Closed sphere in perspective: with back faces culled every pixel inside the silhouette is
// covered exactly once; without culling exactly twice (front and back shells).
TEST(Watertight, ClosedSphere) {
    const int W = 160, H = 120;
    const scene::Scene s = test::scene_of({test::uv_sphere(37, 23, 1.0f)});
    const float fov = 0.9f, dist = 3.2f;
    const scene::Camera cam = test::look_at({0, 0, dist}, {0, 0, 0}, fov);
    // Silhouette radius in pixels of the inscribed polygonal sphere is below that of the true
    // sphere; the true one bounds it from outside.
    const double f = 1.0 / std::tan(0.5 * fov) * 0.5 * H;
    const double r_true = std::tan(std::asin(1.0 / dist)) * f;
    for (bool cull : {true, false}) {
        raster::RenderSettings st = test::plain_settings(W, H);
        st.cull_backfaces = cull;
        const ImageF cnt = count_both(s, cam, st);
        int inside = 0;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const double r = std::hypot(x + 0.5 - 0.5 * W, y + 0.5 - 0.5 * H);
                const float c = cnt.at(x, y, 0);
                ASSERT_LE(c, cull ? 1.0f : 2.0f) << x << "," << y;
                if (r < r_true - 2.0) {
                    ASSERT_EQ(c, cull ? 1.0f : 2.0f) << "pixel " << x << "," << y << " cull " << cull;
                    ++inside;
                }
                if (r > r_true + 0.5) { ASSERT_EQ(c, 0.0f) << x << "," << y; }
            }
        EXPECT_GT(inside, 2000);
    }
}

// A ground plane from behind the camera to far in front: the visible part renders (below the
// horizon), nothing above it; the linear depth matches the analytic ray-plane distance.
TEST(Clipping, NearPlaneCrossingTriangle) {
    const int W = 64, H = 48;
    const scene::Scene s = test::scene_of(
        {test::make_prim({{-30, -1, 5}, {30, -1, 5}, {30, -1, -60}, {-30, -1, -60}}, {0, 1, 2, 0, 2, 3})},
        test::flat_material());
    const float fov = 1.0f;
    const scene::Camera cam = test::look_at({0, 0, 0}, {0, 0, -1}, fov, 0.1f, 100.0f);
    for (Traversal tr : {Traversal::Fast, Traversal::Reference}) {
        raster::RenderSettings st = test::plain_settings(W, H);
        st.exec.traversal = tr;
        std::vector<std::string> warn;
        const Targets t = raster::render_gbuffer(s, cam, st, &warn);
        const ImageF& col = t.get(target::kColor);
        const ImageF& dep = t.get(target::kDepthLinear);
        const double th = std::tan(0.5 * fov);
        int covered = 0;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const double ndc_y = 1.0 - 2.0 * (y + 0.5) / H;
                const double ndc_x = 2.0 * (x + 0.5) / W - 1.0;
                const double ry = ndc_y * th;  // ray (rx, ry, -1)
                const double rx = ndc_x * th * double(W) / H;
                const double depth = ry < 0 ? 1.0 / -ry : 1e9;  // plane y = -1
                const bool expect = depth < 59.0 && std::abs(rx * depth) < 29.0;
                if (ry > 0) {
                    ASSERT_EQ(col.at(x, y, 3), 0.0f) << "above the horizon " << x << "," << y;
                    ASSERT_EQ(dep.at(x, y, 0), 100.0f);
                }
                if (expect) {
                    ASSERT_EQ(col.at(x, y, 3), 1.0f) << x << "," << y;
                    if (depth < 30.0) { ASSERT_NEAR(dep.at(x, y, 0), depth, depth * 2e-3) << x << "," << y; }
                    ++covered;
                }
            }
        EXPECT_GT(covered, W * H / 3);
    }
}

TEST(Clipping, FullyBehindCameraRendersNothing) {
    const int W = 32, H = 32;
    const scene::Scene s = test::scene_of({test::make_prim({{-1, -1, 1}, {1, -1, 1}, {0, 1, 3}}, {0, 1, 2})});
    const scene::Camera cam = test::look_at({0, 0, 0}, {0, 0, -1});
    const ImageF cnt = count_both(s, cam, test::plain_settings(W, H));
    for (std::size_t i = 0; i < cnt.num_values(); ++i) ASSERT_EQ(cnt.data()[i], 0.0f);
    const Targets t = raster::render_gbuffer(s, cam, test::plain_settings(W, H));
    const ImageF& id = t.get(target::kObjectId);
    for (std::size_t i = 0; i < id.num_values(); ++i) ASSERT_EQ(id.data()[i], 0.0f);
}

// Triangles with 1e30 / 1e38 coordinates and NaN / Inf: no crash, the NaN/Inf ones are dropped
// with a warning, and a normal triangle in front still renders exactly as on its own.
TEST(BadGeometry, HugeAndNonFiniteCoordinates) {
    const int W = 64, H = 64;
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    const scene::Primitive good = test::make_prim({{-0.5f, -0.5f, -2}, {0.5f, -0.5f, -2}, {0, 0.5f, -2}}, {0, 1, 2});
    scene::Primitive bad = test::make_prim(
        {{-1e30f, -1e30f, -5}, {1e30f, -1e30f, -5}, {0, 1e30f, -5},       // huge, spans the view
         {-1e38f, 0, -5}, {3e38f, 1e38f, -3e38f}, {0, -3e38f, 1e38f},    // near float max
         {nan, 0, -5}, {1, 0, -5}, {0, 1, -5},                           // NaN
         {inf, 0, -5}, {1, 0, -5}, {0, 1, -5},                           // Inf
         {-1, 40, -1e30f}, {1, 40, -1e30f}, {0, 42, 1e30f}},             // huge depth range, above
        {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14});
    const scene::Camera cam = test::look_at({0, 0, 0}, {0, 0, -1}, 0.9f, 0.1f, 100.0f);
    const scene::Scene both = test::scene_of({good, bad});
    const scene::Scene alone = test::scene_of({good});
    raster::RenderSettings st = test::plain_settings(W, H);
    for (Traversal tr : {Traversal::Fast, Traversal::Reference}) {
        st.exec.traversal = tr;
        std::vector<std::string> warn;
        const Targets tb = raster::render_gbuffer(both, cam, st, &warn);
        const Targets ta = raster::render_gbuffer(alone, cam, st);
        bool warned = false;
        for (const std::string& w : warn) warned |= w.find("non-finite") != std::string::npos;
        EXPECT_TRUE(warned) << "NaN/Inf triangles must be reported";
        // Where the good triangle is, both renders agree exactly (it is in front of the rest).
        const ImageF& ida = ta.get(target::kObjectId);
        int good_px = 0;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x)
                if (ida.at(x, y, 0) == 1.0f) {
                    ++good_px;
                    ASSERT_EQ(tb.get(target::kObjectId).at(x, y, 0), 1.0f);
                    for (int c = 0; c < 4; ++c)
                        ASSERT_EQ(tb.get(target::kColor).at(x, y, c), ta.get(target::kColor).at(x, y, c));
                    ASSERT_EQ(tb.get(target::kDepthLinear).at(x, y, 0), ta.get(target::kDepthLinear).at(x, y, 0));
                }
        EXPECT_GT(good_px, 100);
        // The huge (finite) triangle at z = -5 behind it covers the rest of the view.
        EXPECT_EQ(tb.get(target::kObjectId).at(2, 2, 0), 2.0f);
    }
}

TEST(BadGeometry, DegenerateTrianglesCoverNothing) {
    const int W = 32, H = 32;
    const scene::Scene s = test::scene_of({test::make_prim(
        {px(W, H, 3, 3), px(W, H, 20, 20), px(W, H, 11.5f, 11.5f),  // collinear
         px(W, H, 5, 5), px(W, H, 5, 5), px(W, H, 5, 5),             // a point
         px(W, H, 8, 8), px(W, H, 8.001f, 8), px(W, H, 8, 8.001f)},  // zero area after snapping
        {0, 1, 2, 3, 4, 5, 6, 7, 8})});
    const ImageF cnt = count_both(s, test::pixel_camera(W, H), test::plain_settings(W, H));
    for (std::size_t i = 0; i < cnt.num_values(); ++i) ASSERT_EQ(cnt.data()[i], 0.0f);
}

TEST(Culling, BackFacesCulledUnlessDoubleSided) {
    const int W = 32, H = 32;
    // Clockwise as seen from the camera (+Z): a back face.
    const auto prim = test::make_prim({px(W, H, 4, 4), px(W, H, 28, 4), px(W, H, 4, 28)}, {0, 1, 2});
    for (bool ds : {false, true}) {
        scene::Material m;
        m.double_sided = ds;
        const scene::Scene s = test::scene_of({prim}, m);
        raster::RenderSettings st = test::plain_settings(W, H);
        st.cull_backfaces = true;
        const ImageF cnt = count_both(s, test::pixel_camera(W, H), st);
        EXPECT_EQ(cnt.at(8, 8, 0), ds ? 1.0f : 0.0f);
        st.cull_backfaces = false;
        EXPECT_EQ(count_both(s, test::pixel_camera(W, H), st).at(8, 8, 0), 1.0f);
    }
    // Counter-clockwise (front face) is never culled.
    const auto front = test::make_prim({px(W, H, 4, 4), px(W, H, 4, 28), px(W, H, 28, 4)}, {0, 1, 2});
    raster::RenderSettings st = test::plain_settings(W, H);
    st.cull_backfaces = true;
    EXPECT_EQ(count_both(test::scene_of({front}), test::pixel_camera(W, H), st).at(8, 8, 0), 1.0f);
}

// Large triangles spanning many tiles: the tiled count equals the reference and is exact.
TEST(Watertight, TriangleSpanningManyTiles) {
    const int W = 300, H = 200;
    const scene::Scene s = test::scene_of({test::make_prim(
        {px(W, H, -50.3f, -20.1f), px(W, H, 350.7f, 10.2f), px(W, H, 120.2f, 260.9f), px(W, H, 400, 300)},
        {0, 2, 1, 1, 2, 3})});
    const ImageF cnt = count_both(s, test::pixel_camera(W, H), test::plain_settings(W, H));
    for (std::size_t i = 0; i < cnt.num_values(); ++i) ASSERT_LE(cnt.data()[i], 1.0f);
    EXPECT_EQ(cnt.at(150, 100, 0), 1.0f);
}

// Thousands of small draws (chunks span draws): tiled == reference and every quad is drawn.
TEST(TiledVsReferenceSmall, ManySmallDraws) {
    const int W = 200, H = 150, N = 3000;
    scene::Scene s;
    s.materials.push_back(test::flat_material({0.3f, 0.6f, 0.9f, 1.0f}));
    s.meshes.push_back({"quad", {test::make_prim({px(W, H, 0, 0), px(W, H, 0, 3), px(W, H, 3, 3), px(W, H, 3, 0)},
                                                 {0, 1, 2, 0, 2, 3})}});
    for (int i = 0; i < N; ++i) {
        scene::Instance inst;
        inst.mesh = 0;
        inst.world = glm::translate(glm::mat4(1.0f), glm::vec3(float((i * 37) % (W - 3)), -float((i * 11) % (H - 3)), -0.001f * i));
        inst.object_id = std::uint32_t(i + 1);
        s.instances.push_back(inst);
    }
    raster::RenderSettings st = test::plain_settings(W, H);
    st.exec = Exec::fast(2);
    const Targets fast = raster::render_gbuffer(s, test::pixel_camera(W, H), st);
    st.exec = Exec::reference();
    const Targets ref = raster::render_gbuffer(s, test::pixel_camera(W, H), st);
    for (const auto& [name, img] : fast.all()) EXPECT_EQ(sha256_hex(img), sha256_hex(ref.get(name))) << name;
    // Instance i sits at z = -1 - 0.001 i: instance 0 is the nearest where quads overlap.
    const ImageF& id = fast.get(target::kObjectId);
    EXPECT_EQ(id.at(1, 1, 0), 1.0f);
}
