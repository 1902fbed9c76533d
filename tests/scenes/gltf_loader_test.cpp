// tests/scenes/gltf_loader_test.cpp — glTF loading of the shared real models and conformance cases.
#include "scenes/gltf_loader.h"

#include <gtest/gtest.h>

#include "core/color.h"

#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <set>

#include "tests/test_support.h"

namespace aq::scene {
namespace {

using aq::test::asset;

Scene load(const std::string& rel, std::vector<std::string>* w = nullptr) { return load_gltf(asset(rel), w); }

void expect_valid(const Scene& s) {
    for (const Mesh& m : s.meshes)
        for (const Primitive& p : m.primitives) {
            ASSERT_EQ(p.indices.size() % 3, 0u);
            ASSERT_EQ(p.normals.size(), p.positions.size());
            for (std::uint32_t i : p.indices) ASSERT_LT(i, p.positions.size());
            if (!p.uv0.empty()) { ASSERT_EQ(p.uv0.size(), p.positions.size()); }
            if (!p.colors.empty()) { ASSERT_EQ(p.colors.size(), p.positions.size()); }
            if (!p.tangents.empty()) { ASSERT_EQ(p.tangents.size(), p.positions.size()); }
            ASSERT_GE(p.material, 0);
            ASSERT_LT(p.material, int(s.materials.size()));
        }
    for (const Instance& i : s.instances) {
        ASSERT_GE(i.mesh, 0);
        ASSERT_LT(i.mesh, int(s.meshes.size()));
        ASSERT_GE(i.object_id, 1u);
    }
}

struct ModelCase {
    const char* path;
    std::size_t triangles;
};

void PrintTo(const ModelCase& c, std::ostream* os) { *os << c.path << " (" << c.triangles << " triangles)"; }

class RealModels : public ::testing::TestWithParam<ModelCase> {};

TEST_P(RealModels, LoadWithExpectedTriangleCount) {
    const Scene s = load(GetParam().path);
    EXPECT_EQ(s.triangle_count(), GetParam().triangles);
    expect_valid(s);
    EXPECT_TRUE(s.world_bounds().valid);
}

INSTANTIATE_TEST_SUITE_P(
    Assets, RealModels,
    ::testing::Values(ModelCase{"gltf/Triangle/glTF/Triangle.gltf", 1}, ModelCase{"gltf/Triangle/glTF-Embedded/Triangle.gltf", 1},
                      ModelCase{"gltf/Box/glTF-Embedded/Box.gltf", 12}, ModelCase{"gltf/BoxTextured/BoxTextured.gltf", 12},
                      ModelCase{"gltf/BoxVertexColors_CC0/glTF-Embedded/BoxVertexColors.gltf", 12},
                      ModelCase{"gltf/BoxVertexColors_legacy/glTF/BoxVertexColors.gltf", 12},
                      ModelCase{"gltf/BoxVertexColors_legacy/glTF-Binary/BoxVertexColors.glb", 12},
                      ModelCase{"gltf/BoxVertexColors_legacy/glTF-Embedded/BoxVertexColors.gltf", 12},
                      ModelCase{"gltf/Cube/glTF/Cube.gltf", 12}, ModelCase{"gltf/Avocado/glTF/Avocado.gltf", 682},
                      ModelCase{"gltf/Fox/glTF/Fox.gltf", 576}, ModelCase{"gltf/OrientationTest/glTF/OrientationTest.gltf", 524},
                      ModelCase{"gltf/OrientationTest/glTF-Binary/OrientationTest.glb", 524},
                      ModelCase{"gltf/OrientationTest/glTF-Embedded/OrientationTest.gltf", 524},
                      ModelCase{"gltf/Suzanne/glTF/Suzanne.gltf", 3936}, ModelCase{"gltf/WaterBottle/glTF/WaterBottle.gltf", 4510},
                      ModelCase{"meshes/stanford_dragon/dragon_202k.glb", 202520}),
    [](const ::testing::TestParamInfo<ModelCase>& info) {
        // "gltf/Box/glTF-Embedded/Box.gltf" -> "Box_glTF_Embedded_Box_gltf" (unique and readable)
        std::string s = info.param.path;
        if (s.rfind("gltf/", 0) == 0) s = s.substr(5);
        if (s.rfind("meshes/", 0) == 0) s = s.substr(7);
        for (char& c : s)
            if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
        return s;
    });

}  // namespace
}  // namespace aq::scene

// ---------------------------------------------------------------------------------------------
#include <filesystem>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "core/io.h"
#include "tests/scenes/gltf_builder.h"

