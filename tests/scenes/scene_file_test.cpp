// tests/scenes/scene_file_test.cpp — scene files, control rules, WC17 mapping, automatic framing.
#include "scenes/scene_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>

#include <glm/gtc/matrix_transform.hpp>

#include "core/io.h"
#include "scenes/procedural.h"
#include "tests/scenes/gltf_builder.h"
#include "tests/test_support.h"

namespace aq::scene {
namespace {
namespace fs = std::filesystem;

std::string out_path(const std::string& name) {
    const std::string d = aq::test::output_dir() + "/scenes";
    fs::create_directories(d);
    return d + "/" + name;
}

// Writes a scene file into the test output folder; `gltf` paths are made absolute.
std::string write_scene(const std::string& name, const std::string& text) {
    const std::string p = out_path(name);
    std::ofstream(p) << text;
    return p;
}

std::string box_path() { return fs::absolute(aq::test::asset("gltf/Box/glTF-Embedded/Box.gltf")).string(); }
std::string vc_path() { return fs::absolute(aq::test::asset("gltf/BoxVertexColors_CC0/glTF-Embedded/BoxVertexColors.gltf")).string(); }

void expect_error(const std::string& file, const std::string& key, const std::string& what = "") {
    try {
        load_scene(file);
        ADD_FAILURE() << file << " loaded; expected an error about key '" << key << "'";
    } catch (const aq::Error& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find(fs::path(file).filename().string()), std::string::npos) << "file not named: " << m;
        EXPECT_NE(m.find("'" + key + "'"), std::string::npos) << "key path not named: " << m;
        EXPECT_NE(m.find(what), std::string::npos) << m;
    }
}

// --- shipped files -------------------------------------------------------------------------------

TEST(ShippedScenes, EveryDataFileLoads) {
    const fs::path dir = fs::path(aq::test::source_dir()) / "scenes" / "data";
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) {
        if (e.path().extension() != ".json") continue;
        SCOPED_TRACE(e.path().string());
        names.insert(e.path().stem().string());
        const SceneDesc d = load_scene(e.path().string());
        EXPECT_GT(d.scene.triangle_count(), 0u);
        EXPECT_FALSE(d.scene.lights.empty());
        EXPECT_TRUE(d.scene.world_bounds().valid);
        EXPECT_FALSE(d.style.empty());
        // Visible control: at least two control targets carry non-zero values somewhere.
        int targets_painted = 0;
        for (int t = 0; t < kNumControlTargets; ++t) {
            bool any = false;
            for (const Mesh& m : d.scene.meshes)
                for (const Primitive& p : m.primitives)
                    for (const glm::vec4& v : p.control[std::size_t(t)]) any = any || v.x != 0.0f || v.y != 0.0f || v.z != 0.0f;
            targets_painted += any;
        }
        EXPECT_GE(targets_painted, 2);
        // The camera sees the scene centre in front of it.
        const Bounds b = d.scene.world_bounds();
        const glm::vec4 c = d.camera.view * glm::vec4(0.5f * (b.min + b.max), 1.0f);
        EXPECT_LT(c.z, -d.camera.znear);
        EXPECT_GT(c.z, -d.camera.zfar);
        if (!d.paper.empty()) {
            EXPECT_TRUE(fs::is_regular_file(d.paper)) << d.paper;
        }
    }
    for (const char* required : {"suzanne", "waterbottle", "orientation_test", "dragon_202k", "procedural"})
        EXPECT_EQ(names.count(required), 1u) << required;
}

TEST(ShippedScenes, SuzanneSettings) {
    const SceneDesc d = load_scene((fs::path(aq::test::source_dir()) / "scenes/data/suzanne.json").string());
    EXPECT_EQ(d.scene.triangle_count(), 3936u);
    EXPECT_EQ(d.width, 1280);
    EXPECT_EQ(d.height, 720);
    EXPECT_EQ(d.style, "wc18");
    EXPECT_EQ(d.scene.lights.size(), 2u);
    EXPECT_FLOAT_EQ(d.scene.materials.at(0).wc.cangiante, 0.25f);
    // The model scale (4) is applied to the instance.
    EXPECT_FLOAT_EQ(d.scene.instances.at(0).world[0][0], 4.0f);
    EXPECT_NE(d.paper.find("rough_default_2k.jpg"), std::string::npos);
    // Substrate distortion is the constant 0.3 everywhere.
    for (const glm::vec4& v : d.scene.meshes[0].primitives[0].control[kCtrlSubstrate]) ASSERT_FLOAT_EQ(v.r, 0.3f);
}

// --- entry points --------------------------------------------------------------------------------

TEST(LoadScene, BareGltfFramesTheBoundsWithADefaultLight) {
    const SceneDesc d = load_scene(box_path());
    EXPECT_EQ(d.scene.triangle_count(), 12u);
    EXPECT_TRUE(d.camera_auto);
    ASSERT_EQ(d.scene.lights.size(), 1u);
    for (const Mesh& m : d.scene.meshes)
        for (const Primitive& p : m.primitives)
            for (const auto& c : p.control) EXPECT_TRUE(c.empty());  // neutral control
    // All 8 corners of the bounds project inside the image.
    const Bounds b = d.scene.world_bounds();
    const glm::mat4 proj = glm::perspective(d.camera.yfov, d.auto_aspect, d.camera.znear, d.camera.zfar);
    for (int k = 0; k < 8; ++k) {
        const glm::vec3 p((k & 1) ? b.max.x : b.min.x, (k & 2) ? b.max.y : b.min.y, (k & 4) ? b.max.z : b.min.z);
        const glm::vec4 clip = proj * d.camera.view * glm::vec4(p, 1.0f);
        ASSERT_GT(clip.w, 0.0f);
        EXPECT_LE(std::abs(clip.x / clip.w), 1.0f);
        EXPECT_LE(std::abs(clip.y / clip.w), 1.0f);
        EXPECT_GE(clip.z / clip.w, -1.0f);
        EXPECT_LE(clip.z / clip.w, 1.0f);
    }
}

