// tests/raster/strokes_test.cpp — LD06 §4.4 strokes (raster/strokes.h): coverage along a polyline
// is the union of the segments' capsules (no gap and no double hit at joints), fades follow their
// definitions, contours of a sphere ring its silhouette, bad input is dropped or refused, and the
// same bytes come out of every traversal and thread count.
#include <gtest/gtest.h>

#include <limits>

#include <cmath>

#include "core/hash.h"
#include "raster/foliage.h"
#include "raster/strokes.h"
#include "raster/vertex.h"
#include "scenes/gltf_loader.h"
#include "tests/raster/raster_test_util.h"
#include "tests/test_support.h"

namespace aq::raster {
namespace {

struct Fixture {
    scene::Scene sc = test::scene_of({test::make_prim({{-2, -2, -1}, {2, -2, -1}, {0, 2, -1}}, {0, 1, 2})});
    scene::Camera cam = test::look_at({0, 0, 6}, {0, 0, 0});
    PassScene ps = make_pass_scene(sc, cam, 160, 120);
    glm::vec2 px(glm::vec3 w) const {
        const PassViewSetup v = pass_view(ps, PassView::Camera, 1.0f);
        const glm::vec4 c = projection_matrix(v.camera, 160.0f / 120.0f) * v.camera.view * glm::vec4(w, 1.0f);
        return {(c.x / c.w + 1.0f) * 80.0f, (1.0f - c.y / c.w) * 60.0f};
    }
};

// GLSL smoothstep, written out.
float stylize_smoothstep_for_test(float a, float b, float x) {
    const float t = std::clamp((x - a) / (b - a), 0.0f, 1.0f);
    return t * t * (3.0f - 2.0f * t);
}

// Distance from point p to segment ab, in double (written independently of the implementation).
double dist(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b) {
    const glm::dvec2 d = b - a;
    const double t = std::clamp(glm::dot(p - a, d) / glm::dot(d, d), 0.0, 1.0);
    return glm::length(a + d * t - p);
}

TEST(Strokes, CoverageIsTheUnionOfCapsulesWithoutGapsOrDoubleHitsAtJoints) {
    Fixture f;
    // A zig-zag with a sharp joint and a shallow one, in the plane z = 0 facing the camera.
    const std::vector<glm::vec3> pts = {{-1.5f, -0.5f, 0}, {0.0f, 0.8f, 0}, {0.2f, -0.9f, 0}, {1.4f, -0.6f, 0}};
    StrokeParams p;
    p.test = DepthTest::Binary;  // no depth map: f_v = 1
    p.width_px = 5.0f * 720.0f / 160.0f;  // 5 px wide at 160 px
    p.alpha = 0.5f;
    p.fade_near = p.fade_far = 1.0f;
    ImageF out;
    render_strokes(out, f.ps, {Stroke{pts, {}, false}}, p, Exec::reference());
    std::vector<glm::dvec2> s;
    for (const glm::vec3& q : pts) s.push_back(glm::dvec2(f.px(q)));
    int covered = 0, mismatches = 0;
    for (int y = 0; y < 120; ++y)
        for (int x = 0; x < 160; ++x) {
            const glm::dvec2 c(x + 0.5, y + 0.5);
            double d = 1e9;
            for (std::size_t k = 0; k + 1 < s.size(); ++k) d = std::min(d, dist(c, s[k], s[k + 1]));
            const float v = out.at(x, y, 0);
            ASSERT_TRUE(v == 0.0f || v == 0.5f) << "pixel " << x << "," << y << " hit twice or partly: " << v;
            if (std::abs(d - 2.5) < 1e-3) continue;  // on the capsule border: float rounding may go either way
            mismatches += (d <= 2.5) != (v == 0.5f);
            covered += v == 0.5f;
        }
    EXPECT_EQ(mismatches, 0);
    EXPECT_GT(covered, 300);
}

// Short strokes (hatching-sized: a few pixels long, 0.6-6 px wide) at arbitrary sub-pixel
// positions, drawn by both traversals: a pixel is covered exactly when its centre lies within half
// the width of a segment (the drawn pixels come from per-segment bounds, which must not lose any).
TEST(Strokes, ShortStrokesAtSubpixelPositionsCoverTheirCapsules) {
    Fixture f;
    std::uint32_t seed = 12345u;
    auto uniform = [&](double lo, double hi) {  // a fixed LCG: the same strokes on every platform
        seed = seed * 1664525u + 1013904223u;
        return lo + (hi - lo) * double(seed >> 8) / double(1u << 24);
    };
    // A size in whole 8-pixel groups and one that is not (the right and bottom tiles end mid-group);
    // strokes anywhere, crossing the image's edges too.
    for (const glm::ivec2 size : {glm::ivec2(160, 120), glm::ivec2(157, 117)}) {
        const int W = size.x, H = size.y;
        const PassScene ps = make_pass_scene(f.sc, f.cam, W, H);
        const PassViewSetup v = pass_view(ps, PassView::Camera, 1.0f);
        const glm::mat4 vp = projection_matrix(v.camera, float(W) / float(H)) * v.camera.view;
        const glm::mat4 inv = glm::inverse(vp);
        auto world_of = [&](glm::dvec2 px) {  // the pixel position on the plane z = 0 (a ray hit)
            const glm::vec2 ndc(float(px.x / (0.5 * W) - 1.0), float(1.0 - px.y / (0.5 * H)));
            const glm::vec4 a = inv * glm::vec4(ndc, -1.0f, 1.0f), b = inv * glm::vec4(ndc, 1.0f, 1.0f);
            const glm::vec3 pa = glm::vec3(a) / a.w, pb = glm::vec3(b) / b.w;
            return pa + (pb - pa) * (-pa.z / (pb.z - pa.z));
        };
        auto px_of = [&](glm::vec3 w) {
            const glm::vec4 c = vp * glm::vec4(w, 1.0f);
            return glm::dvec2((c.x / c.w + 1.0f) * 0.5f * float(W), (1.0f - c.y / c.w) * 0.5f * float(H));
        };
        int covered = 0, mismatches = 0, checked = 0, at_edges = 0;
        for (int k = 0; k < 80; ++k) {
            const double width = uniform(0.6, 6.0);
            std::vector<glm::vec3> pts;
            glm::dvec2 c(uniform(-3, W + 3), uniform(-3, H + 3));
            for (int i = 0; i < 3; ++i, c += glm::dvec2(uniform(-4, 4), uniform(-4, 4))) pts.push_back(world_of(c));
            std::vector<glm::dvec2> s;
            for (const glm::vec3& q : pts) s.push_back(px_of(q));
            StrokeParams p;
            p.test = DepthTest::Binary;
            p.width_px = float(width * 720.0 / W);
            p.fade_near = p.fade_far = 1.0f;
            const double half = 0.5 * double(p.width_px) * W / 720.0;
            for (const Exec& ex : {Exec::reference(), Exec::fast(2)}) {
                ImageF out;
                render_strokes(out, ps, {Stroke{pts, {}, false}}, p, ex);
                for (int y = 0; y < H; ++y)
                    for (int x = 0; x < W; ++x) {
                        const glm::dvec2 q(x + 0.5, y + 0.5);
                        const double d = std::min(dist(q, s[0], s[1]), dist(q, s[1], s[2]));
                        if (std::abs(d - half) < 1e-4) continue;  // on the border: float rounding may go either way
                        const bool drawn = out.at(x, y, 0) != 0.0f;
                        mismatches += (d <= half) != drawn;
                        covered += drawn;
                        checked += d < half + 1.0;
                        at_edges += drawn && (x == W - 1 || y == H - 1);
                    }
            }
        }
        EXPECT_EQ(mismatches, 0) << W << " x " << H;
        EXPECT_GT(covered, 1000);
        EXPECT_GT(checked, covered);
        EXPECT_GT(at_edges, 10) << "strokes crossing the right and bottom edges";
    }
}

// A stroke from a point in view to one behind the camera is clipped at the near plane: what is
// drawn runs from the visible point towards the clipped end's side of the screen (x grows; the
// point behind the camera would project mirrored, to the left), to the image edge.
TEST(Strokes, AStrokeCrossingTheNearPlaneRunsFromItsVisibleEndToTheClippedEnd) {
    Fixture f;
    StrokeParams p;
    p.test = DepthTest::Binary;
    p.width_px = 3.0f * 720.0f / 160.0f;
    p.fade_near = p.fade_far = 1.0f;
    const glm::vec3 seen(0.5f, 0.0f, 0.0f), behind(0.5f, 0.0f, 7.0f);  // the camera is at (0, 0, 6)
    const glm::vec2 c = f.px(seen);
    for (const Exec& ex : {Exec::reference(), Exec::fast(2)}) {
        for (const bool reversed : {false, true}) {
            ImageF out;
            std::size_t dropped = 0;
            const std::vector<glm::vec3> pts = reversed ? std::vector<glm::vec3>{behind, seen} : std::vector<glm::vec3>{seen, behind};
            render_strokes(out, f.ps, {Stroke{pts, {}, false}}, p, ex, &dropped);
            EXPECT_EQ(dropped, 0u);
            const int y = int(c.y);
            int right = 0, left = 0;
            for (int x = 0; x < 160; ++x) {
                right += x > int(c.x) + 3 && out.at(x, y, 0) > 0.0f;
                left += x < int(c.x) - 3 && out.at(x, y, 0) > 0.0f;
            }
            EXPECT_EQ(right, 160 - (int(c.x) + 4)) << "the clipped end lies right of the image: drawn to the edge";
            EXPECT_EQ(left, 0) << "nothing left of the visible end";
        }
    }
}

TEST(Strokes, FadesFollowTheirDefinitions) {
    Fixture f;
    StrokeParams p;
    p.test = DepthTest::Binary;
    p.width_px = 20.0f;
    p.fade_near = p.fade_far = 1.0f;
    const std::vector<glm::vec3> pts = {{-1, 0, 0}, {1, 0, 0}};
    auto centre = [&](const Stroke& s, const StrokeParams& q) {
        ImageF out;
        render_strokes(out, f.ps, {s}, q, Exec::reference());
        const glm::vec2 c = f.px({0, 0, 0});
        return out.at(int(c.x), int(c.y), 0);
    };
    // n.v: facing the camera -> full; edge-on -> invisible; in between -> the smoothstep.
    EXPECT_EQ(centre({pts, {{0, 0, 1}, {0, 0, 1}}, false}, p), 1.0f);
    EXPECT_EQ(centre({pts, {{0, 1, 0}, {0, 1, 0}}, false}, p), 0.0f);
    const glm::vec3 n = glm::normalize(glm::vec3(0, 1, 0.2f));
    const float nv = glm::dot(n, glm::normalize(glm::vec3(0, 0, 6)));
    EXPECT_NEAR(centre({pts, {n, n}, false}, p), stylize_smoothstep_for_test(p.nv_lo, p.nv_hi, nv), 1e-5f);
    // Hatching strokes fade on the lit side (n.l >= nl_hi), stay on the dark side.
    scene::Scene lit = f.sc;
    lit.lights.push_back({glm::vec3(0, 0, 1), glm::vec3(1), 1.0f});
    Fixture g;
    g.ps = make_pass_scene(lit, f.cam, 160, 120);
    ImageF out;
    render_strokes(out, g.ps, {Stroke{pts, {{0, 0, 1}, {0, 0, 1}}, true}}, p, Exec::reference());
    const glm::vec2 c = f.px({0, 0, 0});
    EXPECT_EQ(out.at(int(c.x), int(c.y), 0), 0.0f) << "n.l = 1: a hatching stroke on the lit side fades out";
    // Distance fade: 1 before fade_near, 0 from fade_far on.
    p.fade_near = 0.0f;
    p.fade_far = 0.01f;
    EXPECT_EQ(centre({pts, {}, false}, p), 0.0f);
}

TEST(Strokes, ContoursOfASphereRingItsSilhouette) {
    scene::Scene sc = test::scene_of({test::uv_sphere(48, 24, 1.0f)});
    const scene::Camera cam = test::look_at({0, 0, 5}, {0, 0, 0});
    const PassScene ps = make_pass_scene(sc, cam, 200, 200);
    const std::vector<Stroke> c = contour_strokes(ps);
    ASSERT_FALSE(c.empty());
    std::size_t points = 0;
    for (const Stroke& s : c) {
        points += s.points.size();
        for (const glm::vec3& q : s.points) {
            // Silhouette of a unit sphere seen from distance 5: where the view ray is tangent,
            // q.z = 1/5; the polygonal sphere's silhouette edges lie near that circle.
            EXPECT_NEAR(q.z, 0.2f, 0.15f);
            EXPECT_NEAR(glm::length(q), 1.0f, 0.02f);
        }
    }
    EXPECT_GE(points, 48u);
    EXPECT_LE(c.size(), 4u) << "the silhouette is chained into a few polylines, not loose edges";
}

TEST(Strokes, BadInputIsDroppedOrRefused) {
    Fixture f;
    StrokeParams p;
    p.test = DepthTest::Binary;
    ImageF out;
    std::size_t dropped = 0;
    render_strokes(out, f.ps, {Stroke{{{0, 0, 0}, {NAN, 0, 0}, {1, 1, 0}, {1, 0, 0}}, {}, false}}, p, Exec::fast(2), &dropped);
    EXPECT_EQ(dropped, 2u) << "both segments touching the NaN point";
    p.width_px = 0;
    EXPECT_THROW(render_strokes(out, f.ps, std::vector<Stroke>{}, p), Error);
    p.width_px = 1000;
    EXPECT_THROW(render_strokes(out, f.ps, std::vector<Stroke>{}, p), Error);
    p = {};
    EXPECT_THROW(render_strokes(out, f.ps, std::vector<Stroke>{}, p), Error) << "blurred test without a depth map";
    p.test = DepthTest::Binary;
    std::vector<Stroke> many(kMaxStrokes + 1);
    EXPECT_THROW(render_strokes(out, f.ps, many, p), Error);
    // Issue 47 item 5: the drawing's work is bounded before a pixel is touched. 700,000 points
    // zig-zagging across the whole 160 x 120 image: every segment's capsule bounds cover it (about
    // 1.4e10 pixel-segment tests, minutes of work), refused with the budget named.
    {
        std::vector<glm::vec3> zig;
        for (int i = 0; i < 700000; ++i) zig.push_back({i % 2 ? 5.0f : -5.0f, i % 2 ? -4.0f : 4.0f, 0.0f});
        StrokeParams w = p;
        w.width_px = kMaxStrokeWidthPx;
        for (const Exec& ex : {Exec::fast(2), Exec::reference()}) {
            try {
                render_strokes(out, f.ps, {Stroke{zig, {}, false}}, w, ex);
                ADD_FAILURE() << "no error";
            } catch (const Error& e) {
                EXPECT_NE(std::string(e.what()).find("over the budget"), std::string::npos) << e.what();
            }
        }
    }
    // A stroke crossing the camera's near plane is clipped, not dropped.
    render_strokes(out, f.ps, {Stroke{{{0, 0, 0}, {0, 0, 10}}, {}, false}}, p, Exec::reference(), &dropped);
    EXPECT_EQ(dropped, 0u);
}

TEST(Strokes, SameBytesForEveryTraversalAndThreadCount) {
    const scene::Scene bush = scene::load_gltf(test::asset("plants/ez-tree/ez_bush2.glb"));
    const auto a = abstract_foliage(bush, [] { FoliageParams fp; fp.threshold = 4.0f; return fp; }());
    const scene::Camera cam = test::frame_scene(a->scene);
    const PassScene ps = make_pass_scene(a->scene, cam, 220, 180);
    TrianglePass dp;
    dp.value = PassValue::Depth;
    ImageF depth;
    render_triangle_pass(depth, ps, dp, Exec::fast(2));
    std::vector<Stroke> strokes = contour_strokes(ps, Exec::reference());
    ASSERT_GT(strokes.size(), 3u);
    // The facing and silhouette tests run in blocks on the fast traversal: the trunk has
    // more triangles than one block, and every thread count chains the same strokes.
    const ContourCache cache = build_contour_cache(a->scene);
    std::size_t trunk_tris = 0;
    for (const ContourCache::Mesh& m : cache.meshes) trunk_tris += m.prim->indices.size() / 3;
    EXPECT_GT(trunk_tris, 2 * kContourBlock);
    for (int threads : {1, 2, 8}) {
        const std::vector<Stroke> c = contour_strokes(ps, cache, Exec::fast(threads));
        ASSERT_EQ(c.size(), strokes.size()) << threads;
        for (std::size_t i = 0; i < c.size(); ++i) EXPECT_EQ(c[i].points, strokes[i].points) << threads << " " << i;
    }
    // Plus a hatching stroke with normals.
    strokes.push_back({a->surface.positions.size() > 10
                           ? std::vector<glm::vec3>(a->surface.positions.begin(), a->surface.positions.begin() + 10)
                           : std::vector<glm::vec3>{},
                       {}, true});
    // And more strokes than one projection task holds (512): short hatching with normals over the
    // crown, every 97th with a NaN point (its two segments dropped in whichever task projects it).
    const std::vector<glm::vec3>& sp = a->surface.positions;
    const std::vector<glm::vec3>& sn = a->surface.normals;
    ASSERT_GT(sp.size(), 100u);
    for (std::size_t k = 0; k < 1300; ++k) {
        const std::size_t i = k * (sp.size() - 3) / 1300;
        Stroke h{{sp[i], sp[i + 1], sp[i + 2]}, {sn[i], sn[i + 1], sn[i + 2]}, k % 2 == 0};
        if (k % 97 == 5) h.points[1].y = std::numeric_limits<float>::quiet_NaN();
        strokes.push_back(std::move(h));
    }
    for (DepthTest t : {DepthTest::Blurred, DepthTest::BlurredRgba8, DepthTest::Binary}) {
        StrokeParams p;
        p.depth_map = &depth;
        p.test = t;
        p.width_px = 3;
        ImageF ref;
        std::size_t ref_dropped = 0;
        render_strokes(ref, ps, strokes, p, Exec::reference(), &ref_dropped);
        EXPECT_EQ(ref_dropped, 2u * 14u) << "14 strokes with a NaN point";
        float sum = 0;
        for (int y = 0; y < ref.height(); ++y)
            for (int x = 0; x < ref.width(); ++x) sum += ref.at(x, y, 0);
        EXPECT_GT(sum, 20.0f) << "drew nothing";
        for (int threads : {1, 2, 8}) {
            ImageF fast;
            std::size_t fast_dropped = 0;
            render_strokes(fast, ps, strokes, p, Exec::fast(threads), &fast_dropped);
            EXPECT_EQ(sha256_hex(fast), sha256_hex(ref)) << int(t) << " " << threads;
            EXPECT_EQ(fast_dropped, ref_dropped);
        }
        // The same strokes split over two lists (the strokes pass: the scene's, then the contours).
        const std::vector<Stroke> head(strokes.begin(), strokes.begin() + 2), tail(strokes.begin() + 2, strokes.end());
        const std::vector<Stroke>* lists[2] = {&head, &tail};
        for (const Exec& ex : {Exec::reference(), Exec::fast(2)}) {
            ImageF split;
            render_strokes(split, ps, lists, p, ex);
            EXPECT_EQ(sha256_hex(split), sha256_hex(ref)) << int(t) << " two lists";
        }
    }
}

}  // namespace
}  // namespace aq::raster