namespace aq::scene {
namespace {

using aq::test::GltfBuilder;
using aq::test::kFloat;
using aq::test::kUByte;
using aq::test::kUInt;
using aq::test::kUShort;

std::string out_path(const std::string& name) {
    const std::string d = aq::test::output_dir() + "/scenes";
    std::filesystem::create_directories(d);
    return d + "/" + name;
}

bool contains(const std::vector<std::string>& v, const std::string& needle) {
    for (const auto& s : v)
        if (s.find(needle) != std::string::npos) return true;
    return false;
}

const Primitive& only_primitive(const Scene& s) {
    EXPECT_EQ(s.meshes.size(), 1u);
    EXPECT_EQ(s.meshes.at(0).primitives.size(), 1u);
    return s.meshes.at(0).primitives.at(0);
}

// Signed area in XY of triangle t (all PrimitiveMode models lie in the z = 0 plane).
float signed_area_xy(const Primitive& p, std::size_t t) {
    const glm::vec3 a = p.positions[p.indices[3 * t]], b = p.positions[p.indices[3 * t + 1]],
                    c = p.positions[p.indices[3 * t + 2]];
    return 0.5f * ((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y));
}

// --- primitive modes (glTF Asset Generator conformance files) ---------------------------------

TEST(PrimitiveMode, StripsAndFansExpandToTriangleListsWithConsistentWinding) {
    for (const char* f : {"04", "05", "06", "11", "12", "13", "14", "15"}) {
        SCOPED_TRACE(f);
        const Scene s = load(std::string("conformance/Mesh_PrimitiveMode/Mesh_PrimitiveMode_") + f + ".gltf");
        const Primitive& p = only_primitive(s);
        ASSERT_EQ(p.indices.size(), 6u);  // every case draws the same unit square as two triangles
        float total = 0.0f;
        for (std::size_t t = 0; t < 2; ++t) {
            const float a = signed_area_xy(p, t);
            EXPECT_GT(a, 0.0f) << "triangle " << t << " is clockwise (front faces must stay CCW)";
            total += a;
        }
        EXPECT_NEAR(total, 1.0f, 1e-6f);  // the two triangles tile the 1x1 square, no overlap
        for (const glm::vec3& n : p.normals) EXPECT_NEAR(n.z, 1.0f, 1e-6f);  // computed: no NORMAL in the files
    }
}

TEST(PrimitiveMode, IndexedStripAndFanFollowTheSpecOrder) {
    // 11: strip [0,3,1,2] -> (0,3,1), (3,1,2) with the odd triangle's first two swapped: (1,3,2).
    const Scene strip = load("conformance/Mesh_PrimitiveMode/Mesh_PrimitiveMode_11.gltf");
    EXPECT_EQ(only_primitive(strip).indices, (std::vector<std::uint32_t>{0, 3, 1, 1, 3, 2}));
    // 12: fan [0,3,2,1] -> (0,3,2), (0,2,1).
    const Scene fan = load("conformance/Mesh_PrimitiveMode/Mesh_PrimitiveMode_12.gltf");
    EXPECT_EQ(only_primitive(fan).indices, (std::vector<std::uint32_t>{0, 3, 2, 0, 2, 1}));
    // 13-15: the same triangle list with uint, ubyte and ushort indices.
    for (const char* f : {"13", "14", "15"}) {
        const Scene s = load(std::string("conformance/Mesh_PrimitiveMode/Mesh_PrimitiveMode_") + f + ".gltf");
        EXPECT_EQ(only_primitive(s).indices, (std::vector<std::uint32_t>{1, 0, 3, 1, 3, 2})) << f;
    }
}

TEST(PrimitiveMode, PointsAndLinesAreSkippedWithAWarning) {
    for (const char* f : {"00", "01", "02", "03", "07", "08", "09", "10"}) {
        std::vector<std::string> w;
        const Scene s = load(std::string("conformance/Mesh_PrimitiveMode/Mesh_PrimitiveMode_") + f + ".gltf", &w);
        EXPECT_EQ(s.triangle_count(), 0u) << f;
        EXPECT_TRUE(contains(w, "skipped")) << f;
        EXPECT_TRUE(contains(s.warnings, "skipped")) << f;
    }
}

TEST(TriangleList, StripAndFanExpansion) {
    EXPECT_EQ(to_triangle_list(5, {0, 1, 2, 3, 4}), (std::vector<std::uint32_t>{0, 1, 2, 2, 1, 3, 2, 3, 4}));
    EXPECT_EQ(to_triangle_list(6, {0, 1, 2, 3, 4}), (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3, 0, 3, 4}));
    EXPECT_TRUE(to_triangle_list(5, {0, 1}).empty());
    EXPECT_TRUE(to_triangle_list(6, {}).empty());
    EXPECT_EQ(to_triangle_list(4, {0, 1, 2, 3}), (std::vector<std::uint32_t>{0, 1, 2}));  // trailing index dropped
    EXPECT_THROW(to_triangle_list(1, {0, 1}), aq::Error);
}

// --- vertex colours -----------------------------------------------------------------------------

TEST(VertexColors, CC0BoxColorEqualsPosition) {
    // README: "the color of each vertex is given by the RGB colors that are defined by the vertex
    // coordinates" (unit cube [0,1]^3).
    const Scene s = load("gltf/BoxVertexColors_CC0/glTF-Embedded/BoxVertexColors.gltf");
    const Primitive& p = only_primitive(s);
    ASSERT_EQ(p.colors.size(), p.positions.size());
    for (std::size_t i = 0; i < p.colors.size(); ++i) {
        EXPECT_NEAR(p.colors[i].r, p.positions[i].x, 1e-6f);
        EXPECT_NEAR(p.colors[i].g, p.positions[i].y, 1e-6f);
        EXPECT_NEAR(p.colors[i].b, p.positions[i].z, 1e-6f);
        EXPECT_EQ(p.colors[i].a, 1.0f);  // VEC3 -> alpha 1
    }
}

TEST(VertexColors, LegacyBoxIsIdenticalInAllThreeContainers) {
    const Scene a = load("gltf/BoxVertexColors_legacy/glTF/BoxVertexColors.gltf");
    const Scene b = load("gltf/BoxVertexColors_legacy/glTF-Binary/BoxVertexColors.glb");
    const Scene c = load("gltf/BoxVertexColors_legacy/glTF-Embedded/BoxVertexColors.gltf");
    const Primitive& pa = only_primitive(a);
    ASSERT_EQ(pa.colors.size(), 24u);
    ASSERT_EQ(pa.uv0.size(), 24u);
    EXPECT_EQ(pa.colors, only_primitive(b).colors);
    EXPECT_EQ(pa.colors, only_primitive(c).colors);
    EXPECT_EQ(pa.positions, only_primitive(b).positions);
    for (const glm::vec4& col : pa.colors)
        for (int k = 0; k < 4; ++k) {
            EXPECT_GE(col[k], 0.0f);
            EXPECT_LE(col[k], 1.0f);
        }
    ASSERT_EQ(a.materials.size(), 1u);
    EXPECT_EQ(a.materials[0].name, "Default");
    EXPECT_NEAR(a.materials[0].base_color.r, 0.8f, 1e-6f);
}

// The CC0 box re-encoded with COLOR_0 in every allowed component type and width.
struct ColorEncoding {
    int component_type;
    int components;  // 3 or 4
};

void PrintTo(const ColorEncoding& e, std::ostream* os) { *os << "componentType " << e.component_type << " x" << e.components; }

class ColorComponentTypes : public ::testing::TestWithParam<ColorEncoding> {};

TEST_P(ColorComponentTypes, DecodeToNormalisedValues) {
    const ColorEncoding enc = GetParam();
    const Scene ref = load("gltf/BoxVertexColors_CC0/glTF-Embedded/BoxVertexColors.gltf");
    const Primitive& rp = only_primitive(ref);
    const std::size_t n = rp.positions.size();
    GltfBuilder b;
    std::vector<float> pos;
    for (const auto& v : rp.positions) pos.insert(pos.end(), {v.x, v.y, v.z});
    const int pa = b.add(pos, kFloat, "VEC3", n);
    // Colour = position, alpha = 0.25 (VEC4), encoded in the requested type.
    int ca = -1;
    const std::string type = enc.components == 4 ? "VEC4" : "VEC3";
    std::vector<float> expect;
    for (const auto& v : rp.positions) {
        expect.insert(expect.end(), {v.x, v.y, v.z});
        if (enc.components == 4) expect.push_back(0.25f);
    }
    if (enc.component_type == kFloat) {
        ca = b.add(expect, kFloat, type, n);
    } else if (enc.component_type == kUByte) {
        std::vector<std::uint8_t> q;
        for (float f : expect) q.push_back(std::uint8_t(std::lround(f * 255.0f)));
        while (q.size() % 4) q.push_back(0);
        // glTF aligns each ubyte VEC3 element to 4 bytes: use a stride of 4 for VEC3.
        if (enc.components == 3) {
            std::vector<std::uint8_t> s;
            for (std::size_t i = 0; i < n; ++i) s.insert(s.end(), {q[3 * i], q[3 * i + 1], q[3 * i + 2], 0});
            ca = b.add_accessor(b.add_view(s.data(), s.size(), 4), kUByte, n, type, true);
        } else {
            ca = b.add(q, kUByte, type, n, true);
        }
    } else {
        std::vector<std::uint16_t> q;
        for (float f : expect) q.push_back(std::uint16_t(std::lround(f * 65535.0f)));
        if (enc.components == 3) {
            std::vector<std::uint16_t> s;
            for (std::size_t i = 0; i < n; ++i) s.insert(s.end(), {q[3 * i], q[3 * i + 1], q[3 * i + 2], 0});
            ca = b.add_accessor(b.add_view(s.data(), s.size() * 2, 8), kUShort, n, type, true);
        } else {
            ca = b.add(q, kUShort, type, n, true);
        }
    }
    b.single_primitive({{"attributes", {{"POSITION", pa}, {"COLOR_0", ca}}}});
    const std::string path = out_path("color_" + std::to_string(enc.component_type) + "_" + std::to_string(enc.components) + ".gltf");
    const Scene s = load_gltf(b.write_gltf(path));
    const Primitive& p = only_primitive(s);
    ASSERT_EQ(p.colors.size(), n);
    const float tol = enc.component_type == kFloat ? 0.0f : enc.component_type == kUByte ? 0.5f / 255.0f : 0.5f / 65535.0f;
    for (std::size_t i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(p.colors[i][k], rp.positions[i][k], tol + 1e-7f);
        EXPECT_NEAR(p.colors[i].a, enc.components == 4 ? 0.25f : 1.0f, tol + 1e-7f);
    }
}

INSTANTIATE_TEST_SUITE_P(AllTypes, ColorComponentTypes,
                         ::testing::Values(ColorEncoding{kFloat, 3}, ColorEncoding{kFloat, 4}, ColorEncoding{kUByte, 3},
                                           ColorEncoding{kUByte, 4}, ColorEncoding{kUShort, 3}, ColorEncoding{kUShort, 4}),
                         [](const ::testing::TestParamInfo<ColorEncoding>& info) {
                             const int ct = info.param.component_type;
                             return std::string(ct == kFloat ? "float" : ct == kUByte ? "ubyte" : "ushort") + "_vec" +
                                    std::to_string(info.param.components);
                         });

// --- node transforms ---------------------------------------------------------------------------

TEST(NodeTransforms, OrientationTestMatchesTheFileInAllContainers) {
    const std::string path = asset("gltf/OrientationTest/glTF/OrientationTest.gltf");
    const Scene s = load_gltf(path);
    ASSERT_EQ(s.instances.size(), 13u);
    const nlohmann::json j = nlohmann::json::parse(aq::test::read_bytes(path));
    std::set<std::uint32_t> ids;
    for (const Instance& inst : s.instances) {
        ids.insert(inst.object_id);
        // Find the node by name and compare the translation column with the file.
        const nlohmann::json* node = nullptr;
        for (const auto& n : j["nodes"])
            if (n["name"] == inst.name) node = &n;
        ASSERT_NE(node, nullptr) << inst.name;
        glm::vec3 t(0.0f);
        if (node->contains("translation")) t = {(*node)["translation"][0], (*node)["translation"][1], (*node)["translation"][2]};
        if (node->contains("matrix")) t = {(*node)["matrix"][12], (*node)["matrix"][13], (*node)["matrix"][14]};
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(inst.world[3][k], t[k], 1e-5f) << inst.name;
        // Every transform in this file is a rotation (plus translation): orthonormal, det +1.
        const glm::mat3 r(inst.world);
        EXPECT_NEAR(glm::determinant(r), 1.0f, 1e-5f) << inst.name;
        if (inst.name == "ArrowX1") {
            // Rotation about +X: the X axis is kept.
            EXPECT_NEAR(inst.world[0][0], 1.0f, 1e-5f);
            EXPECT_NEAR(inst.world[1][0], 0.0f, 1e-5f);
            EXPECT_NEAR(inst.world[2][0], 0.0f, 1e-5f);
            // q = (-0.3007, 0, 0, 0.9537): angle -35 degrees; Y goes to (0, cos, sin(-35)).
            EXPECT_NEAR(inst.world[1][1], std::cos(glm::radians(35.0f)), 1e-4f);
            EXPECT_NEAR(inst.world[1][2], -std::sin(glm::radians(35.0f)), 1e-4f);
        }
    }
    EXPECT_EQ(ids.size(), 13u);  // unique object IDs
    EXPECT_EQ(*ids.begin(), 1u);
    for (const char* other : {"gltf/OrientationTest/glTF-Binary/OrientationTest.glb",
                              "gltf/OrientationTest/glTF-Embedded/OrientationTest.gltf"}) {
        const Scene o = load(other);
        ASSERT_EQ(o.instances.size(), s.instances.size());
        for (std::size_t i = 0; i < s.instances.size(); ++i) {
            EXPECT_EQ(o.instances[i].name, s.instances[i].name);
            EXPECT_EQ(o.instances[i].world, s.instances[i].world);
        }
        EXPECT_EQ(o.materials.size(), 7u);
    }
}

TEST(NodeTransforms, HierarchyComposesParentTimesChild) {
    GltfBuilder b;
    const auto pos = aq::test::quad_positions();
    const int pa = b.add(pos, kFloat, "VEC3", 4);
    const auto idx = aq::test::quad_indices();
    const int ia = b.add(idx, kUShort, "SCALAR", 6);
    b.single_primitive({{"attributes", {{"POSITION", pa}}}, {"indices", ia}});
    // root: translate (1,2,3) and rotate 90 degrees about Z; child: matrix = uniform scale 2.
    const float h = std::sqrt(0.5f);
    b.j["nodes"] = nlohmann::json::array({{{"translation", {1, 2, 3}}, {"rotation", {0, 0, h, h}}, {"children", {1}}},
                                          {{"matrix", {2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1}}, {"mesh", 0}}});
    const Scene s = load_gltf(b.write_gltf(out_path("hierarchy.gltf")));
    ASSERT_EQ(s.instances.size(), 1u);
    // Vertex (1,0,0): scale -> (2,0,0), rotate 90 about Z -> (0,2,0), translate -> (1,4,3).
    const glm::vec4 w = s.instances[0].world * glm::vec4(1, 0, 0, 1);
    EXPECT_NEAR(w.x, 1.0f, 1e-6f);
    EXPECT_NEAR(w.y, 4.0f, 1e-6f);
    EXPECT_NEAR(w.z, 3.0f, 1e-6f);
    // Vertex (0,1,0) -> (0,2,0) -> (-2,0,0) -> (-1,2,3).
    const glm::vec4 v = s.instances[0].world * glm::vec4(0, 1, 0, 1);
    EXPECT_NEAR(v.x, -1.0f, 1e-6f);
    EXPECT_NEAR(v.y, 2.0f, 1e-6f);
    EXPECT_NEAR(v.z, 3.0f, 1e-6f);
}

TEST(NodeTransforms, NoSceneMeansEveryRootNode) {
    GltfBuilder b;
    const int pa = b.add(aq::test::quad_positions(), kFloat, "VEC3", 4);
    b.single_primitive({{"attributes", {{"POSITION", pa}}}, {"mode", 6}});
    b.j.erase("scenes");
    b.j.erase("scene");
    b.j["nodes"] = nlohmann::json::array({{{"mesh", 0}, {"children", {2}}}, {{"mesh", 0}}, {{"mesh", 0}}});
    const Scene s = load_gltf(b.write_gltf(out_path("noscene.gltf")));
    EXPECT_EQ(s.instances.size(), 3u);  // roots 0 and 1, plus child 2 of 0
    EXPECT_EQ(s.triangle_count(), 6u);
}

// --- normals and tangents -----------------------------------------------------------------------

TEST(Normals, OctahedronVertexNormalsPointAlongTheAxes) {
    const std::vector<glm::vec3> p = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    // 8 faces, CCW seen from outside.
    const std::vector<std::uint32_t> idx = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
    const auto n = compute_normals(p, idx);
    for (std::size_t i = 0; i < p.size(); ++i)
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(n[i][k], p[i][k], 1e-6f) << "vertex " << i;
}

TEST(Normals, AreaWeighted) {
    // Vertex 0 is shared by a triangle of area 2 in the XY plane (normal +Z) and one of area 1/2
    // in the XZ plane (normal -Y): weights 2 : 1/2 -> normalize(0, -1, 4).
    const std::vector<glm::vec3> p = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {1, 0, 0}, {0, 0, 1}};
    const std::vector<std::uint32_t> idx = {0, 1, 2, 0, 3, 4};
    const auto n = compute_normals(p, idx);
    const glm::vec3 e = glm::normalize(glm::vec3(0, -1, 4));
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(n[0][k], e[k], 1e-6f);
    EXPECT_NEAR(n[1].z, 1.0f, 1e-6f);
    EXPECT_NEAR(n[3].y, -1.0f, 1e-6f);
}