TEST(LoadScene, ProceduralSpec) {
    const SceneDesc d = load_scene("procedural:swatches");
    EXPECT_GT(d.scene.triangle_count(), 1000u);
    EXPECT_FALSE(d.camera_auto);  // the scene brings its camera
    EXPECT_THROW(load_scene("procedural:no_such_scene"), aq::Error);
}

TEST(LoadScene, UnknownKindsAndMissingFiles) {
    EXPECT_THROW(load_scene(out_path("nothing_here.json")), aq::Error);
    const std::string txt = write_scene("scene.txt", "hello");
    EXPECT_THROW(load_scene(txt), aq::Error);
}

// --- errors name the file and the key -----------------------------------------------------------

TEST(SceneFileErrors, UnknownKey) {
    expect_error(write_scene("unknown_key.json", R"({"gltf": ")" + box_path() + R"(", "colour": 1})"), "colour", "unknown key");
    expect_error(write_scene("unknown_camera_key.json", R"({"gltf": ")" + box_path() + R"(", "camera": {"auto": true, "fov": 3}})"),
                 "camera.fov", "unknown key");
    expect_error(write_scene("unknown_rule_key.json",
                             R"({"gltf": ")" + box_path() + R"(", "control": [{"target": "edge.r", "source": "constant", "value": 1, "valeu": 2}]})"),
                 "control[0].valeu", "unknown key");
    expect_error(write_scene("unknown_noise_key.json",
                             R"({"gltf": ")" + box_path() + R"(", "control": [{"target": "edge.r", "source": "noise", "noise": {"freq": 2}}]})"),
                 "control[0].noise.freq", "unknown key");
    expect_error(write_scene("unknown_material_key.json", R"({"gltf": ")" + box_path() + R"(", "materials": {"*": {"dilution": 1}}})"),
                 "materials.*.dilution", "unknown key");
}

TEST(SceneFileErrors, WrongTypes) {
    expect_error(write_scene("bad_width.json", R"({"gltf": ")" + box_path() + R"(", "width": "wide"})"), "width", "integer");
    expect_error(write_scene("bad_eye.json", R"({"gltf": ")" + box_path() + R"(", "camera": {"eye": [0, 1], "target": [0, 0, 0]}})"),
                 "camera.eye", "3 numbers");
    expect_error(write_scene("bad_light.json", R"({"gltf": ")" + box_path() + R"(", "lights": [{"intensity": "bright"}]})"),
                 "lights[0].intensity", "number");
    expect_error(write_scene("bad_dilute.json", R"({"gltf": ")" + box_path() + R"(", "materials": {"*": {"dilute": 7}}})"),
                 "materials.*.dilute", "outside");
    expect_error(write_scene("bad_layout.json", R"({"gltf": ")" + box_path() + R"(", "control_layout": "wc99"})"), "control_layout");
    expect_error(write_scene("bad_target.json",
                             R"({"gltf": ")" + box_path() + R"(", "control": [{"target": "edge.q", "source": "constant", "value": 1}]})"),
                 "control[0].target");
    expect_error(write_scene("bad_source.json", R"({"gltf": ")" + box_path() + R"(", "control": [{"target": "edge.r", "source": "COLOR_0"}]})"),
                 "control[0].source");
    expect_error(write_scene("bad_style.json", R"({"gltf": ")" + box_path() + R"(", "style": {"set": {"edge.width": "x"}}})"),
                 "style.set.edge.width", "number");
    expect_error(write_scene("bad_material.json", R"({"gltf": ")" + box_path() + R"(", "materials": {"NoSuchMaterial": {"dilute": 0.5}}})"),
                 "materials.NoSuchMaterial", "no material");
    expect_error(write_scene("bad_camera_index.json", R"({"gltf": ")" + box_path() + R"(", "camera": 2})"), "camera", "does not exist");
    expect_error(write_scene("not_object.json", R"([1, 2])"), "", "expected an object");
}

TEST(SceneFileErrors, MissingFilesNameThePath) {
    expect_error(write_scene("missing_gltf.json", R"({"gltf": "no/such/model.gltf"})"), "gltf", "no/such/model.gltf");
    expect_error(write_scene("missing_paper.json", R"({"gltf": ")" + box_path() + R"(", "paper": "paper_missing.png"})"), "paper",
                 "paper_missing.png");
    expect_error(write_scene("missing_ctrl_tex.json",
                             R"({"gltf": ")" + box_path() + R"(", "control": [{"target": "edge", "source": "texture", "file": "nope.png"}]})"),
                 "control[0].file", "nope.png");
    expect_error(write_scene("no_model.json", R"({"width": 10})"), "gltf");
}

