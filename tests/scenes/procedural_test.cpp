// tests/scenes/procedural_test.cpp — mesh builders (closed, consistently oriented, watertight by
// construction), the swatches scene and the noise field.
#include "scenes/procedural.h"

#include <gtest/gtest.h>
#include <cstring>
#include <cmath>
#include <algorithm>
#include "core/hash.h"

#include <map>
#include <set>
#include <vector>

#include "scenes/noise.h"

namespace aq::scene {
namespace {

// Every directed edge (a, b) of a consistently oriented closed surface appears exactly once and
// its reverse (b, a) exactly once. Shared edges must use shared vertex indices or bit-identical
// positions; this checks by position so duplicated seam vertices count.
void expect_closed_and_oriented(const Primitive& p) {
    std::map<std::pair<std::array<float, 3>, std::array<float, 3>>, int> directed;
    auto key = [&](std::uint32_t i) { return std::array<float, 3>{p.positions[i].x, p.positions[i].y, p.positions[i].z}; };
    for (std::size_t t = 0; t < p.indices.size(); t += 3)
        for (int e = 0; e < 3; ++e) {
            const auto a = key(p.indices[t + std::size_t(e)]), b = key(p.indices[t + std::size_t((e + 1) % 3)]);
            if (a == b) continue;  // degenerate edge at a pole
            ++directed[{a, b}];
        }
    for (const auto& [edge, n] : directed) {
        EXPECT_EQ(n, 1) << "directed edge used " << n << " times";
        auto rev = directed.find({edge.second, edge.first});
        ASSERT_NE(rev, directed.end()) << "boundary edge: the surface is not closed";
    }
}

// Outward orientation: the sum over triangles of (centroid . area-normal) is positive for a
// closed surface around the origin (it is 3x the enclosed volume).
float signed_volume(const Primitive& p) {
    double v = 0.0;
    for (std::size_t t = 0; t < p.indices.size(); t += 3) {
        const glm::dvec3 a(p.positions[p.indices[t]]), b(p.positions[p.indices[t + 1]]), c(p.positions[p.indices[t + 2]]);
        v += glm::dot(a, glm::cross(b, c)) / 6.0;
    }
    return float(v);
}

void expect_valid(const Primitive& p) {
    ASSERT_EQ(p.indices.size() % 3, 0u);
    ASSERT_EQ(p.normals.size(), p.positions.size());
    ASSERT_EQ(p.uv0.size(), p.positions.size());
    for (std::uint32_t i : p.indices) ASSERT_LT(i, p.positions.size());
    for (const glm::vec3& n : p.normals) EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
}

TEST(Builders, GridCoversTheSquareOnce) {
    const Primitive g = make_grid(8, 2.0f);
    expect_valid(g);
    EXPECT_EQ(g.indices.size(), 8u * 8u * 6u);
    EXPECT_EQ(g.positions.size(), 81u);
    double area = 0.0;
    for (std::size_t t = 0; t < g.indices.size(); t += 3) {
        const glm::vec3 a = g.positions[g.indices[t]], b = g.positions[g.indices[t + 1]], c = g.positions[g.indices[t + 2]];
        const float z = glm::cross(b - a, c - a).z;
        EXPECT_GT(z, 0.0f);  // CCW seen from +Z
        area += 0.5 * z;
    }
    EXPECT_NEAR(area, 4.0, 1e-5);
    // Interior edges are shared by exactly two triangles, boundary edges by one.
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
    for (std::size_t t = 0; t < g.indices.size(); t += 3)
        for (int e = 0; e < 3; ++e) {
            std::uint32_t a = g.indices[t + std::size_t(e)], b = g.indices[t + std::size_t((e + 1) % 3)];
            ++edges[{std::min(a, b), std::max(a, b)}];
        }
    int boundary = 0;
    for (const auto& [e, n] : edges) {
        EXPECT_LE(n, 2);
        boundary += n == 1;
    }
    EXPECT_EQ(boundary, 4 * 8);
    EXPECT_THROW(make_grid(0), aq::Error);
}

TEST(Builders, FanSharesTheCentreAndCloses) {
    const Primitive f = make_fan(16, 1.0f);
    expect_valid(f);
    EXPECT_EQ(f.indices.size(), 16u * 3u);
    for (std::size_t t = 0; t < f.indices.size(); t += 3) {
        EXPECT_EQ(f.indices[t], 0u);
        const glm::vec3 a = f.positions[f.indices[t]], b = f.positions[f.indices[t + 1]], c = f.positions[f.indices[t + 2]];
        EXPECT_GT(glm::cross(b - a, c - a).z, 0.0f);
    }
    EXPECT_EQ(f.indices.back(), 1u);  // last triangle closes onto the first rim vertex
}

TEST(Builders, ClosedSolidsAreWatertightAndOutward) {
    const Primitive sphere = make_uv_sphere(24, 12, 1.0f);
    expect_valid(sphere);
    expect_closed_and_oriented(sphere);
    EXPECT_GT(signed_volume(sphere), 3.5f);  // 4/3 pi = 4.19, inscribed polyhedron a bit less
    EXPECT_LT(signed_volume(sphere), 4.19f);

    const Primitive box = make_box({1, 2, 3});
    expect_valid(box);
    expect_closed_and_oriented(box);
    EXPECT_NEAR(signed_volume(box), 48.0f, 1e-4f);

    const Primitive torus = make_torus(1.0f, 0.25f, 32, 16);
    expect_valid(torus);
    expect_closed_and_oriented(torus);
    EXPECT_GT(signed_volume(torus), 0.0f);

    const Primitive cyl = make_cylinder(0.5f, 2.0f, 20);
    expect_valid(cyl);
    EXPECT_GT(signed_volume(cyl), 0.0f);
    // The cylinder's caps use their own (flat-normal) vertices: closed by position.
    expect_closed_and_oriented(cyl);
}

TEST(Builders, VertexNormalsPointOutward) {
    for (const Primitive& p : {make_uv_sphere(16, 8), make_torus(1.0f, 0.3f, 16, 8)}) {
        for (std::size_t t = 0; t < p.indices.size(); t += 3) {
            const glm::vec3 a = p.positions[p.indices[t]], b = p.positions[p.indices[t + 1]], c = p.positions[p.indices[t + 2]];
            const glm::vec3 fn = glm::cross(b - a, c - a);
            if (glm::length(fn) < 1e-9f) continue;
            const glm::vec3 vn = p.normals[p.indices[t]] + p.normals[p.indices[t + 1]] + p.normals[p.indices[t + 2]];
            EXPECT_GT(glm::dot(fn, vn), 0.0f);
        }
    }
}

TEST(Swatches, DeterministicAndPaintedForEveryEffect) {
    const Scene a = make_procedural("swatches");
    const Scene b = make_procedural("swatches");
    ASSERT_EQ(a.meshes.size(), b.meshes.size());
    for (std::size_t m = 0; m < a.meshes.size(); ++m)
        for (std::size_t p = 0; p < a.meshes[m].primitives.size(); ++p)
            for (int t = 0; t < kNumControlTargets; ++t)
                EXPECT_EQ(a.meshes[m].primitives[p].control[std::size_t(t)], b.meshes[m].primitives[p].control[std::size_t(t)]);
    ASSERT_GE(a.instances.size(), 5u);
    ASSERT_EQ(a.cameras.size(), 1u);
    // Every control channel of the spec's table reaches a strong value (|v| >= 0.9) somewhere,
    // except the incline channels (substrate.g/b), which are painted by no MNPR effect.
    for (int t = 0; t < kNumControlTargets; ++t)
        for (int c = 0; c < 3; ++c) {
            if (t == kCtrlSubstrate && c > 0) continue;
            float hi = 0.0f, lo = 0.0f;
            for (const Mesh& m : a.meshes)
                for (const Primitive& p : m.primitives) {
                    ASSERT_EQ(p.control[std::size_t(t)].size(), p.positions.size());
                    for (const glm::vec4& v : p.control[std::size_t(t)]) {
                        hi = std::max(hi, v[c]);
                        lo = std::min(lo, v[c]);
                        ASSERT_LE(std::abs(v[c]), 1.0f);
                    }
                }
            EXPECT_GE(hi, 0.9f) << "target " << t << " channel " << c;
            // Signed channels are painted both ways (granulation/dry-brush, accumulate/dilute,
            // overlaps/gaps, edge intensity).
            if ((t == kCtrlPigment && c >= 1) || (t == kCtrlEdge && (c == 0 || c == 2))) {
                EXPECT_LE(lo, -0.9f) << t << "," << c;
            }
        }
    // Unique object IDs from 1.
    std::set<std::uint32_t> ids;
    for (const Instance& i : a.instances) ids.insert(i.object_id);
    EXPECT_EQ(ids.size(), a.instances.size());
    EXPECT_EQ(*ids.begin(), 1u);
    EXPECT_THROW(make_procedural("nope"), aq::Error);
}

// "procedural:tree" (LD06's test plant made by code): the same bytes every call, trunk and leaves
// separable by the foliage rule, about the height of the paper's Fig. 8 tree (23.8), leaves around
// the branch tips, every triangle and normal finite.
TEST(ProceduralTree, DeterministicWithTrunkAndFoliage) {
    const Scene a = make_procedural("tree"), b = make_procedural("tree");
    ASSERT_EQ(a.meshes.size(), 2u);
    for (std::size_t m = 0; m < a.meshes.size(); ++m) {
        const Primitive& pa = a.meshes[m].primitives[0];
        const Primitive& pb = b.meshes[m].primitives[0];
        EXPECT_EQ(pa.positions, pb.positions);
        EXPECT_EQ(pa.indices, pb.indices);
        for (const glm::vec3& n : pa.normals) EXPECT_NEAR(glm::length(n), 1.0f, 1e-4f);
        for (std::uint32_t i : pa.indices) ASSERT_LT(i, pa.positions.size());
    }
    std::size_t foliage = 0, trunk = 0;
    for (const Instance& inst : a.instances)
        for (const Primitive& p : a.meshes[std::size_t(inst.mesh)].primitives)
            (is_foliage(a, inst, p) ? foliage : trunk) += p.indices.size() / 3;
    EXPECT_EQ(foliage, 1080u * 4u);  // 1,080 leaves of two crossed quads
    EXPECT_EQ(trunk, 121u * 8u * 2u);  // 121 tubes of 8 sides
    const Bounds bb = a.world_bounds();
    EXPECT_GT(bb.max.y - bb.min.y, 15.0f);
    EXPECT_LT(bb.max.y - bb.min.y, 32.0f);
    ASSERT_EQ(a.cameras.size(), 1u);
    const glm::vec4 c = a.cameras[0].view * glm::vec4(0.5f * (bb.min + bb.max), 1.0f);
    EXPECT_LT(c.z, -a.cameras[0].znear) << "the camera looks at the tree";
}

TEST(Noise, DeterministicInRangeAndSeeded) {
    float lo = 1.0f, hi = -1.0f;
    int differs = 0;
    for (int i = 0; i < 20000; ++i) {
        const glm::vec3 p(float(i % 37) * 0.173f - 3.0f, float(i / 37 % 29) * 0.219f, float(i / 1073) * 0.31f - 1.0f);
        const float v = value_noise(p, 7u);
        ASSERT_EQ(v, value_noise(p, 7u));
        ASSERT_GE(v, -1.0f);
        ASSERT_LE(v, 1.0f);
        lo = std::min(lo, v);
        hi = std::max(hi, v);
        differs += value_noise(p, 8u) != v;
    }
    EXPECT_LT(lo, -0.6f);  // uses most of the range
    EXPECT_GT(hi, 0.6f);
    EXPECT_GT(differs, 19000);  // the seed changes the field
    // Continuous: a tiny step changes the value a little.
    EXPECT_NEAR(value_noise({0.5f, 0.5f, 0.5f}, 1u), value_noise({0.5001f, 0.5f, 0.5f}, 1u), 1e-3f);
    // Non-finite and huge inputs are safe.
    EXPECT_EQ(value_noise({NAN, 0, 0}, 1u), 0.0f);
    EXPECT_EQ(value_noise({INFINITY, 0, 0}, 1u), 0.0f);
    const float big = value_noise({3e9f, -3e9f, 1e30f}, 1u);
    EXPECT_GE(big, -1.0f);
    EXPECT_LE(big, 1.0f);
}

// value_noise equals its plain definition: each of the cell's eight corners hashed on its own,
// hash32 chained over the seed and the corner's x, y, z (the shared-prefix form in noise.cpp must
// give these values bit for bit; the control goldens depend on them).
TEST(Noise, EqualsThePlainChainedHashDefinition) {
    auto lattice = [](std::int32_t x, std::int32_t y, std::int32_t z, std::uint32_t seed) {
        std::uint32_t h = hash32(seed ^ 0x9e3779b9U);
        h = hash32(h ^ std::uint32_t(x));
        h = hash32(h ^ std::uint32_t(y));
        h = hash32(h ^ std::uint32_t(z));
        return float(h >> 8) * (2.0f / 16777215.0f) - 1.0f;
    };
    auto fade = [](float t) { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); };
    auto lerp = [](float a, float b, float t) { return a + (b - a) * t; };
    auto plain = [&](glm::vec3 p, std::uint32_t seed) {
        p = glm::vec3(std::fmod(p.x, 1048576.0f), std::fmod(p.y, 1048576.0f), std::fmod(p.z, 1048576.0f));
        const glm::vec3 f = glm::floor(p);
        const std::int32_t x = std::int32_t(f.x), y = std::int32_t(f.y), z = std::int32_t(f.z);
        const float tx = fade(std::clamp(p.x - f.x, 0.0f, 1.0f)), ty = fade(std::clamp(p.y - f.y, 0.0f, 1.0f)),
                    tz = fade(std::clamp(p.z - f.z, 0.0f, 1.0f));
        const float c00 = lerp(lattice(x, y, z, seed), lattice(x + 1, y, z, seed), tx);
        const float c10 = lerp(lattice(x, y + 1, z, seed), lattice(x + 1, y + 1, z, seed), tx);
        const float c01 = lerp(lattice(x, y, z + 1, seed), lattice(x + 1, y, z + 1, seed), tx);
        const float c11 = lerp(lattice(x, y + 1, z + 1, seed), lattice(x + 1, y + 1, z + 1, seed), tx);
        return std::clamp(lerp(lerp(c00, c10, ty), lerp(c01, c11, ty), tz), -1.0f, 1.0f);
    };
    for (int i = 0; i < 20000; ++i) {
        const glm::vec3 p(float(i % 41) * 0.377f - 7.0f, float(i / 41 % 23) * -0.611f + 2.0f, float(i / 943) * 0.53f - 4.0f);
        for (std::uint32_t seed : {0u, 101u, 0xffffffffu}) {
            const float a = value_noise(p, seed), b = plain(p, seed);
            ASSERT_EQ(std::memcmp(&a, &b, sizeof a), 0) << "at " << p.x << "," << p.y << "," << p.z << " seed " << seed;
        }
    }
}

TEST(Noise, FieldAmplitudeOffsetOctaves) {
    NoiseField f;
    f.frequency = 2.0f;
    f.amplitude = 0.25f;
    f.offset = 0.5f;
    f.octaves = 4;
    f.seed = 3;
    for (int i = 0; i < 5000; ++i) {
        const glm::vec3 p(float(i) * 0.0137f, float(i % 11) * 0.1f, 0.3f);
        const float v = noise_field(f, p);
        ASSERT_GE(v, 0.25f);
        ASSERT_LE(v, 0.75f);
        ASSERT_EQ(v, noise_field(f, p));
    }
}

// noise_field_n (eight vertices per vector) gives noise_field's bits for every vertex: lattice
// cells on both sides of zero, integer and half-integer coordinates (floor's exact cases), -0,
// positions whose later octaves leave the folded range (2^20 cells), NaN and infinities among
// ordinary lanes, counts that leave a scalar tail, a scale, and every octave count.
TEST(Noise, EightAtATimeGivesThePlainFieldBitForBit) {
    std::vector<glm::vec3> p;
    std::uint32_t s = 12345u;
    auto rnd = [&](float lo, float hi) {
        s = hash32(s);
        return lo + (hi - lo) * float(s >> 8) * (1.0f / 16777216.0f);
    };
    for (int i = 0; i < 3000; ++i) p.emplace_back(rnd(-9, 9), rnd(-9, 9), rnd(-9, 9));
    for (int i = -12; i <= 12; ++i) {
        const float h = 0.5f * float(i);
        p.emplace_back(h, -h, float(i));
        p.emplace_back(std::nextafter(h, -100.0f), std::nextafter(h, 100.0f), -0.0f);
    }
    for (int i = 0; i < 40; ++i) p.emplace_back(rnd(-3e5f, 3e5f), rnd(-1, 1), rnd(-1e6f, 1e6f));
    const float special[] = {NAN, INFINITY, -INFINITY, 1048576.0f, -1048576.0f, 3e9f, 1e30f};
    for (float v : special)
        for (int k = 0; k < 3; ++k) {
            glm::vec3 q(rnd(-2, 2), rnd(-2, 2), rnd(-2, 2));
            q[k] = v;
            p.insert(p.begin() + std::ptrdiff_t(s % p.size()), q);
        }
    for (int octaves : {0, 1, 2, 3, 5, 8, 9})
        for (float scale : {1.0f, 0.0173f, 37.0f}) {
            NoiseField f;
            f.frequency = 2.7f;
            f.amplitude = 0.8f;
            f.offset = -0.1f;
            f.seed = std::uint32_t(101 + octaves);
            f.octaves = octaves;
            for (std::size_t n : {p.size(), std::size_t(13), std::size_t(8), std::size_t(5)}) {
                std::vector<float> out(n + 1, 42.0f);
                noise_field_n(f, p.data(), n, scale, out.data());
                for (std::size_t i = 0; i < n; ++i) {
                    const float want = noise_field(f, p[i] * scale);
                    ASSERT_EQ(std::memcmp(&out[i], &want, sizeof want), 0)
                        << "vertex " << i << " at " << p[i].x << "," << p[i].y << "," << p[i].z << " octaves " << octaves
                        << " scale " << scale << ": " << out[i] << " vs " << want;
                }
                EXPECT_EQ(out[n], 42.0f) << "writes only n values";
            }
        }
}

}  // namespace
// The generated plant family (issue 46 item 9): every kind builds finite geometry with foliage by
// the default rule; kind broadleaf with default proportions is procedural:tree itself; the seed
// changes the plant and the same query gives the same bytes; proportions act (more leaves, taller);
// malformed queries are refused with the parameter's name.
TEST(ProceduralTree, FamilyOfPlants) {
    auto foliage_tris = [](const Scene& s) {
        std::size_t n = 0;
        for (const Instance& inst : s.instances)
            for (const Primitive& p : s.meshes[std::size_t(inst.mesh)].primitives)
                if (is_foliage(s, inst, p)) n += p.indices.size() / 3;
        return n;
    };
    const Scene base = make_procedural("tree");
    const Scene same = make_procedural("tree?kind=broadleaf&seed=0");
    ASSERT_EQ(base.meshes.size(), same.meshes.size());
    for (std::size_t m = 0; m < base.meshes.size(); ++m)
        EXPECT_EQ(base.meshes[m].primitives[0].positions, same.meshes[m].primitives[0].positions);
    for (const char* kind : {"broadleaf", "light", "conifer", "shrub", "grass"}) {
        const std::string q = std::string("tree?kind=") + kind + "&seed=5";
        const Scene a = make_procedural(q), b = make_procedural(q);
        const Scene c = make_procedural(std::string("tree?kind=") + kind + "&seed=6");
        EXPECT_EQ(a.source, "procedural:" + q);
        ASSERT_FALSE(a.meshes.empty()) << kind;
        EXPECT_EQ(a.meshes.back().primitives[0].positions, b.meshes.back().primitives[0].positions) << kind;
        EXPECT_NE(a.meshes.back().primitives[0].positions, c.meshes.back().primitives[0].positions) << kind << ": seed ignored";
        EXPECT_GT(foliage_tris(a), 100u) << kind;
        for (const Mesh& m : a.meshes)
            for (const glm::vec3& v : m.primitives[0].positions) ASSERT_TRUE(std::isfinite(v.x + v.y + v.z)) << kind;
        const Scene more = make_procedural(q + "&leaves=2");
        EXPECT_GT(foliage_tris(more), foliage_tris(a)) << kind;
        const Scene tall = make_procedural(q + "&height=2");
        EXPECT_GT(tall.world_bounds().max.y, 1.5f * a.world_bounds().max.y) << kind;
    }
    EXPECT_EQ(make_procedural("tree?kind=grass").meshes.size(), 1u) << "grass is foliage only";
    for (const char* bad : {"tree?kind=palm", "tree?seed=-1", "tree?seed=1.5", "tree?leaves=0", "tree?height=abc",
                            "tree?colour=red", "tree?kind"})
        EXPECT_THROW(make_procedural(bad), aq::Error) << bad;
}

}  // namespace aq::scene