TEST(Normals, ComputedWhenTheFileHasNone) {
    GltfBuilder b;
    const int pa = b.add(aq::test::quad_positions(), kFloat, "VEC3", 4);
    const int ia = b.add(aq::test::quad_indices(), kUShort, "SCALAR", 6);
    b.single_primitive({{"attributes", {{"POSITION", pa}}}, {"indices", ia}});
    const Scene s = load_gltf(b.write_gltf(out_path("nonormals.gltf")));
    for (const glm::vec3& n : only_primitive(s).normals) {
        EXPECT_NEAR(n.z, 1.0f, 1e-6f);
        EXPECT_NEAR(glm::length(n), 1.0f, 1e-6f);
    }
}

TEST(Tangents, FollowTheUDirection) {
    const std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    const std::vector<glm::vec3> n(4, glm::vec3(0, 0, 1));
    const std::vector<glm::vec2> uv = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    const std::vector<std::uint32_t> idx = {0, 1, 2, 0, 2, 3};
    for (const glm::vec4& t : compute_tangents(p, n, uv, idx)) {
        EXPECT_NEAR(t.x, 1.0f, 1e-6f);
        EXPECT_NEAR(t.w, 1.0f, 0.0f);
    }
    // Mirrored U: the tangent flips and the handedness becomes -1.
    const std::vector<glm::vec2> mirrored = {{1, 0}, {0, 0}, {0, 1}, {1, 1}};
    for (const glm::vec4& t : compute_tangents(p, n, mirrored, idx)) {
        EXPECT_NEAR(t.x, -1.0f, 1e-6f);
        EXPECT_EQ(t.w, -1.0f);
    }
}