// A scene file's paper is handed to LoadOptions::paper_known, resolved, before its model loads (the
// CLI decodes the paper meanwhile): a scene whose model is missing has already reported it; a scene
// without a paper never calls it; with both, once, with the path the description holds.
TEST(LoadScene, ThePaperIsKnownBeforeTheModelLoads) {
    const std::string paper = fs::absolute(aq::test::asset("paper/mnpr/rough_default_2k.jpg")).string();
    std::vector<std::string> seen;
    LoadOptions opt;
    opt.paper_known = [&](const std::string& p) { seen.push_back(p); };
    EXPECT_THROW(load_scene(write_scene("paper_then_no_model.json", R"({"gltf": "no/such/model.gltf", "paper": ")" + paper + R"("})"), opt),
                 aq::Error);
    ASSERT_EQ(seen.size(), 1u);
    EXPECT_EQ(fs::weakly_canonical(seen[0]), fs::weakly_canonical(paper));
    seen.clear();
    (void)load_scene(write_scene("model_no_paper.json", R"({"gltf": ")" + box_path() + R"("})"), opt);
    EXPECT_TRUE(seen.empty());
    const SceneDesc d = load_scene(write_scene("model_and_paper.json", R"({"gltf": ")" + box_path() + R"(", "paper": ")" + paper + R"("})"), opt);
    ASSERT_EQ(seen.size(), 1u);
    EXPECT_EQ(seen[0], d.paper);
}

TEST(SceneFileErrors, DeepNestingIsRefused) {
    const int d = 200000;
    const std::string p = write_scene("deep.json", "{\"description\": " + std::string(d, '[') + std::string(d, ']') + "}");
    EXPECT_THROW(load_scene(p), aq::Error);
}

TEST(SceneFileErrors, InvalidJsonNamesTheFile) {
    const std::string p = write_scene("broken.json", R"({"gltf": )");
    try {
        load_scene(p);
        ADD_FAILURE();
    } catch (const aq::Error& e) {
        EXPECT_NE(std::string(e.what()).find("broken.json"), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("invalid JSON"), std::string::npos);
    }
}

// --- control mapping -----------------------------------------------------------------------------

TEST(ControlRules, AttributeNoiseConstantAndMaterialFilter) {
    const std::string p = write_scene("rules.json", R"({
      "gltf": ")" + vc_path() + R"(",
      "control": [
        {"target": "edge.intensity", "source": "COLOR_0.r", "scale": 2, "bias": -1},
        {"target": "pigment.b", "source": "noise", "noise": {"frequency": 3, "amplitude": 0.5, "seed": 9}},
        {"target": "substrate.distortion", "source": "constant", "value": 0.25},
        {"target": "substrate.distortion", "source": "constant", "value": 0.5},
        {"target": "abstraction.b", "source": "constant", "value": 1, "materials": ["no_such_material_name_is_checked"]}
      ]})");
    // The last rule names a material that does not exist: an error naming the key.
    expect_error(p, "control[4].materials", "no material");

    const std::string q = write_scene("rules_ok.json", R"({
      "gltf": ")" + vc_path() + R"(",
      "control": [
        {"target": "edge.intensity", "source": "COLOR_0.r", "scale": 2, "bias": -1},
        {"target": "pigment.b", "source": "noise", "noise": {"frequency": 3, "amplitude": 0.5, "seed": 9}},
        {"target": "substrate.distortion", "source": "constant", "value": 0.25},
        {"target": "substrate.distortion", "source": "constant", "value": 0.5},
        {"target": "abstraction.g", "source": "constant", "value": 3},
        {"target": "abstraction.r", "source": "TEXCOORD_3.x"}
      ]})");
    const SceneDesc d = load_scene(q);
    const Primitive& prim = d.scene.meshes.at(0).primitives.at(0);
    ASSERT_EQ(prim.control[kCtrlEdge].size(), prim.positions.size());
    NoiseField nf;
    nf.frequency = 3.0f;
    nf.amplitude = 0.5f;
    nf.seed = 9;
    for (std::size_t i = 0; i < prim.positions.size(); ++i) {
        EXPECT_FLOAT_EQ(prim.control[kCtrlEdge][i].r, prim.colors[i].r * 2.0f - 1.0f);  // colour = position in [0,1]
        EXPECT_EQ(prim.control[kCtrlEdge][i].g, 0.0f);                                 // unwritten channel
        EXPECT_FLOAT_EQ(prim.control[kCtrlPigment][i].b, noise_field(nf, prim.positions[i]));
        EXPECT_FLOAT_EQ(prim.control[kCtrlSubstrate][i].r, 0.75f);  // rules on one channel add up
        EXPECT_FLOAT_EQ(prim.control[kCtrlAbstraction][i].g, 1.0f); // clamped to [-1, 1]
    }
    // The absent attribute is a warning, not an error.
    bool warned = false;
    for (const auto& w : d.scene.warnings) warned = warned || w.find("TEXCOORD_3") != std::string::npos;
    EXPECT_TRUE(warned);
}

