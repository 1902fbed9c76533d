// tests/scenes/malformed_test.cpp — hostile glTF input: every case must end in a clean aq::Error
// (never a crash, an over-read or a hang). Run under ASan/UBSan to make over-reads visible.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>

#include "core/io.h"
#include "scenes/gltf_loader.h"
#include "tests/scenes/gltf_builder.h"
#include "tests/test_support.h"

namespace aq::scene {
namespace {

using aq::test::GltfBuilder;
using aq::test::kFloat;
using aq::test::kUByte;
using aq::test::kUInt;
using aq::test::kUShort;
namespace fs = std::filesystem;

std::string out_path(const std::string& name) {
    const std::string d = aq::test::output_dir() + "/scenes";
    fs::create_directories(d);
    return d + "/" + name;
}

//! Expects aq::Error whose message contains `needle` (and the file name).
void expect_error(const std::string& path, const std::string& needle) {
    try {
        load_gltf(path);
        ADD_FAILURE() << path << ": loaded, expected an error containing '" << needle << "'";
    } catch (const aq::Error& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find(needle), std::string::npos) << "message: " << msg;
        EXPECT_NE(msg.find(fs::path(path).filename().string()), std::string::npos) << "message does not name the file: " << msg;
    }
}

TEST(Malformed, EveryFileInTheSharedFolderIsAnError) {
    const fs::path dir = aq::test::asset("malformed");
    int n = 0;
    for (const auto& e : fs::directory_iterator(dir)) {
        if (e.path().extension() != ".gltf") continue;
        ++n;
        SCOPED_TRACE(e.path().string());
        EXPECT_THROW(load_gltf(e.path().string()), aq::Error);
    }
    EXPECT_GE(n, 4);
}

TEST(Malformed, MissingFileNamesThePath) { expect_error(out_path("does_not_exist.gltf"), "not found"); }

TEST(Malformed, DirectoryIsNotAFile) {
    fs::create_directories(out_path("a_folder.gltf"));
    expect_error(out_path("a_folder.gltf"), "is a folder; only regular files are read");
}

// A valid quad GLB cut at many lengths: every prefix must be refused cleanly.
TEST(Malformed, TruncatedGlb) {
    GltfBuilder b;
    const int pa = b.add(aq::test::quad_positions(), kFloat, "VEC3", 4);
    const int ia = b.add(aq::test::quad_indices(), kUShort, "SCALAR", 6);
    b.single_primitive({{"attributes", {{"POSITION", pa}}}, {"indices", ia}});
    const std::vector<unsigned char> full = b.glb_bytes();
    aq::test::write_bytes(out_path("full.glb"), full);
    EXPECT_EQ(load_gltf(out_path("full.glb")).triangle_count(), 2u);  // the uncut file is fine
    for (std::size_t len = 0; len < full.size(); len += (len < 64 ? 1 : 7)) {
        SCOPED_TRACE(len);
        const std::vector<unsigned char> cut(full.begin(), full.begin() + std::ptrdiff_t(len));
        const std::string p = out_path("truncated.glb");
        aq::test::write_bytes(p, cut);
        EXPECT_THROW(load_gltf(p), aq::Error);
    }
    // The same bytes with a corrupted header length, version and chunk sizes.
    auto patched = [&](std::size_t off, std::uint32_t v) {
        std::vector<unsigned char> c = full;
        for (int i = 0; i < 4; ++i) c[off + std::size_t(i)] = static_cast<unsigned char>(v >> (8 * i));
        const std::string p = out_path("patched.glb");
        aq::test::write_bytes(p, c);
        return p;
    };
    expect_error(patched(4, 1), "version");
    expect_error(patched(8, 0xFFFFFFF0u), "truncated");
    expect_error(patched(12, 0xFFFFFFF0u), "JSON chunk");
    expect_error(patched(16, 0x12345678u), "JSON");
}

TEST(Malformed, GarbageBytes) {
    std::uint32_t state = 12345u;
    for (int trial = 0; trial < 40; ++trial) {
        std::vector<unsigned char> g(std::size_t(16 + trial * 37));
        for (auto& c : g) {
            state = state * 1664525u + 1013904223u;
            c = static_cast<unsigned char>(state >> 24);
        }
        if (trial % 2) g[0] = 'g', g[1] = 'l', g[2] = 'T', g[3] = 'F';  // valid magic, garbage after
        for (const char* ext : {".glb", ".gltf"}) {
            const std::string p = out_path(std::string("garbage") + ext);
            aq::test::write_bytes(p, g);
            EXPECT_THROW(load_gltf(p), aq::Error) << "trial " << trial << ext;
        }
    }
    aq::test::write_bytes(out_path("empty.gltf"), {});
    EXPECT_THROW(load_gltf(out_path("empty.gltf")), aq::Error);
    const std::string not_json = "{\"asset\": {\"version\": \"2.0\"}, \"meshes\": [";
    aq::test::write_bytes(out_path("cut.gltf"), std::vector<unsigned char>(not_json.begin(), not_json.end()));
    EXPECT_THROW(load_gltf(out_path("cut.gltf")), aq::Error);
}

// A valid quad; each test breaks one thing.
GltfBuilder quad(bool indexed = true) {
    GltfBuilder b;
    const int pa = b.add(aq::test::quad_positions(), kFloat, "VEC3", 4);
    nlohmann::json prim = {{"attributes", {{"POSITION", pa}}}};
    if (indexed) prim["indices"] = b.add(aq::test::quad_indices(), kUShort, "SCALAR", 6);
    b.single_primitive(prim);
    return b;
}

TEST(Malformed, AccessorPastTheEndOfItsBufferView) {
    GltfBuilder b = quad();
    b.j["accessors"][0]["count"] = 5;  // 5 x 12 bytes in a 48-byte view
    expect_error(b.write_gltf(out_path("acc_past_end.gltf")), "exceeds bufferView");
    GltfBuilder c = quad();
    c.j["accessors"][0]["byteOffset"] = 4;  // 4 + 48 > 48
    expect_error(c.write_gltf(out_path("acc_offset.gltf")), "exceeds bufferView");
    GltfBuilder d = quad();
    d.j["accessors"][0]["byteOffset"] = 4000000000ull;
    expect_error(d.write_gltf(out_path("acc_offset_huge.gltf")), "exceeds bufferView");
}

TEST(Malformed, BufferViewPastTheEndOfItsBuffer) {
    GltfBuilder b = quad();
    b.j["bufferViews"][0]["byteLength"] = 4096;
    expect_error(b.write_gltf(out_path("view_past_end.gltf")), "exceeds buffer");
    GltfBuilder c = quad();
    c.j["bufferViews"][0]["byteOffset"] = 18446744073709551000ull;  // offset + length wraps around
    expect_error(c.write_gltf(out_path("view_wrap.gltf")), "exceeds buffer");
}

TEST(Malformed, ByteStride) {
    GltfBuilder b = quad();
    b.j["bufferViews"][0]["byteStride"] = 4;  // smaller than a VEC3 float
    expect_error(b.write_gltf(out_path("stride_small.gltf")), "byteStride");
    GltfBuilder c = quad();
    c.j["bufferViews"][0]["byteStride"] = 16;  // 3 x 16 + 12 > 48
    expect_error(c.write_gltf(out_path("stride_overflow.gltf")), "exceeds bufferView");
    GltfBuilder d = quad();
    d.j["bufferViews"][0]["byteStride"] = 400;  // above the glTF maximum of 252
    expect_error(d.write_gltf(out_path("stride_huge.gltf")), "byteStride");
}

TEST(Malformed, AbsurdCountIsRefusedBeforeAllocating) {
    GltfBuilder b = quad(false);
    // No bufferView: glTF says zeros, so nothing bounds the count but our limit.
    b.j["accessors"][0].erase("bufferView");
    b.j["accessors"][0]["count"] = 4000000000ull;
    expect_error(b.write_gltf(out_path("count_huge.gltf")), "limit");
    GltfBuilder c = quad();
    c.j["accessors"][0]["count"] = 0x4000000000000001ull;  // count * stride overflows 64 bits
    expect_error(c.write_gltf(out_path("count_overflow.gltf")), "limit");
}

TEST(Malformed, PrimitivesCannotAddUpPastTheLimitsBeforeAllocating) {
    // 3 primitives of 20M zero vertices each (no bufferView): 60M vertices in total.
    GltfBuilder b = quad(false);
    b.j["accessors"][0].erase("bufferView");
    b.j["accessors"][0]["count"] = 20000000;
    const nlohmann::json prim = {{"attributes", {{"POSITION", 0}}}, {"mode", 4}};
    b.j["meshes"][0]["primitives"] = nlohmann::json::array({prim, prim, prim});
    expect_error(b.write_gltf(out_path("many_vertices.gltf")), "vertices in total");
    // 20M-index strips over a 4-vertex quad: ~60M triangles in total (refused by the pre-pass,
    // before the undersized index view is even looked at).
    GltfBuilder c = quad(false);
    c.j["accessors"].push_back({{"bufferView", 0}, {"componentType", kUShort}, {"count", 20000000}, {"type", "SCALAR"}});
    const nlohmann::json strip = {{"attributes", {{"POSITION", 0}}}, {"mode", 5}, {"indices", 1}};
    c.j["meshes"][0]["primitives"] = nlohmann::json::array({strip, strip, strip});
    expect_error(c.write_gltf(out_path("many_triangles.gltf")), "triangles in the file");
}

TEST(Malformed, InstancingCannotMultiplyTrianglesPastTheLimit) {
    // A 1M-triangle strip (accessor without bufferView: zeros) placed by 60 nodes = 60M triangles.
    GltfBuilder b = quad(false);
    b.j["accessors"][0].erase("bufferView");
    b.j["accessors"][0]["count"] = 1000002;
    b.j["meshes"][0]["primitives"][0]["mode"] = 5;
    b.j["nodes"] = nlohmann::json::array();
    b.j["scenes"][0]["nodes"] = nlohmann::json::array();
    for (int i = 0; i < 60; ++i) {
        b.j["nodes"].push_back({{"mesh", 0}});
        b.j["scenes"][0]["nodes"].push_back(i);
    }
    expect_error(b.write_gltf(out_path("instancing.gltf")), "after instancing");
}

TEST(Malformed, IndexOutOfRange) {
    GltfBuilder b;
    const int pa = b.add(aq::test::quad_positions(), kFloat, "VEC3", 4);
    const std::vector<std::uint32_t> idx = {0, 1, 2, 0, 2, 4};
    const int ia = b.add(idx, kUInt, "SCALAR", 6);
    b.single_primitive({{"attributes", {{"POSITION", pa}}}, {"indices", ia}});
    expect_error(b.write_gltf(out_path("index_range.gltf")), "out of range");
    GltfBuilder c;
    const int pc = c.add(aq::test::quad_positions(), kFloat, "VEC3", 4);
    const std::vector<std::uint32_t> big = {0, 1, 0xFFFFFFFFu};
    const int ic = c.add(big, kUInt, "SCALAR", 3);
    c.single_primitive({{"attributes", {{"POSITION", pc}}}, {"indices", ic}, {"mode", 5}});
    expect_error(c.write_gltf(out_path("index_max.gltf")), "out of range");
}

TEST(Malformed, BadIndexComponentTypeAndAttributeTypes) {
    GltfBuilder b = quad();
    b.j["accessors"][1]["componentType"] = kFloat;
    expect_error(b.write_gltf(out_path("index_float.gltf")), "indices");
    GltfBuilder c = quad();
    c.j["accessors"][0]["type"] = "VEC2";
    expect_error(c.write_gltf(out_path("pos_vec2.gltf")), "POSITION");
    GltfBuilder d = quad();
    const std::vector<float> n = {0, 0, 1, 0, 0, 1};  // 2 normals for 4 positions
    d.j["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = d.add(n, kFloat, "VEC3", 2);
    expect_error(d.write_gltf(out_path("normal_count.gltf")), "differs from POSITION count");
    GltfBuilder e = quad();
    e.j["meshes"][0]["primitives"][0]["attributes"].erase("POSITION");
    e.j["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = 0;
    expect_error(e.write_gltf(out_path("no_position.gltf")), "POSITION");
    GltfBuilder f = quad();
    f.j["meshes"][0]["primitives"][0]["mode"] = 9;
    expect_error(f.write_gltf(out_path("bad_mode.gltf")), "mode");
}

TEST(Malformed, DanglingReferences) {
    GltfBuilder a = quad();
    a.j["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 7;
    expect_error(a.write_gltf(out_path("ref_accessor.gltf")), "accessor 7 does not exist");
    GltfBuilder b = quad();
    b.j["accessors"][0]["bufferView"] = 9;
    expect_error(b.write_gltf(out_path("ref_view.gltf")), "");
    GltfBuilder c = quad();
    c.j["nodes"][0]["mesh"] = 3;
    expect_error(c.write_gltf(out_path("ref_mesh.gltf")), "mesh 3 does not exist");
    GltfBuilder d = quad();
    d.j["meshes"][0]["primitives"][0]["material"] = 2;
    expect_error(d.write_gltf(out_path("ref_material.gltf")), "material 2 does not exist");
    GltfBuilder e = quad();
    e.j["nodes"][0]["children"] = {5};
    expect_error(e.write_gltf(out_path("ref_child.gltf")), "");
    GltfBuilder f = quad();
    f.j["materials"] = nlohmann::json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 4}}}}}}});
    f.j["meshes"][0]["primitives"][0]["material"] = 0;
    expect_error(f.write_gltf(out_path("ref_texture.gltf")), "texture 4 does not exist");
    GltfBuilder g = quad();
    g.j["scene"] = 3;
    expect_error(g.write_gltf(out_path("ref_scene.gltf")), "scene");
    GltfBuilder h = quad();
    h.j["nodes"][0]["camera"] = 0;
    expect_error(h.write_gltf(out_path("ref_camera.gltf")), "camera");
}