// --- textures ----------------------------------------------------------------------------------

// Quad with uv, a material with base colour and normal textures named by URI.
GltfBuilder textured_quad(const std::string& base_uri, const std::string& normal_uri) {
    GltfBuilder b;
    const int pa = b.add(aq::test::quad_positions(), kFloat, "VEC3", 4);
    const std::vector<float> uv = {0, 0, 1, 0, 1, 1, 0, 1};
    const int ta = b.add(uv, kFloat, "VEC2", 4);
    const int ia = b.add(aq::test::quad_indices(), kUShort, "SCALAR", 6);
    b.single_primitive({{"attributes", {{"POSITION", pa}, {"TEXCOORD_0", ta}}}, {"indices", ia}, {"material", 0}});
    b.j["images"] = nlohmann::json::array({{{"uri", base_uri}}, {{"uri", normal_uri}}});
    b.j["samplers"] = nlohmann::json::array({{{"wrapS", 33071}, {"wrapT", 33648}, {"magFilter", 9728}, {"minFilter", 9987}}});
    b.j["textures"] = nlohmann::json::array({{{"source", 0}, {"sampler", 0}}, {{"source", 1}}});
    b.j["materials"] = nlohmann::json::array(
        {{{"name", "tex"},
          {"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.25, 1.0, 1.0}}, {"baseColorTexture", {{"index", 0}}}}},
          {"normalTexture", {{"index", 1}, {"scale", 0.5}}},
          {"alphaMode", "MASK"},
          {"alphaCutoff", 0.3},
          {"doubleSided", true},
          {"extras", {{"watercolor", {{"dilute", 0.6}, {"control", {{"edge", {0.5, 0.1, -0.2}}}}}}}}}});
    return b;
}

TEST(Textures, LoadedWithSamplerAndMaterialFields) {
    ImageF img(4, 2, 3);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 4; ++x) {
            img.at(x, y, 0) = float(x) / 3.0f;
            img.at(x, y, 1) = float(y);
            img.at(x, y, 2) = 0.5f;
        }
    write_image(out_path("tex_base.png"), img);
    write_image(out_path("tex_normal.png"), img);
    GltfBuilder b = textured_quad("tex_base.png", "tex_normal.png");
    std::vector<std::string> w;
    const Scene s = load_gltf(b.write_gltf(out_path("textured.gltf")), &w);
    ASSERT_EQ(s.textures.size(), 2u);
    const Material& m = s.materials.at(0);
    ASSERT_GE(m.base_color_texture.texture, 0);
    const Texture& t = s.textures[std::size_t(m.base_color_texture.texture)];
    EXPECT_TRUE(t.srgb);
    EXPECT_FALSE(s.textures[std::size_t(m.normal_texture.texture)].srgb);
    ASSERT_EQ(t.width(), 4);
    EXPECT_FALSE(t.codes.empty());                          // an 8-bit file: level 0 as codes
    EXPECT_TRUE(t.image.empty());
    // Base colour textures are sRGB (glTF 2.0 §3.9.2): decoded to linear at load (docs/look.md).
    EXPECT_NEAR(t.texel0(3, 1).x, 1.0f, 1e-6f);
    EXPECT_NEAR(t.texel0(1, 0).x, 0.0908417f, 1e-6f);       // sRGB 85/255 -> linear
    EXPECT_NEAR(t.texel0(2, 1).z, 0.2158605f, 1e-6f);       // sRGB 128/255 -> linear
    EXPECT_FLOAT_EQ(t.texel0(1, 0).x, srgb_to_linear(85.0f / 255.0f));
    EXPECT_EQ(t.texel0(0, 0).w, 1.0f);                      // RGB widened to RGBA
    EXPECT_EQ(m.base_color_texture.sampler.wrap_s, Wrap::ClampToEdge);
    EXPECT_EQ(m.base_color_texture.sampler.wrap_t, Wrap::MirroredRepeat);
    EXPECT_EQ(m.base_color_texture.sampler.mag, Filter::Nearest);
    EXPECT_EQ(m.base_color_texture.sampler.min, Filter::Linear);
    EXPECT_EQ(m.base_color_texture.sampler.mip, MipFilter::Linear);  // 9987 LINEAR_MIPMAP_LINEAR
    EXPECT_EQ(m.normal_texture.sampler.wrap_s, Wrap::Repeat);  // no sampler: glTF defaults
    EXPECT_EQ(m.normal_texture.sampler.mip, MipFilter::Linear);  // undefined: trilinear
    EXPECT_FLOAT_EQ(m.normal_texture.scale, 0.5f);
    EXPECT_EQ(m.alpha_mode, AlphaMode::Mask);
    EXPECT_FLOAT_EQ(m.alpha_cutoff, 0.3f);
    EXPECT_TRUE(m.double_sided);
    EXPECT_FLOAT_EQ(m.base_color.g, 0.25f);
    EXPECT_FLOAT_EQ(m.wc.dilute, 0.6f);  // from extras.watercolor
    EXPECT_FLOAT_EQ(m.wc.control[kCtrlEdge].x, 0.5f);
    EXPECT_FLOAT_EQ(m.wc.control[kCtrlEdge].z, -0.2f);
    // Normal map without TANGENT: tangents computed, along +U = +X here.
    const Primitive& p = only_primitive(s);
    ASSERT_EQ(p.tangents.size(), 4u);
    for (const glm::vec4& tg : p.tangents) EXPECT_NEAR(tg.x, 1.0f, 1e-6f);
}

