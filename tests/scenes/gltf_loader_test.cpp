// tests/scenes/gltf_loader_test.cpp — glTF loading of the shared real models and conformance cases.
#include "scenes/gltf_loader.h"

#include <gtest/gtest.h>

#include <cmath>

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
                      ModelCase{"meshes/stanford_dragon/dragon_202k.glb", 202520}));

}  // namespace
}  // namespace aq::scene