TEST(ControlRules, Wc17LayoutMapsOntoTheWc18Targets) {
    std::array<glm::vec4, kNumControlTargets> w{};
    map_wc17_control({0.2f, 0.4f, 0.6f, 0.5f}, w);
    EXPECT_FLOAT_EQ(w[kCtrlSubstrate].r, 0.2f);
    EXPECT_FLOAT_EQ(w[kCtrlPigment].g, 0.4f);
    EXPECT_FLOAT_EQ(w[kCtrlEdge].r, 0.6f);
    EXPECT_FLOAT_EQ(w[kCtrlAbstraction].b, 0.6f);
    EXPECT_FLOAT_EQ(w[kCtrlPigment].b, 0.0f);  // A = 0.5 is neutral
    map_wc17_control({0, 0, 0, 0.0f}, w);
    EXPECT_FLOAT_EQ(w[kCtrlPigment].b, 1.0f);  // full turbulence: accumulate
    map_wc17_control({0, 0, 0, 1.0f}, w);
    EXPECT_FLOAT_EQ(w[kCtrlPigment].b, -1.0f);  // full fading: dilute to the paper
    map_wc17_control({-3, 7, 0, 0.5f}, w);      // inputs clamped to [0, 1]
    EXPECT_FLOAT_EQ(w[kCtrlSubstrate].r, 0.0f);
    EXPECT_FLOAT_EQ(w[kCtrlPigment].g, 1.0f);

    const std::string p = write_scene("wc17.json", R"({
      "gltf": ")" + vc_path() + R"(",
      "control_layout": "wc17",
      "control": [ {"target": "B", "source": "COLOR_0.b"}, {"target": "distortion", "source": "constant", "value": 0.3} ]})");
    const SceneDesc d = load_scene(p);
    const Primitive& prim = d.scene.meshes.at(0).primitives.at(0);
    for (std::size_t i = 0; i < prim.positions.size(); ++i) {
        EXPECT_FLOAT_EQ(prim.control[kCtrlEdge][i].r, prim.colors[i].b);
        EXPECT_FLOAT_EQ(prim.control[kCtrlAbstraction][i].b, prim.colors[i].b);
        EXPECT_FLOAT_EQ(prim.control[kCtrlSubstrate][i].r, 0.3f);
        EXPECT_FLOAT_EQ(prim.control[kCtrlPigment][i].b, 0.0f);  // A unwritten: neutral 0.5
        EXPECT_FLOAT_EQ(prim.control[kCtrlPigment][i].g, 0.0f);
    }
    expect_error(write_scene("wc17_texture.json", R"({"gltf": ")" + vc_path() +
                                                       R"(", "control_layout": "wc17", "control": [{"target": "edge", "source": "texture", "file": ")" +
                                                       box_path() + R"("}]})"),
                 "control[0].source", "wc18");
}

TEST(ControlRules, ControlTextureIsBoundToTheMaterials) {
    ImageF img(2, 2, 3, 0.0f);
    img.at(1, 0, 0) = 1.0f;
    img.at(0, 1, 1) = 0.5f;
    write_image(out_path("ctrl_tex.png"), img);
    const std::string p = write_scene("ctrl_tex.json", R"({
      "gltf": ")" + vc_path() + R"(",
      "control": [ {"target": "edge", "source": "texture", "file": "ctrl_tex.png"},
                   {"target": "abstraction", "source": "texture", "file": "ctrl_tex.png", "scale": 1, "bias": 0} ]})");
    const SceneDesc d = load_scene(p);
    ASSERT_FALSE(d.scene.materials.empty());
    for (const Material& m : d.scene.materials) {
        const int t = m.wc.control_texture[kCtrlEdge].texture;
        ASSERT_GE(t, 0);
        const Texture& im = d.scene.textures[std::size_t(t)];
        // Default mapping v = 2t - 1, stored as (v + 1) / 2 = t: the file's values.
        EXPECT_FLOAT_EQ(im.texel0(1, 0).x, 1.0f);
        EXPECT_FLOAT_EQ(im.texel0(0, 0).x, 0.0f);
        // scale 1, bias 0: v = t, stored as (t + 1) / 2, so 0 -> 0.5 (neutral after 2t - 1).
        const Texture& ab = d.scene.textures[std::size_t(m.wc.control_texture[kCtrlAbstraction].texture)];
        EXPECT_FLOAT_EQ(ab.texel0(0, 0).x, 0.5f);
        EXPECT_FLOAT_EQ(ab.texel0(1, 0).x, 1.0f);
        EXPECT_EQ(m.wc.control_texture[kCtrlPigment].texture, -1);
    }
}

TEST(SceneFile, CameraLightsStyleAndOverrides) {
    const std::string p = write_scene("full.json", R"({
      "description": "everything",
      "gltf": ")" + box_path() + R"(",
      "scale": 2.0,
      "camera": {"eye": [0, 0, 10], "target": [0, 0, 0], "up": [0, 1, 0], "yfov_deg": 40, "near": 1, "far": 50},
      "lights": [{"direction": [0, 2, 0], "color": [1, 0.5, 0.25], "intensity": 2}],
      "ambient": [0.1, 0.1, 0.1],
      "materials": {"0": {"base_color": [0.2, 0.3, 0.4], "specular": 0.5, "control": {"edge": [0.1, 0.2, 0.3]}, "double_sided": true}},
      "style": {"preset": "wc17", "set": {"edge_darken.intensity": 2.5}, "variant": {"bleed": "naive"}},
      "width": 640, "height": 480, "fps": 12,
      "substrate_color": [0.9, 0.9, 0.8]
    })");
    const SceneDesc d = load_scene(p);
    EXPECT_EQ(d.width, 640);
    EXPECT_EQ(d.height, 480);
    EXPECT_FLOAT_EQ(d.fps, 12.0f);
    EXPECT_EQ(d.style, "wc17");
    EXPECT_DOUBLE_EQ(d.style_set.at("edge_darken.intensity"), 2.5);
    EXPECT_EQ(d.style_variant.at("bleed"), "naive");
    EXPECT_FLOAT_EQ(d.substrate_color.b, 0.8f);
    EXPECT_FALSE(d.camera_auto);
    EXPECT_NEAR(d.camera.yfov, glm::radians(40.0f), 1e-6f);
    EXPECT_FLOAT_EQ(d.camera.znear, 1.0f);
    const glm::vec4 o = d.camera.view * glm::vec4(0, 0, 0, 1);
    EXPECT_NEAR(o.z, -10.0f, 1e-5f);
    ASSERT_EQ(d.scene.lights.size(), 1u);
    EXPECT_NEAR(d.scene.lights[0].direction.y, 1.0f, 1e-6f);  // normalised
    EXPECT_FLOAT_EQ(d.scene.lights[0].intensity, 2.0f);
    EXPECT_FLOAT_EQ(d.scene.ambient.g, 0.1f);
    const Material& m = d.scene.materials.at(0);
    EXPECT_FLOAT_EQ(m.base_color.g, 0.3f);
    EXPECT_FLOAT_EQ(m.base_color.a, 1.0f);
    EXPECT_FLOAT_EQ(m.wc.specular, 0.5f);
    EXPECT_FLOAT_EQ(m.wc.control[kCtrlEdge].z, 0.3f);
    EXPECT_TRUE(m.double_sided);
    EXPECT_NEAR(d.scene.world_bounds().max.x, 1.0f, 1e-6f);  // Box is [-0.5, 0.5], scaled by 2
}