TEST(Textures, MissingFileIsAWarningAndTheTextureIsAbsent) {
    GltfBuilder b = textured_quad("no_such_base.png", "no_such_normal.png");
    std::vector<std::string> w;
    const Scene s = load_gltf(b.write_gltf(out_path("missing_tex.gltf")), &w);
    EXPECT_EQ(s.triangle_count(), 2u);
    EXPECT_EQ(s.materials.at(0).base_color_texture.texture, -1);
    EXPECT_EQ(s.materials.at(0).normal_texture.texture, -1);
    EXPECT_TRUE(contains(w, "no_such_base.png"));
    EXPECT_TRUE(contains(w, "white base colour"));
    EXPECT_TRUE(contains(w, "flat normal"));
    EXPECT_TRUE(only_primitive(s).tangents.empty());  // no usable normal map: no tangents needed
}

TEST(Textures, UndecodableBytesAreAWarning) {
    const std::vector<unsigned char> junk = {'n', 'o', 't', ' ', 'a', 'n', ' ', 'i', 'm', 'a', 'g', 'e'};
    aq::test::write_bytes(out_path("junk.png"), junk);
    GltfBuilder b = textured_quad("junk.png", "junk.png");
    std::vector<std::string> w;
    const Scene s = load_gltf(b.write_gltf(out_path("junk_tex.gltf")), &w);
    EXPECT_EQ(s.materials.at(0).base_color_texture.texture, -1);
    EXPECT_TRUE(contains(w, "cannot be decoded"));
}

