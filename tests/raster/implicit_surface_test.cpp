// tests/raster/implicit_surface_test.cpp — LD06 eq. 6-7 (raster/implicit_surface.h): the surface
// of one point is the analytic sphere, the mesh is closed and consistently wound, the build is
// the same bytes for every schedule, and absurd grids are refused before allocating.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <utility>

#include "core/hash.h"
#include "raster/implicit_surface.h"

namespace aq::raster {
namespace {

// Radius where one point's density (1 - (d/r)²)² equals T (eq. 6 = eq. 7): d = r sqrt(1 - sqrt(T)).
double sphere_radius(double T, double r) { return r * std::sqrt(1.0 - std::sqrt(T)); }

// Closed and consistently wound: every edge is used as often in one direction as in the other (no
// boundary). `manifold`: exactly once each way. Surface nets may join two sheets at a cell whose
// corners are ambiguous (an edge then has four triangles), so general clouds are only closed.
void expect_closed_and_consistent(const ImplicitSurface& s, bool manifold = true) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    for (std::size_t t = 0; t < s.indices.size(); t += 3)
        for (int e = 0; e < 3; ++e) ++directed[{s.indices[t + e], s.indices[t + (e + 1) % 3]}];
    int bad = 0;
    for (const auto& [e, n] : directed) {
        const auto back = directed.find({e.second, e.first});
        const int m = back == directed.end() ? 0 : back->second;
        if (m != n || (manifold && n != 1)) ++bad;
    }
    EXPECT_EQ(bad, 0) << "edges on a boundary or wound inconsistently";
}

TEST(ImplicitSurface, OnePointIsASphereOfTheAnalyticRadius) {
    for (auto [T, r, cpr] : {std::tuple{0.25f, 1.0f, 8}, std::tuple{0.5f, 3.0f, 6}, std::tuple{0.05f, 0.2f, 10}}) {
        const glm::vec3 c(1.5f, -2.0f, 0.25f);
        ImplicitSurfaceParams p;
        p.threshold = T;
        p.radius = r;
        p.cells_per_radius = cpr;
        const ImplicitSurface s = build_implicit_surface({c}, p);
        ASSERT_GT(s.positions.size(), 50u);
        const double R = sphere_radius(T, r);
        const double cell = r / cpr;
        for (std::size_t i = 0; i < s.positions.size(); ++i) {
            const glm::vec3 d = s.positions[i] - c;
            EXPECT_NEAR(glm::length(d), R, 0.15 * cell) << "T " << T << " r " << r;
            EXPECT_GT(glm::dot(s.normals[i], glm::normalize(d)), 0.98f) << "normal not radial";
        }
        expect_closed_and_consistent(s);
        // Euler characteristic of a sphere: V - E + F = 2.
        const long V = long(s.positions.size()), F = long(s.indices.size() / 3), E = 3 * F / 2;
        EXPECT_EQ(V - E + F, 2);
        // Winding: counter-clockwise seen from outside (face normal along the outward direction).
        for (std::size_t t = 0; t < s.indices.size(); t += 3) {
            const glm::vec3 a = s.positions[s.indices[t]], b = s.positions[s.indices[t + 1]], e = s.positions[s.indices[t + 2]];
            ASSERT_GT(glm::dot(glm::cross(b - a, e - a), (a + b + e) / 3.0f - c), 0.0f);
        }
    }
}

TEST(ImplicitSurface, DensityIsEquation6Summed) {
    const std::vector<glm::vec3> pts = {{0, 0, 0}, {0.5f, 0, 0}};
    EXPECT_FLOAT_EQ(implicit_density(pts, 1.0f, {0, 0, 0}), 1.0f + std::pow(1.0f - 0.25f, 2.0f));
    EXPECT_FLOAT_EQ(implicit_density(pts, 1.0f, {2, 0, 0}), 0.0f);
    EXPECT_FLOAT_EQ(implicit_density(pts, 1.0f, {0.25f, 0, 0}), 2.0f * std::pow(1.0f - 0.0625f, 2.0f));
}

TEST(ImplicitSurface, ThresholdAboveTheFieldGivesNothingAndFarPointsGiveTwoSpheres) {
    ImplicitSurfaceParams p;
    p.radius = 1.0f;
    p.threshold = 1.5f;  // one point's density peaks at 1
    EXPECT_TRUE(build_implicit_surface({{0, 0, 0}}, p).indices.empty());
    p.threshold = 0.3f;
    const ImplicitSurface one = build_implicit_surface({{0, 0, 0}}, p);
    const ImplicitSurface two = build_implicit_surface({{0, 0, 0}, {10, 0, 0}}, p);
    EXPECT_EQ(two.indices.size(), 2 * one.indices.size());
    expect_closed_and_consistent(two);
}

TEST(ImplicitSurface, SameBytesForEverySchedule) {
    std::vector<glm::vec3> pts;
    std::uint32_t h = 12345;
    for (int i = 0; i < 3000; ++i) {
        auto next = [&] {
            h = h * 1664525u + 1013904223u;
            return float(h >> 8) / float(1 << 24);
        };
        const float x = next(), y = next(), z = next();
        pts.push_back(glm::vec3(x, y * 0.7f, z) * 10.0f);
    }
    ImplicitSurfaceParams p;
    p.radius = 0.8f;
    p.threshold = 2.0f;
    const ImplicitSurface ref = build_implicit_surface(pts, p, Exec::reference());
    ASSERT_GT(ref.indices.size(), 1000u);
    expect_closed_and_consistent(ref, false);
    auto bytes = [](const ImplicitSurface& s) {
        return sha256_hex(s.positions.data(), s.positions.size() * sizeof(glm::vec3)) +
               sha256_hex(s.normals.data(), s.normals.size() * sizeof(glm::vec3)) +
               sha256_hex(s.indices.data(), s.indices.size() * sizeof(std::uint32_t));
    };
    for (int threads : {1, 2, 8}) EXPECT_EQ(bytes(build_implicit_surface(pts, p, Exec::fast(threads))), bytes(ref)) << threads;
}

TEST(ImplicitSurface, BadInputIsRefusedBeforeAllocating) {
    ImplicitSurfaceParams p;
    p.radius = 1.0f;
    p.threshold = 0.5f;
    // Two points 1e6 apart with r = 1: 1e18 grid nodes.
    try {
        build_implicit_surface({{0, 0, 0}, {1e6f, 1e6f, 1e6f}}, p);
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("limit"), std::string::npos) << e.what();
    }
    EXPECT_THROW(build_implicit_surface({}, p), Error);
    EXPECT_THROW(build_implicit_surface({{NAN, 0, 0}}, p), Error);
    p.radius = 0.0f;
    EXPECT_THROW(build_implicit_surface({{0, 0, 0}}, p), Error);
    p.radius = 1.0f;
    p.threshold = NAN;
    EXPECT_THROW(build_implicit_surface({{0, 0, 0}}, p), Error);
    p.threshold = 1.0f;
    p.cells_per_radius = 0;
    EXPECT_THROW(build_implicit_surface({{0, 0, 0}}, p), Error);
    // NaN points among good ones are skipped.
    p.cells_per_radius = 4;
    p.threshold = 0.25f;
    EXPECT_EQ(build_implicit_surface({{0, 0, 0}, {NAN, 1, 1}}, p).indices.size(),
              build_implicit_surface({{0, 0, 0}}, p).indices.size());
}