TEST(SceneFile, GltfCameraByIndexFollowsTheModelScale) {
    aq::test::GltfBuilder b;
    const int pa = b.add(aq::test::quad_positions(), aq::test::kFloat, "VEC3", 4);
    b.single_primitive({{"attributes", {{"POSITION", pa}}}, {"mode", 6}, {"material", 0}});
    b.j["materials"] = nlohmann::json::array({{{"name", "flat"}, {"extras", {{"dilute", 0.4}, {"specular", 0.7}, {"author", "x"}}}}});
    b.j["cameras"] = nlohmann::json::array({{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}, {"zfar", 20}}}}});
    b.j["nodes"].push_back({{"camera", 0}, {"translation", {0.5, 0.5, 4}}});
    b.j["scenes"][0]["nodes"] = {0, 1};
    const std::string model = b.write_gltf(out_path("cam_model.gltf"));
    const SceneDesc d = load_scene(write_scene("cam_index.json", R"({"gltf": "cam_model.gltf", "camera": 0, "scale": 3})"));
    EXPECT_FALSE(d.camera_auto);
    EXPECT_FLOAT_EQ(d.camera.yfov, 0.5f);
    EXPECT_NEAR(d.camera.znear, 0.3f, 1e-6f);  // scaled with the model
    EXPECT_NEAR(d.camera.zfar, 60.0f, 1e-4f);
    // The quad's corner (1,1,0) scaled to (3,3,0) is seen from the scaled eye (1.5,1.5,12).
    const glm::vec4 e = d.camera.view * glm::vec4(3, 3, 0, 1);
    EXPECT_NEAR(e.x, 1.5f, 1e-5f);
    EXPECT_NEAR(e.y, 1.5f, 1e-5f);
    EXPECT_NEAR(e.z, -12.0f, 1e-5f);
    // Flat watercolor keys in glTF extras are read; unrelated keys ignored.
    EXPECT_FLOAT_EQ(d.scene.materials.at(0).wc.dilute, 0.4f);
    EXPECT_FLOAT_EQ(d.scene.materials.at(0).wc.specular, 0.7f);
    expect_error(write_scene("cam_index_bad.json", R"({"gltf": "cam_model.gltf", "camera": 1})"), "camera", "does not exist");
}

TEST(FrameBounds, FitsTheBoundingSphereAtAnyAspect) {
    Bounds b;
    b.valid = true;
    b.min = {-1, -2, -3};
    b.max = {5, 1, 0};
    for (float aspect : {0.5f, 1.0f, 16.0f / 9.0f, 3.0f})
        for (glm::vec3 dir : {glm::vec3(0, 0, -1), glm::vec3(1, -1, 0.3f), glm::vec3(0, -1, 0)}) {
            const Camera c = frame_bounds(b, aspect, dir, 0.6f);
            const glm::mat4 proj = glm::perspective(c.yfov, aspect, c.znear, c.zfar);
            for (int k = 0; k < 8; ++k) {
                const glm::vec3 p((k & 1) ? b.max.x : b.min.x, (k & 2) ? b.max.y : b.min.y, (k & 4) ? b.max.z : b.min.z);
                const glm::vec4 clip = proj * c.view * glm::vec4(p, 1.0f);
                ASSERT_GT(clip.w, 0.0f);
                EXPECT_LE(std::abs(clip.x / clip.w), 1.0f) << aspect;
                EXPECT_LE(std::abs(clip.y / clip.w), 1.0f) << aspect;
                EXPECT_LE(std::abs(clip.z / clip.w), 1.0f) << aspect;
            }
        }
    const Camera none = frame_bounds(Bounds{}, 1.0f);
    EXPECT_TRUE(std::isfinite(none.view[3][2]));
}

}  // namespace
// --- LD06 foliage selection ----------------------------------------------------------------------

TEST(SceneFile, FoliageIsSelectedByNameWithItsAbstractionParameters) {
    const SceneDesc d = load_scene((fs::path(aq::test::source_dir()) / "scenes/data/common_tree.json").string());
    ASSERT_TRUE(d.scene.foliage.set);
    int foliage = 0, other = 0;
    for (const Instance& inst : d.scene.instances)
        for (const Primitive& p : d.scene.meshes[std::size_t(inst.mesh)].primitives) {
            const bool f = is_foliage(d.scene, inst, p);
            EXPECT_EQ(f, d.scene.materials[std::size_t(p.material)].name == "Green");
            (f ? foliage : other) += 1;
        }
    EXPECT_GT(foliage, 0);
    EXPECT_GT(other, 0);
    ASSERT_TRUE(d.foliage_threshold.has_value());
    EXPECT_FLOAT_EQ(*d.foliage_threshold, 2.0f);
    EXPECT_FLOAT_EQ(*d.foliage_radius, 0.12f);
}