TEST(Textures, ImageInABufferViewOfAGlb) {
    ImageF img(3, 3, 4, 0.75f);
    write_image(out_path("tex_bv.png"), img);
    const std::vector<unsigned char> png = aq::test::read_bytes(out_path("tex_bv.png"));
    GltfBuilder b = textured_quad("x.png", "x.png");
    const int view = b.add_view(png.data(), png.size());
    b.j["images"] = nlohmann::json::array({{{"bufferView", view}, {"mimeType", "image/png"}}});
    b.j["textures"] = nlohmann::json::array({{{"source", 0}}});
    b.j["materials"][0].erase("normalTexture");
    const Scene s = load_gltf(b.write_glb(out_path("tex_bv.glb")));
    ASSERT_EQ(s.textures.size(), 1u);
    EXPECT_EQ(s.textures[0].width(), 3);
    EXPECT_NEAR(s.textures[0].texel0(1, 1).w, 191.0f / 255.0f, 1e-6f);
}

TEST(Textures, RealModelsDecodeTheirMaps) {
    const Scene s = load("gltf/WaterBottle/glTF/WaterBottle.gltf");
    const Material& m = s.materials.at(0);
    ASSERT_GE(m.base_color_texture.texture, 0);
    ASSERT_GE(m.normal_texture.texture, 0);
    EXPECT_EQ(s.textures[std::size_t(m.base_color_texture.texture)].width(), 2048);
    EXPECT_FALSE(only_primitive(s).tangents.empty());
    EXPECT_TRUE(s.warnings.empty());
}

