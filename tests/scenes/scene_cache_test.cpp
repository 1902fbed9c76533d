// load_scene through the content cache (scenes/scene_cache.h): a hit is the loaded scene byte for
// byte, a changed file the scene reads is a miss, a damaged entry is loaded again.
#include "scenes/scene_cache.h"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "scenes/scene_archive.h"
#include "scenes/scene_file.h"
#include "tests/test_support.h"

namespace aq::scene {
namespace {
namespace fs = std::filesystem;

struct BytesSink final : archive::Sink {
    std::string bytes;
    void write(const void* d, std::size_t n) override { bytes.append(static_cast<const char*>(d), n); }
};

//! Every archived member of the description (scenes/scene_archive.h lists them all; its size checks
//! stop the build when a member is added without it).
std::string archived(const SceneDesc& d) {
    BytesSink s;
    archive::Writer w(s);
    w(d);
    return s.bytes;
}

std::string fresh_dir(const std::string& name) {
    const std::string d = test::output_dir() + "/" + name;
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

//! A scene file over a copy of BoxTextured with a control texture: three files besides itself.
std::string box_scene(const std::string& dir) {
    for (const char* f : {"BoxTextured.gltf", "BoxTextured0.bin", "CesiumLogoFlat.png"})
        fs::copy_file(test::asset(std::string("gltf/BoxTextured/") + f), dir + "/" + f, fs::copy_options::overwrite_existing);
    fs::copy_file(test::asset("gltf/BoxTextured/CesiumLogoFlat.png"), dir + "/ctrl.png", fs::copy_options::overwrite_existing);
    std::ofstream(dir + "/box.json") << R"({"gltf": "BoxTextured.gltf", "camera": "auto", "width": 64, "height": 48,
        "control": [{"target": "edge", "source": "texture", "file": "ctrl.png"}]})";
    return dir + "/box.json";
}

TEST(SceneCache, AHitIsTheLoadedSceneMemberForMember) {
    const cache::Store store({fresh_dir("hit") + "/cache", cache::kDefaultMaxBytes});
    const std::string box = box_scene(fresh_dir("box"));
    for (const std::string& spec : {test::asset("gltf/WaterBottle/glTF/WaterBottle.gltf"), test::asset("plants/ez-tree/ez_bush2.glb"),
                                    box, test::source_dir() + "/scenes/data/bush.json"}) {
        const std::string plain = archived(load_scene(spec));
        SceneCacheUse miss, hit;
        const std::string first = archived(load_scene_cached(spec, {}, &store, &miss));
        const std::string second = archived(load_scene_cached(spec, {}, &store, &hit));
        EXPECT_FALSE(miss.hit) << spec;
        EXPECT_TRUE(hit.hit) << spec;
        EXPECT_TRUE(miss.notes.empty() && hit.notes.empty()) << spec;
        EXPECT_EQ(miss.key, hit.key);
        EXPECT_TRUE(first == plain) << spec;
        EXPECT_TRUE(second == plain) << spec;
    }
    // The texture store survives the trip: the WaterBottle's maps hold codes and mip levels.
    const SceneDesc d = load_scene_cached(test::asset("gltf/WaterBottle/glTF/WaterBottle.gltf"), {}, &store);
    ASSERT_FALSE(d.scene.textures.empty());
    EXPECT_FALSE(d.scene.textures[0].codes.empty());
    EXPECT_FALSE(d.scene.textures[0].mips.empty());
}

TEST(SceneCache, AChangedFileTheSceneReadsIsAMiss) {
    const cache::Store store({fresh_dir("changed") + "/cache", cache::kDefaultMaxBytes});
    const std::string dir = fresh_dir("changed_box");
    const std::string box = box_scene(dir);
    SceneCacheUse u;
    (void)load_scene_cached(box, {}, &store, &u);
    (void)load_scene_cached(box, {}, &store, &u);
    ASSERT_TRUE(u.hit);
    // Another control texture under the same name, then another buffer: each a miss whose result
    // is the new files' scene, and then a hit again.
    fs::copy_file(test::asset("gltf/WaterBottle/glTF/WaterBottle_normal.png"), dir + "/ctrl.png", fs::copy_options::overwrite_existing);
    SceneDesc d = load_scene_cached(box, {}, &store, &u);
    EXPECT_FALSE(u.hit);
    EXPECT_TRUE(archived(d) == archived(load_scene(box)));
    (void)load_scene_cached(box, {}, &store, &u);
    EXPECT_TRUE(u.hit);
    {
        std::fstream f(dir + "/BoxTextured0.bin", std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(0);
        f.put(char(0x7f));  // the first position's x changes
    }
    d = load_scene_cached(box, {}, &store, &u);
    EXPECT_FALSE(u.hit);
    EXPECT_TRUE(archived(d) == archived(load_scene(box)));
    // A file that is gone: a miss, and the load's own error.
    fs::remove(dir + "/ctrl.png");
    EXPECT_NE(test::error_of([&] { (void)load_scene_cached(box, {}, &store, &u); }).find("ctrl.png"), std::string::npos);
    EXPECT_FALSE(u.hit);
    // The load options that shape the scene are part of the key.
    LoadOptions outside;
    outside.allow_outside_files = true;
    SceneCacheUse v;
    (void)load_scene_cached(test::asset("gltf/BoxTextured/BoxTextured.gltf"), {}, &store, &u);
    (void)load_scene_cached(test::asset("gltf/BoxTextured/BoxTextured.gltf"), outside, &store, &v);
    EXPECT_NE(u.key, v.key);
}

TEST(SceneCache, EditsOfTheArtDirectionArePartOfTheKey) {
    const cache::Store store({fresh_dir("edits") + "/cache", cache::kDefaultMaxBytes});
    const std::string oak = test::source_dir() + "/scenes/data/oak.json";
    LoadOptions a, b;
    a.edits = {parse_scene_edit("/layers/1/color=[0.8,0.3,0.2]")};
    b.edits = {parse_scene_edit("/layers/1/color=[0.2,0.3,0.8]")};
    SceneCacheUse plain, ua, ub, again;
    (void)load_scene_cached(oak, {}, &store, &plain);
    const SceneDesc da = load_scene_cached(oak, a, &store, &ua);
    const SceneDesc db = load_scene_cached(oak, b, &store, &ub);
    (void)load_scene_cached(oak, a, &store, &again);
    EXPECT_FALSE(ua.hit);
    EXPECT_FALSE(ub.hit);
    EXPECT_TRUE(again.hit);
    EXPECT_NE(plain.key, ua.key);
    EXPECT_NE(ua.key, ub.key);
    EXPECT_FLOAT_EQ(da.scene.layers.at(1).color->r, 0.8f);
    EXPECT_FLOAT_EQ(db.scene.layers.at(1).color->r, 0.2f);
    EXPECT_TRUE(archived(da) == archived(load_scene(oak, a)));
}

TEST(SceneCache, ADamagedEntryIsReportedAndLoadedAgain) {
    const cache::Store store({fresh_dir("damaged") + "/cache", cache::kDefaultMaxBytes});
    const std::string spec = test::asset("gltf/BoxTextured/BoxTextured.gltf");
    SceneCacheUse u;
    const std::string plain = archived(load_scene_cached(spec, {}, &store, &u));
    {  // a byte in the scene's data (past the list of inputs at its start)
        const std::string p = store.path("scene", u.key);
        std::fstream f(p, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(std::streamoff(fs::file_size(p) / 2));
        f.put('!');
    }
    const std::string again = archived(load_scene_cached(spec, {}, &store, &u));
    EXPECT_FALSE(u.hit);
    ASSERT_EQ(u.notes.size(), 1u);
    EXPECT_NE(u.notes[0].find("damaged"), std::string::npos) << u.notes[0];
    EXPECT_TRUE(again == plain);
    (void)load_scene_cached(spec, {}, &store, &u);
    EXPECT_TRUE(u.hit) << "stored again after the damaged entry";
}

TEST(SceneCache, ProceduralScenesAndNoStoreLoadAsBefore) {
    const cache::Store store({fresh_dir("procedural") + "/cache", cache::kDefaultMaxBytes});
    SceneCacheUse u;
    const SceneDesc d = load_scene_cached("procedural:swatches", {}, &store, &u);
    EXPECT_TRUE(u.key.empty());
    EXPECT_FALSE(u.hit);
    EXPECT_TRUE(archived(d) == archived(load_scene("procedural:swatches")));
    EXPECT_FALSE(fs::exists(store.config().dir));
    (void)load_scene_cached(test::asset("gltf/BoxTextured/BoxTextured.gltf"), {}, nullptr, &u);
    EXPECT_TRUE(u.key.empty());
}

}  // namespace
}  // namespace aq::scene