TEST(Malformed, ImageBufferViewOutOfRange) {
    GltfBuilder b = quad();
    const std::vector<unsigned char> bytes(16, 0x89);
    const int view = b.add_view(bytes.data(), bytes.size());
    b.j["bufferViews"][std::size_t(view)]["byteLength"] = 1 << 20;
    b.j["images"] = nlohmann::json::array({{{"bufferView", view}, {"mimeType", "image/png"}}});
    b.j["textures"] = nlohmann::json::array({{{"source", 0}}});
    b.j["materials"] = nlohmann::json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
    b.j["meshes"][0]["primitives"][0]["material"] = 0;
    expect_error(b.write_glb(out_path("image_view.glb")), "exceeds buffer");
}

TEST(Malformed, NodeCyclesAndSharedChildren) {
    GltfBuilder b = quad();
    b.j["nodes"] = nlohmann::json::array({{{"mesh", 0}, {"children", {1}}}, {{"children", {0}}}});
    expect_error(b.write_gltf(out_path("cycle.gltf")), "cycle");
    GltfBuilder c = quad();
    c.j["nodes"] = nlohmann::json::array({{{"children", {0}}}});
    expect_error(c.write_gltf(out_path("self_cycle.gltf")), "cycle");
    GltfBuilder d = quad();
    d.j["nodes"] = nlohmann::json::array({{{"children", {2}}}, {{"children", {2}}}, {{"mesh", 0}}});
    d.j["scenes"][0]["nodes"] = {0, 1};
    expect_error(d.write_gltf(out_path("two_parents.gltf")), "more than one parent");
}