// A foliage block without names only sets the abstraction's parameters: the default rule still
// selects the foliage; the technique is kept as written.
TEST(SceneFile, FoliageParametersWithoutASelection) {
    const SceneDesc d = load_scene(
        write_scene("foliage_params.json", R"({"gltf": ")" + box_path() + R"(", "foliage": {"T": 3, "technique": "texture"}})"));
    EXPECT_FALSE(d.scene.foliage.set);
    ASSERT_TRUE(d.foliage_threshold.has_value());
    EXPECT_EQ(*d.foliage_threshold, 3.0f);
    ASSERT_TRUE(d.foliage_technique.has_value());
    EXPECT_EQ(*d.foliage_technique, "texture");
}

TEST(SceneFile, FoliageNamesThatMatchNothingAreErrors) {
    expect_error(write_scene("foliage_typo.json", R"({"gltf": ")" + box_path() + R"(", "foliage": {"materials": ["Leavs"]}})"),
                 "foliage.materials[0]", "no material is named 'Leavs'");
    expect_error(write_scene("foliage_empty.json", R"({"gltf": ")" + box_path() + R"(", "foliage": {"materials": [], "T": 3}})"),
                 "foliage", "names no node, mesh or material");
    expect_error(write_scene("foliage_tech.json", R"({"gltf": ")" + box_path() + R"(", "foliage": {"technique": "blobs"}})"),
                 "foliage.technique", "expected");
    expect_error(write_scene("foliage_t.json", R"({"gltf": ")" + box_path() + R"(", "foliage": {"meshes": ["Mesh"], "T": -1}})"),
                 "foliage.T");
}

TEST(SceneFile, LayersGroupPrimitivesWithTheirColours) {
    const SceneDesc d = load_scene(write_scene("layers.json", R"({"gltf": ")" + box_path() + R"(", "layers": [
        {"name": "box", "meshes": ["Mesh"], "color": [0.2, 0.4, 0.6], "dark": [0.1, 0.1, 0.2], "alpha": 0.75}]})"));
    ASSERT_EQ(d.scene.layers.size(), 1u);
    const LayerSpec& l = d.scene.layers[0];
    EXPECT_EQ(l.name, "box");
    EXPECT_EQ(l.meshes, std::vector<std::string>{"Mesh"});
    ASSERT_TRUE(l.color && l.dark && l.alpha);
    EXPECT_FLOAT_EQ(l.color->b, 0.6f);
    EXPECT_FLOAT_EQ(l.dark->b, 0.2f);
    EXPECT_FLOAT_EQ(*l.alpha, 0.75f);
}

TEST(SceneFile, LayerNamesAndColoursAreChecked) {
    expect_error(write_scene("layers_typo.json", R"({"gltf": ")" + box_path() + R"(", "layers": [{"meshes": ["Mesj"]}]})"),
                 "layers[0].meshes[0]", "no mesh is named 'Mesj'");
    expect_error(write_scene("layers_empty.json", R"({"gltf": ")" + box_path() + R"(", "layers": [{"name": "x"}]})"),
                 "layers[0]", "names no node, mesh or material");
    expect_error(write_scene("layers_color.json", R"({"gltf": ")" + box_path() + R"(", "layers": [{"meshes": ["Mesh"], "color": [0.2, 1.5, 0]}]})"),
                 "layers[0].color[1]");
    expect_error(write_scene("layers_alpha.json", R"({"gltf": ")" + box_path() + R"(", "layers": [{"meshes": ["Mesh"], "alpha": -0.1}]})"),
                 "layers[0].alpha");
    expect_error(write_scene("layers_type.json", R"({"gltf": ")" + box_path() + R"(", "layers": {"meshes": ["Mesh"]}})"), "layers");
}

// --- editing the art direction (render --scene-set, the live page) -----------------------------

std::string editable_scene() {
    return write_scene("editable.json", R"({"gltf": ")" + box_path() + R"(",
      "lights": [{"direction": [0, 2, 0], "color": [1, 0.5, 0.25], "intensity": 2}],
      "control": [{"target": "pigment.density", "source": "noise", "noise": {"frequency": 2.0, "seed": 4}}],
      "layers": [{"name": "box", "meshes": ["Mesh"], "color": [0.2, 0.4, 0.6], "dark": [0.1, 0.1, 0.2], "alpha": 0.75}],
      "foliage": {"meshes": ["Mesh"], "T": 50, "radius": 0.1, "relative": true},
      "style": {"preset": "ld06", "set": {"strokes.width": 2}}, "width": 64, "height": 48})");
}

TEST(SceneEdits, TheKnobsAreTheFilesValuesOfArtDirection) {
    const std::vector<SceneKnob> k = scene_knobs(editable_scene());
    std::map<std::string, std::string> kind;
    for (const SceneKnob& x : k) kind[x.pointer] = x.kind;
    EXPECT_EQ(kind.at("/layers/0/color"), "color");
    EXPECT_EQ(kind.at("/layers/0/alpha"), "number");
    EXPECT_EQ(kind.at("/foliage/T"), "number");
    EXPECT_EQ(kind.at("/foliage/relative"), "bool");
    EXPECT_EQ(kind.at("/control/0/noise/seed"), "integer");
    EXPECT_EQ(kind.at("/lights/0/direction"), "vector");
    EXPECT_EQ(kind.at("/lights/0/color"), "color");
    // names, geometry, sizes and the style are not art-direction values
    for (const char* p : {"/gltf", "/layers/0/name", "/layers/0/meshes/0", "/width", "/style/set/strokes.width", "/control/0/target"})
        EXPECT_EQ(kind.count(p), 0u) << p;
    const auto layer = std::find_if(k.begin(), k.end(), [](const SceneKnob& x) { return x.pointer == "/layers/0/color"; });
    EXPECT_EQ(layer->group, "layers[0] box");
    EXPECT_EQ(layer->name, "color");
    EXPECT_EQ(layer->value, "[0.2,0.4,0.6]");
}