// Issue 47 item 5: the field's work is bounded before the grid is allocated. 400,000 points in a
// small cube at cells_per_radius 16 (35^3 support nodes each: 1.7e10 kernel evaluations, minutes of
// work) are refused at once, naming the budget; the grid itself would be small.
TEST(ImplicitSurface, WorkBeyondTheBudgetIsRefusedBeforeBuilding) {
    std::vector<glm::vec3> pts;
    for (int i = 0; i < 400000; ++i) pts.push_back({float(i % 73) * 0.01f, float(i % 89) * 0.01f, float(i % 97) * 0.01f});
    ImplicitSurfaceParams p;
    p.radius = 1.0f;
    p.threshold = 0.5f;
    p.cells_per_radius = 16;
    try {
        build_implicit_surface(pts, p);
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("over the budget"), std::string::npos) << e.what();
    }
    p.cells_per_radius = 1;  // 5^3 per point: within the budget
    EXPECT_FALSE(build_implicit_surface(pts, p).indices.empty());
}

// The surface is empty exactly when the field's maximum is not above T (what the threshold fit of
// the foliage abstraction relies on to build once instead of once per candidate).
TEST(ImplicitSurface, TheSurfaceIsEmptyExactlyWhenTheFieldMaximumIsNotAboveT) {
    const std::vector<glm::vec3> pts = {{0, 0, 0}, {0.3f, 0.1f, 0}, {0.2f, 0.5f, 0.1f}};
    ImplicitSurfaceParams p;
    p.radius = 1.0f;
    p.threshold = 0.1f;
    const float max = build_implicit_surface(pts, p).field_max;
    ASSERT_GT(max, 1.0f);
    EXPECT_LE(max, implicit_density(pts, 1.0f, {0.17f, 0.2f, 0.03f}) * 1.5f);
    p.threshold = max;
    EXPECT_TRUE(build_implicit_surface(pts, p).indices.empty());
    p.threshold = std::nextafter(max, 0.0f);
    EXPECT_FALSE(build_implicit_surface(pts, p).indices.empty());
}

}  // namespace
}  // namespace aq::raster