// A texture kept as 8-bit codes holds exactly the values of the RGBA float decode with the
// loader's per-value mapping applied (what every texture held before codes replaced the floats):
// real 8-bit PNG maps (sRGB base colours, linear normal and material maps), JPEG files written
// here (grey and colour, through libjpeg-turbo's RGBA output) and the control mapping.
void expect_texture_equals_float_decode(const Texture& t, const std::vector<unsigned char>& bytes, const TexelMap& map,
                                        const std::string& what) {
    ASSERT_FALSE(t.codes.empty()) << what;
    ASSERT_TRUE(t.image.empty()) << what;
    const ImageF f = decode_image_bytes(bytes.data(), bytes.size(), t.name);  // RGBA float
    ASSERT_EQ(f.width(), t.width()) << what;
    ASSERT_EQ(f.height(), t.height()) << what;
    for (int y = 0; y < f.height(); ++y)
        for (int x = 0; x < f.width(); ++x) {
            const glm::vec4 got = t.texel0(x, y);
            for (int lane = 0; lane < 4; ++lane) {
                const float want = map(f.at(x, y, lane), lane);
                ASSERT_EQ(0, std::memcmp(&want, &got[lane], sizeof want)) << what << " texel " << x << "," << y << " lane " << lane;
            }
        }
}

TEST(Textures, EightBitTexturesHoldTheValuesOfTheFloatDecode) {
    for (const char* model : {"gltf/WaterBottle/glTF/WaterBottle.gltf", "gltf/Suzanne/glTF/Suzanne.gltf"}) {
        const Scene s = load(model);
        ASSERT_FALSE(s.textures.empty()) << model;
        const std::string dir = std::filesystem::path(aq::test::shared_dir() + "/assets/" + model).parent_path().string();
        for (const Texture& t : s.textures)
            expect_texture_equals_float_decode(t, aq::test::read_bytes(dir + "/" + t.name),
                                               {t.srgb ? TexelMap::Kind::Srgb : TexelMap::Kind::Identity},
                                               std::string(model) + " " + t.name);
    }
    for (int channels : {1, 3, 4}) {
        ImageF img(37, 23, channels, kUninitialized);
        for (std::size_t i = 0; i < img.num_values(); ++i) img.data()[i] = float((i * 97u) % 256u) / 255.0f;
        for (const char* ext : {".jpg", ".png"}) {
            if (channels == 4 && std::string(ext) == ".jpg") continue;  // JPEG has no alpha
            const std::string path = out_path("codes_" + std::to_string(channels) + ext);
            write_image(path, img);
            const std::vector<unsigned char> bytes = aq::test::read_bytes(path);
            for (const TexelMap& map : {TexelMap{TexelMap::Kind::Srgb}, TexelMap{TexelMap::Kind::Control, 0.7f, -0.2f}}) {
                const Texture t = decode_texture(path, bytes.data(), bytes.size(), nullptr, map);
                expect_texture_equals_float_decode(t, bytes, map, path);
            }
        }
    }
}

TEST(Textures, RealSamplersMapToWrapAndFilter) {
    // BoxTextured: magFilter LINEAR, minFilter NEAREST_MIPMAP_LINEAR, wrapS MIRRORED_REPEAT, wrapT CLAMP_TO_EDGE.
    const Scene s = load("gltf/BoxTextured/BoxTextured.gltf");
    const TextureRef& t = s.materials.at(0).base_color_texture;
    ASSERT_GE(t.texture, 0);
    EXPECT_EQ(s.textures[std::size_t(t.texture)].width(), 211);
    EXPECT_EQ(t.sampler.mag, Filter::Linear);
    EXPECT_EQ(t.sampler.min, Filter::Nearest);
    EXPECT_EQ(t.sampler.mip, MipFilter::Linear);
    EXPECT_EQ(t.sampler.wrap_s, Wrap::MirroredRepeat);
    EXPECT_EQ(t.sampler.wrap_t, Wrap::ClampToEdge);
    // Its mip levels, built at load: 211 -> 105 -> 52 -> 26 -> 13 -> 6 -> 3 -> 1.
    const std::vector<ImageF>& mips = s.textures[std::size_t(t.texture)].mips;
    ASSERT_EQ(mips.size(), 7u);
    EXPECT_EQ(mips[0].width(), 105);
    EXPECT_EQ(mips.back().width(), 1);
    EXPECT_EQ(mips.back().height(), 1);
}

TEST(Materials, BlendIsKeptAndDefaultMaterialAppended) {
    GltfBuilder b;
    const int pa = b.add(aq::test::quad_positions(), kFloat, "VEC3", 4);
    b.j["meshes"] = nlohmann::json::array({{{"primitives", nlohmann::json::array({{{"attributes", {{"POSITION", pa}}}, {"mode", 6}, {"material", 0}},
                                                                                  {{"attributes", {{"POSITION", pa}}}, {"mode", 6}}})}}});
    b.j["nodes"] = nlohmann::json::array({{{"mesh", 0}}});
    b.j["scenes"] = nlohmann::json::array({{{"nodes", {0}}}});
    b.j["materials"] = nlohmann::json::array({{{"name", "glass"}, {"alphaMode", "BLEND"}}});
    const Scene s = load_gltf(b.write_gltf(out_path("blend.gltf")));
    ASSERT_EQ(s.materials.size(), 2u);
    EXPECT_EQ(s.materials[0].alpha_mode, AlphaMode::Blend);  // drawn opaque by the rasterizer (docs/scenes.md)
    EXPECT_EQ(s.materials[1].name, "default");
    EXPECT_EQ(s.meshes[0].primitives[0].material, 0);
    EXPECT_EQ(s.meshes[0].primitives[1].material, 1);
}