TEST(SceneEdits, EditsChangeWhatIsLoaded) {
    const std::string p = editable_scene();
    LoadOptions o;
    o.edits = {parse_scene_edit("/layers/0/color=[0.5,0.25,0.125]"), parse_scene_edit("/foliage/T=60"),
               parse_scene_edit("/lights/0/intensity=0.5"), parse_scene_edit("/foliage/relative=false")};
    const SceneDesc d = load_scene(p, o);
    ASSERT_TRUE(d.scene.layers.at(0).color);
    EXPECT_FLOAT_EQ(d.scene.layers[0].color->g, 0.25f);
    EXPECT_FLOAT_EQ(*d.foliage_threshold, 60.0f);
    EXPECT_FALSE(*d.foliage_relative);
    EXPECT_FLOAT_EQ(d.scene.lights.at(0).intensity, 0.5f);
    const SceneDesc plain = load_scene(p);
    EXPECT_FLOAT_EQ(plain.scene.layers.at(0).color->g, 0.4f);
    EXPECT_FLOAT_EQ(*plain.foliage_threshold, 50.0f);
}

TEST(SceneEdits, TheModelComesFromTheLoaderHook) {
    int calls = 0;
    LoadOptions o;
    o.load_model = [&](const std::string& path, const LoadOptions& lo) {
        ++calls;
        EXPECT_EQ(fs::path(path), fs::path(box_path()).lexically_normal());
        return load_gltf(path, nullptr, lo);
    };
    o.edits = {parse_scene_edit("/layers/0/alpha=0.5")};
    const SceneDesc d = load_scene(editable_scene(), o);
    EXPECT_EQ(calls, 1);
    EXPECT_FLOAT_EQ(*d.scene.layers.at(0).alpha, 0.5f);
}

TEST(SceneEdits, BadEditsAreClearErrors) {
    const std::string p = editable_scene();
    auto error_of = [&](const std::string& spec, const std::string& edit) -> std::string {
        try {
            LoadOptions o;
            o.edits = {parse_scene_edit(edit)};
            load_scene(spec, o);
        } catch (const aq::Error& e) {
            return e.what();
        }
        return "";
    };
    EXPECT_NE(error_of(p, "/gltf=1").find("not an editable value"), std::string::npos);
    EXPECT_NE(error_of(p, "/layers/3/color=[0,0,0]").find("not an editable value"), std::string::npos);
    EXPECT_NE(error_of(p, "/layers/0/color=[0,0]").find("an array of 3 numbers"), std::string::npos);
    EXPECT_NE(error_of(p, R"(/layers/0/color="red")").find("an array of 3 numbers"), std::string::npos);
    EXPECT_NE(error_of(p, "/foliage/T=x").find("a number"), std::string::npos);
    EXPECT_NE(error_of(p, "/control/0/noise/seed=1.5").find("an integer"), std::string::npos);
    EXPECT_NE(error_of(p, "/foliage/relative=1").find("true or false"), std::string::npos);
    // in range only as the file itself: the reader's checks name the key
    EXPECT_NE(error_of(p, "/layers/0/color=[0.2,1.5,0]").find("layers[0].color[1]"), std::string::npos);
    EXPECT_NE(error_of(p, "/foliage/T=-1").find("foliage.T"), std::string::npos);
    // only scene files have art direction to edit
    EXPECT_NE(error_of(box_path(), "/foliage/T=1").find("a bare model or procedural scene has none"), std::string::npos);
    EXPECT_NE(error_of("procedural:swatches", "/foliage/T=1").find("a bare model or procedural scene has none"), std::string::npos);
    for (const char* bad : {"", "foliage/T=1", "/foliage/T", "/foliage/T="})
        EXPECT_THROW(parse_scene_edit(bad), aq::Error) << bad;
}

TEST(SceneFile, TextureSpaceStrokesAreCopiedOntoEveryLeafOfTheirMaterial) {
    // BoxTextured: six faces of four vertices each (six "leaves"), material "Texture", UVs in [0, 1].
    const std::string box = fs::absolute(aq::test::asset("gltf/BoxTextured/BoxTextured.gltf")).string();
    const SceneDesc plain = load_scene(box);
    const SceneDesc d = load_scene(write_scene("uv_strokes.json", R"({"gltf": ")" + box + R"(", "strokes": [
        {"uv": [[0.1, 0.1], [0.3, 0.2], [0.45, 0.4]], "material": "Texture", "hatching": true}]})"));
    ASSERT_FALSE(d.scene.strokes.empty());
    EXPECT_LE(d.scene.strokes.size(), 6u);  // at most one copy per face
    const Bounds b = plain.scene.world_bounds();
    const float half = 0.5f * (b.max.x - b.min.x);
    for (const Stroke& s : d.scene.strokes) {
        EXPECT_TRUE(s.light_dependent);
        ASSERT_EQ(s.normals.size(), s.points.size());
        ASSERT_GE(s.points.size(), 2u);
        for (std::size_t i = 0; i < s.points.size(); ++i) {
            const glm::vec3 q = s.points[i] - 0.5f * (b.min + b.max);
            // on the box's surface: one coordinate at +-half, along the (unit) normal
            const glm::vec3 n = s.normals[i];
            EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
            EXPECT_NEAR(glm::dot(q, n), half, 1e-4f * half) << "point " << i << " is not on the face its normal names";
            EXPECT_LE(std::max({std::abs(q.x), std::abs(q.y), std::abs(q.z)}), half * (1 + 1e-5f));
        }
    }
    expect_error(write_scene("uv_nomat.json", R"({"gltf": ")" + box + R"(", "strokes": [{"uv": [[0.1, 0.1], [0.2, 0.2]], "material": "Nope"}]})"),
                 "strokes[0].material", "no material is named 'Nope'");
    expect_error(write_scene("uv_nowhere.json", R"({"gltf": ")" + box + R"(", "strokes": [{"uv": [[5, 5], [6, 6]], "material": "Texture"}]})"),
                 "strokes[0]", "lands on no leaf");
    expect_error(write_scene("uv_both.json", R"({"gltf": ")" + box + R"(", "strokes": [{"uv": [[0.1, 0.1], [0.2, 0.2]], "points": [[0,0,0],[1,1,1]], "material": "Texture"}]})"),
                 "strokes[0]", "not both");
    {
        // One long stroke over a material with many triangles: 50,000 points x the procedural
        // tree's 4,320 leaf triangles = 2.16e8 tests, refused by the work bound before placing.
        std::string pts;
        for (int q = 0; q < 50000; ++q) pts += std::string(q ? "," : "") + "[7, 7]";
        expect_error(write_scene("uv_work.json", R"({"procedural": "tree", "strokes": [{"uv": [)" + pts +
                                                     R"(], "material": "leaves"}]})"),
                     "strokes[0]", "(point, triangle) pairs");
    }
    expect_error(write_scene("uv_short.json", R"({"gltf": ")" + box + R"(", "strokes": [{"uv": [[0.1, 0.1]], "material": "Texture"}]})"),
                 "strokes[0].uv");
}

