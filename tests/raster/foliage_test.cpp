// tests/raster/foliage_test.cpp — LD06 §4.1 on the shared plants (raster/foliage.h): the dense oak's
// 58,560 foliage triangles become a few thousand (LD06 Table 1: 56,952 -> 3,538 and 56,250 -> 9,494),
// the trunk stays as modelled, the same bytes every run, and scenes without foliage are reported.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>

#include "core/hash.h"
#include "raster/foliage.h"
#include "scenes/gltf_loader.h"
#include "tests/raster/raster_test_util.h"
#include "tests/test_support.h"

namespace aq::raster {
namespace {

std::string mesh_hash(const scene::Scene& s) {
    std::string h;
    for (const scene::Mesh& m : s.meshes)
        for (const scene::Primitive& p : m.primitives)
            h += sha256_hex(p.positions.data(), p.positions.size() * sizeof(glm::vec3)) +
                 sha256_hex(p.indices.data(), p.indices.size() * sizeof(std::uint32_t));
    return sha256_hex(h.data(), h.size());
}

TEST(Foliage, DenseOakAbstractsToAFewThousandTriangles) {
    const scene::Scene oak = scene::load_gltf(test::asset("plants/ez-tree/ez_oak_large_dense.glb"));
    std::size_t trunk_tris = 0;
    for (const scene::Instance& inst : oak.instances)
        for (const scene::Primitive& p : oak.meshes[std::size_t(inst.mesh)].primitives)
            if (!scene::is_foliage(oak, inst, p)) trunk_tris += p.indices.size() / 3;
    // LD06 Table 1's two settings, T absolute and r relative to the tree height.
    for (auto [T, r_rel] : {std::pair{83.3f, 2.8f / 37.1f}, std::pair{20.0f, 1.2f / 23.8f}}) {
        FoliageParams p;
        p.threshold = T;
        p.radius = r_rel;
        const auto t0 = std::chrono::steady_clock::now();
        std::vector<std::string> warnings;
        const auto a = abstract_foliage(oak, p, Exec::fast(2), &warnings);
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        ASSERT_TRUE(a->abstracted);
        EXPECT_EQ(a->foliage_triangles, 58560u);
        const std::size_t tris = a->surface.indices.size() / 3;
        std::printf("oak: T %.1f r %.4f h (%.2f units, h = %.1f): %zu foliage triangles -> %zu, grid %lld nodes, %.0f ms\n",
                    double(T), double(r_rel), double(a->radius), double(a->height), a->foliage_triangles, tris,
                    static_cast<long long>(a->surface.grid_nodes), ms);
        EXPECT_GE(tris, 1000u);
        EXPECT_LE(tris, 15000u);
        // The trunk is kept as modelled, the surface added as one foliage instance.
        EXPECT_EQ(a->scene.triangle_count(), trunk_tris + tris);
        const scene::Instance& fi = a->scene.instances.back();
        EXPECT_TRUE(scene::is_foliage(a->scene, fi, a->scene.meshes[std::size_t(fi.mesh)].primitives[0]));
        EXPECT_TRUE(warnings.empty());
    }
}

TEST(Foliage, SameMeshBytesEveryRunAndThreadCount) {
    const scene::Scene bush = scene::load_gltf(test::asset("plants/ez-tree/ez_bush2.glb"));
    FoliageParams p;
    p.threshold = 4.0f;
    const std::string want = mesh_hash(abstract_foliage(bush, p, Exec::reference())->scene);
    for (int threads : {1, 2, 8}) EXPECT_EQ(mesh_hash(abstract_foliage(bush, p, Exec::fast(threads))->scene), want);
}

TEST(Foliage, NoFoliageIsReportedAndEmptySurfacesRefused) {
    const scene::Scene box = test::scene_of({test::make_prim({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 2})});
    std::vector<std::string> warnings;
    const auto a = abstract_foliage(box, {}, {}, &warnings);
    EXPECT_FALSE(a->abstracted);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("no foliage"), std::string::npos);
    EXPECT_EQ(a->scene.triangle_count(), 1u);

    const scene::Scene bush = scene::load_gltf(test::asset("plants/ez-tree/ez_bush2.glb"));
    FoliageParams p;
    p.threshold = 1e9f;  // never reached
    try {
        abstract_foliage(bush, p);
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("empty"), std::string::npos) << e.what();
    }
    p.threshold = 83.3f;
    p.radius = 1e-7f;  // a grid far beyond the limit
    EXPECT_THROW(abstract_foliage(bush, p), Error);
}

}  // namespace
}  // namespace aq::raster