// --- other inputs ----------------------------------------------------------------------------

TEST(Positions, NonFiniteAreKeptAndCounted) {
    GltfBuilder b;
    std::vector<float> pos = aq::test::quad_positions();
    pos[0] = std::numeric_limits<float>::quiet_NaN();
    pos[4] = std::numeric_limits<float>::infinity();
    const int pa = b.add(pos, kFloat, "VEC3", 4);
    const int ia = b.add(aq::test::quad_indices(), kUShort, "SCALAR", 6);
    b.single_primitive({{"attributes", {{"POSITION", pa}}}, {"indices", ia}});
    std::vector<std::string> w;
    const Scene s = load_gltf(b.write_gltf(out_path("nonfinite.gltf")), &w);
    EXPECT_EQ(s.triangle_count(), 2u);
    EXPECT_TRUE(std::isnan(only_primitive(s).positions[0].x));
    EXPECT_TRUE(contains(w, "2 vertex positions are not finite"));
    for (const glm::vec3& n : only_primitive(s).normals) EXPECT_TRUE(std::isfinite(n.x + n.y + n.z));
}

TEST(Cameras, PerspectiveNodeCameraAndInfiniteFar) {
    GltfBuilder b;
    const int pa = b.add(aq::test::quad_positions(), kFloat, "VEC3", 4);
    b.single_primitive({{"attributes", {{"POSITION", pa}}}, {"mode", 6}});
    b.j["cameras"] = nlohmann::json::array({{{"type", "perspective"}, {"perspective", {{"yfov", 0.7}, {"znear", 0.05}, {"aspectRatio", 1.5}}}},
                                            {{"type", "orthographic"}, {"orthographic", {{"xmag", 2}, {"ymag", 1}, {"znear", 0}, {"zfar", 10}}}}});
    b.j["nodes"].push_back({{"camera", 0}, {"translation", {0, 0, 5}}});
    b.j["nodes"].push_back({{"camera", 1}, {"translation", {0, 3, 0}}, {"rotation", {-std::sqrt(0.5), 0, 0, std::sqrt(0.5)}}});
    b.j["scenes"][0]["nodes"] = {0, 1, 2};
    const Scene s = load_gltf(b.write_gltf(out_path("cameras.gltf")));
    ASSERT_EQ(s.cameras.size(), 2u);
    const Camera& c = s.cameras[0];
    EXPECT_FALSE(c.orthographic);
    EXPECT_FLOAT_EQ(c.yfov, 0.7f);
    ASSERT_TRUE(c.aspect.has_value());
    EXPECT_FLOAT_EQ(*c.aspect, 1.5f);
    // The origin is 5 units in front of the camera (eye space looks down -Z).
    const glm::vec4 o = c.view * glm::vec4(0, 0, 0, 1);
    EXPECT_NEAR(o.z, -5.0f, 1e-5f);
    // Infinite projection: a finite far plane that contains the whole scene.
    EXPECT_GT(c.zfar, 5.0f + std::sqrt(2.0f));
    EXPECT_TRUE(std::isfinite(c.zfar));
    const Camera& ortho = s.cameras[1];
    EXPECT_TRUE(ortho.orthographic);
    EXPECT_FLOAT_EQ(ortho.xmag, 2.0f);
    // Looking straight down from y = 3: the origin is 3 units in front.
    const glm::vec4 q = ortho.view * glm::vec4(0, 0, 0, 1);
    EXPECT_NEAR(q.z, -3.0f, 1e-5f);
    EXPECT_NEAR(q.x, 0.0f, 1e-5f);
}

TEST(Attributes, ExtraSetsAreKeptForTheControlMapping) {
    GltfBuilder b;
    const int pa = b.add(aq::test::quad_positions(), kFloat, "VEC3", 4);
    const std::vector<std::uint8_t> c1 = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 128, 128, 128, 255};
    const int c1a = b.add(c1, kUByte, "VEC4", 4, true);
    const std::vector<float> t1 = {0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f, 0.7f, 0.8f};
    const int t1a = b.add(t1, kFloat, "VEC2", 4);
    b.single_primitive({{"attributes", {{"POSITION", pa}, {"COLOR_1", c1a}, {"TEXCOORD_1", t1a}}}, {"mode", 6}});
    const Scene s = load_gltf(b.write_gltf(out_path("extra_attrs.gltf")));
    const Primitive& p = only_primitive(s);
    ASSERT_EQ(p.attributes.count("COLOR_1"), 1u);
    ASSERT_EQ(p.attributes.count("TEXCOORD_1"), 1u);
    EXPECT_FLOAT_EQ(p.attributes.at("COLOR_1")[1].g, 1.0f);
    EXPECT_NEAR(p.attributes.at("COLOR_1")[3].r, 128.0f / 255.0f, 1e-7f);
    EXPECT_FLOAT_EQ(p.attributes.at("TEXCOORD_1")[2].y, 0.6f);
    EXPECT_TRUE(p.colors.empty());
}

TEST(Performance, Dragon202kLoadsQuickly) {
    const auto t0 = std::chrono::steady_clock::now();
    const Scene s = load("meshes/stanford_dragon/dragon_202k.glb");
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_EQ(s.triangle_count(), 202520u);
    EXPECT_LT(ms, 2000.0) << "dragon_202k took " << ms << " ms to load";
}

}  // namespace
}  // namespace aq::scene