TEST(SceneFile, MaterialsNameAnIntensityTexture) {
    const std::string tex = fs::absolute(aq::test::asset("paper/mnpr/rough_default_2k.jpg")).string();
    const SceneDesc d = load_scene(write_scene("intensity.json", R"({"gltf": ")" + box_path() +
                                                                     R"(", "materials": {"*": {"intensity_texture": ")" + tex + R"("}}})"));
    bool any = false;
    for (const Material& m : d.scene.materials) {
        ASSERT_GE(m.intensity_texture.texture, 0);
        EXPECT_FALSE(d.scene.textures[std::size_t(m.intensity_texture.texture)].empty());
        any = true;
    }
    EXPECT_TRUE(any);
    expect_error(write_scene("intensity_missing.json", R"({"gltf": ")" + box_path() +
                                                           R"(", "materials": {"*": {"intensity_texture": "nope.png"}}})"),
                 "materials.*.intensity_texture");
}

// Issue 47 item 6: one decode budget for everything a render decodes, whatever names it. A file
// named by several material keys is decoded once; two files over the budget are refused before the
// second is decoded.
TEST(SceneFile, IntensityTexturesShareTheRendersDecodeBudget) {
    const std::string tex = fs::absolute(aq::test::asset("paper/mnpr/rough_default_2k.jpg")).string();  // 2048^2: 64 MiB as RGBA float
    const std::string other = fs::absolute(aq::test::asset("paper/ambientcg_Paper001/Paper001_2K-JPG_Roughness.jpg")).string();
    LoadOptions opt;
    opt.texture_budget_bytes = std::size_t(100) << 20;  // one such texture, not two
    const SceneDesc d = load_scene(write_scene("intensity_twice.json", R"({"gltf": ")" + box_path() +
                                                                            R"(", "materials": {"*": {"intensity_texture": ")" + tex +
                                                                            R"("}, "0": {"intensity_texture": ")" + tex + R"("}}})"),
                                   opt);
    EXPECT_EQ(d.scene.textures.size(), 1u) << "the same file was decoded more than once";
    EXPECT_EQ(d.scene.decode_budget.bytes_left, (std::size_t(100) << 20) - (std::size_t(64) << 20));
    try {
        load_scene(write_scene("intensity_two_files.json", R"({"gltf": ")" + box_path() +
                                                               R"(", "materials": {"*": {"intensity_texture": ")" + tex +
                                                               R"("}, "0": {"intensity_texture": ")" + other + R"("}}})"),
                   opt);
        ADD_FAILURE() << "two 64 MiB decodes fit a 100 MiB budget";
    } catch (const aq::Error& e) {
        EXPECT_NE(std::string(e.what()).find("the images one render decodes"), std::string::npos) << e.what();
    }
}

TEST(SceneFile, HandMadeStrokesAreReadInOrder) {
    const SceneDesc d = load_scene(write_scene("strokes.json", R"({"gltf": ")" + box_path() + R"(", "strokes": [
        {"points": [[0, 0, 0], [1, 0, 0], [1, 1, 0]], "normals": [[0, 0, 1], [0, 0, 1], [0, 0, 1]], "hatching": true},
        {"points": [[0, 0, 1], [0, 2, 1]]}]})"));
    ASSERT_EQ(d.scene.strokes.size(), 2u);
    EXPECT_EQ(d.scene.strokes[0].points.size(), 3u);
    EXPECT_EQ(d.scene.strokes[0].normals.size(), 3u);
    EXPECT_TRUE(d.scene.strokes[0].light_dependent);
    EXPECT_EQ(d.scene.strokes[1].points[1], glm::vec3(0, 2, 1));
    EXPECT_FALSE(d.scene.strokes[1].light_dependent);
    expect_error(write_scene("strokes_short.json", R"({"gltf": ")" + box_path() + R"(", "strokes": [{"points": [[0, 0, 0]]}]})"),
                 "strokes[0].points", "at least two");
    expect_error(write_scene("strokes_normals.json", R"({"gltf": ")" + box_path() +
                                                         R"(", "strokes": [{"points": [[0, 0, 0], [1, 0, 0]], "normals": [[0, 0, 1]]}]})"),
                 "strokes[0].normals", "one [x, y, z] per point");
}

}  // namespace aq::scene