TEST(Malformed, NonFiniteTransforms) {
    // JSON has no NaN literal; 1e999 parses to infinity and must be refused.
    GltfBuilder b = quad();
    b.j["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    std::string text = b.j.dump();
    b.finish_buffer();
    const std::string m = "\"matrix\":[1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1]";
    nlohmann::json jj = b.j;
    jj["buffers"][0]["uri"] = "data:application/octet-stream;base64," + aq::test::base64(b.bin);
    text = jj.dump();
    const auto pos = text.find(m);
    ASSERT_NE(pos, std::string::npos);
    text.replace(pos, m.size(), "\"matrix\":[1e999,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1]");
    aq::test::write_bytes(out_path("matrix_inf.gltf"), std::vector<unsigned char>(text.begin(), text.end()));
    expect_error(out_path("matrix_inf.gltf"), "overflow");  // refused by the JSON parser
    // 1e300 is a finite double but not a finite float.
    GltfBuilder f = quad();
    f.j["nodes"][0]["matrix"] = {1e300, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    expect_error(f.write_gltf(out_path("matrix_float_inf.gltf")), "non-finite");
    GltfBuilder c = quad();
    c.j["nodes"][0]["scale"] = {1e30, 1e30, 1e30};
    c.j["nodes"][0]["children"] = {1};
    c.j["nodes"].push_back({{"scale", {1e30, 1e30, 1e30}}, {"mesh", 0}});
    expect_error(c.write_gltf(out_path("scale_overflow.gltf")), "overflows");
    GltfBuilder d = quad();
    d.j["nodes"][0]["rotation"] = {0, 0, 0, 0};
    expect_error(d.write_gltf(out_path("zero_quat.gltf")), "quaternion");
    GltfBuilder e = quad();
    e.j["nodes"][0]["matrix"] = {1, 0, 0};
    expect_error(e.write_gltf(out_path("short_matrix.gltf")), "");
}

TEST(Malformed, SparseAccessorsAreRefused) {
    GltfBuilder b = quad();
    const std::vector<std::uint16_t> si = {1};
    const std::vector<float> sv = {5, 5, 5};
    const int iv = b.add_view(si.data(), 2);
    const int vv = b.add_view(sv.data(), 12);
    b.j["accessors"][0]["sparse"] = {{"count", 1},
                                     {"indices", {{"bufferView", iv}, {"componentType", kUShort}}},
                                     {"values", {{"bufferView", vv}}}};
    expect_error(b.write_gltf(out_path("sparse.gltf")), "sparse");
}

TEST(Malformed, DeepHierarchyIsBounded) {
    GltfBuilder b = quad();
    b.j["nodes"] = nlohmann::json::array();
    const int depth = kMaxNodeDepth + 10;
    for (int i = 0; i < depth; ++i) {
        nlohmann::json n = {{"translation", {0.0, 0.0, 0.0}}};
        if (i + 1 < depth) n["children"] = {i + 1};
        else n["mesh"] = 0;
        b.j["nodes"].push_back(n);
    }
    expect_error(b.write_gltf(out_path("deep.gltf")), "deeper");
}

TEST(Malformed, PathologicalJsonNestingIsRefusedBeforeParsing) {
    const int d = 200000;  // crashes a recursive JSON parser by stack overflow
    const std::string deep = "{\"asset\":{\"version\":\"2.0\"},\"extras\":" + std::string(d, '[') + std::string(d, ']') + "}";
    aq::test::write_bytes(out_path("deep.gltf"), std::vector<unsigned char>(deep.begin(), deep.end()));
    expect_error(out_path("deep.gltf"), "nested deeper");
    GltfBuilder b = quad();
    b.j["extras"] = nlohmann::json::array();
    nlohmann::json* cur = &b.j["extras"];
    for (int i = 0; i < 300; ++i) {
        cur->push_back(nlohmann::json::array());
        cur = &(*cur)[0];
    }
    expect_error(b.write_glb(out_path("deep.glb")), "nested deeper");
    // Brackets inside strings do not count.
    GltfBuilder c = quad();
    c.j["extras"] = {{"text", std::string(5000, '[')}};
    EXPECT_EQ(load_gltf(c.write_gltf(out_path("brackets_in_string.gltf"))).triangle_count(), 2u);
}

TEST(Malformed, UnsupportedRequiredExtension) {
    GltfBuilder b = quad();
    b.j["extensionsUsed"] = {"KHR_draco_mesh_compression"};
    b.j["extensionsRequired"] = {"KHR_draco_mesh_compression"};
    expect_error(b.write_gltf(out_path("draco.gltf")), "KHR_draco_mesh_compression");
}

// --- issue 8: budgets and the path policy (docs/limits.md) ------------------------------------------

namespace issue8 {

//! A glTF whose mesh has `n` primitives, primitive i using material i whose base colour is the
//! embedded PNG i (64x64), so loading decodes n textures.
std::string many_textures(int n, const std::string& name) {
    GltfBuilder b = quad();
    const std::string png = out_path(name + ".src.png");
    aq::write_image(png, aq::ImageF(64, 64, 3, 0.5f));
    const std::vector<unsigned char> bytes = aq::test::read_bytes(png);
    nlohmann::json prim = b.j["meshes"][0]["primitives"][0];
    b.j["meshes"][0]["primitives"] = nlohmann::json::array();
    b.j["images"] = b.j["textures"] = b.j["materials"] = nlohmann::json::array();
    for (int i = 0; i < n; ++i) {
        b.j["images"].push_back({{"uri", "data:image/png;base64," + aq::test::base64(bytes)}});
        b.j["textures"].push_back({{"source", i}});
        b.j["materials"].push_back({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", i}}}}}});
        prim["material"] = i;
        b.j["meshes"][0]["primitives"].push_back(prim);
    }
    return b.write_gltf(out_path(name + ".gltf"));
}

TEST(Malformed, DecodedTexturesShareOneBudgetPerFile) {
    // Issue 8: a 1 MB glTF embedding PNGs of 16384x2048 zeros decoded 4.7-8.9 GB. The budget is
    // checked from each image's header before decoding; past it the load fails (not a warning).
    const std::string path = many_textures(8, "bomb");
    aq::scene::LoadOptions opt;
    opt.texture_budget_bytes = std::size_t(64) * 64 * 16 * 3;  // three textures fit, not four
    // The textures decode in parallel, each within an equal share of the budget; past a share
    // they are decoded again one by one, so the error is always the sequential one: the fourth.
    for (int run = 0; run < 5; ++run) {
        try {
            load_gltf(path, nullptr, opt);
            ADD_FAILURE() << "eight textures loaded within a budget of three";
        } catch (const aq::Error& e) {
            EXPECT_NE(std::string(e.what()).find("budget"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("material 3 base colour: image 'image 3'"), std::string::npos) << e.what();
        }
    }
    // A budget of exactly eight holds them (each exactly its share), as does the default (1 GiB).
    opt.texture_budget_bytes = std::size_t(64) * 64 * 16 * 8;
    EXPECT_EQ(load_gltf(path, nullptr, opt).textures.size(), 8u);
    const aq::scene::Scene s = load_gltf(path);
    EXPECT_EQ(s.textures.size(), 8u);
}

TEST(Malformed, TinyFileCannotAskForGigabytesOfZeros) {
    // Issue 8: a 2 KB glTF whose POSITION accessor has no bufferView and count 49,999,998 took
    // 5 s and 4.5 GB. Implicit (all-zero) accessor data is capped at 16 MiB per file.
    GltfBuilder b = quad(false);
    b.j["accessors"][0].erase("bufferView");
    b.j["accessors"][0]["count"] = 49999998;
    expect_error(b.write_gltf(out_path("zeros.gltf")), "implicit");
}

TEST(Malformed, UrisOutsideTheModelFolderAreRefused) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::path(out_path("policy")) / "model";
    fs::create_directories(dir);
    GltfBuilder b = quad();
    b.finish_buffer();
    aq::test::write_bytes((dir.parent_path() / "outside.bin").string(), b.bin);
    aq::test::write_bytes((dir / "inside.bin").string(), b.bin);
    for (const std::string uri : {"../outside.bin", "%2e%2e/outside.bin", "%2E%2E%2Foutside.bin"}) {
        b.j["buffers"][0]["uri"] = uri;
        std::ofstream((dir / "m.gltf").string()) << b.j.dump();
        expect_error((dir / "m.gltf").string(), "outside the model's folder");
        aq::scene::LoadOptions allow;
        allow.allow_outside_files = true;
        EXPECT_NO_THROW(load_gltf((dir / "m.gltf").string(), nullptr, allow)) << uri;
    }
    // An absolute path is no relative URI reference: tinygltf joins it below the model's folder,
    // where it is not found (so /etc/passwd is never read).
    b.j["buffers"][0]["uri"] = (dir.parent_path() / "outside.bin").string();
    std::ofstream((dir / "m.gltf").string()) << b.j.dump();
    expect_error((dir / "m.gltf").string(), "not found");
    b.j["buffers"][0]["uri"] = "inside.bin";
    std::ofstream((dir / "m.gltf").string()) << b.j.dump();
    EXPECT_NO_THROW(load_gltf((dir / "m.gltf").string())) << "a buffer beside the model must load";
}

}  // namespace issue8

}  // namespace
}  // namespace aq::scene
