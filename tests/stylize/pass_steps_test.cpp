// tests/stylize/pass_steps_test.cpp — raster passes declared as data (LD06): pipeline files mix
// "pass" and "stage" steps, passes are swapped and tuned like stages (--variant, --set), and a
// pipeline with passes refuses to run without a scene.
#include <string>

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "core/hash.h"
#include "raster/pass.h"
#include "stylize/pipeline.h"
#include "tests/test_support.h"

namespace aq::stylize {
namespace {

using test::error_of;

// Depth from the light, blurred; the camera's shadow intensity from it (LD06 §3.3).
const char* kShadowPipeline = R"({
  "name": "shadow_only", "output": "ld06.shadow",
  "steps": [
    {"pass": "depth", "id": "light_depth", "params": {"view": 1, "scale": 0.5}, "out": {"depth": "ld06.light_depth"}},
    {"stage": "gaussian_blur", "params": {"radius": 3, "sigma": 1.5},
     "in": {"image": "ld06.light_depth"}, "out": {"blurred": "ld06.light_depth.blurred"}},
    {"pass": "shadow", "params": {"scale": 0.75}}
  ]
})";

scene::Scene two_quads() {
    scene::Scene s;
    s.materials.emplace_back();
    s.materials[0].double_sided = true;
    for (auto [y, h] : {std::pair{0.0f, 2.0f}, std::pair{1.0f, 0.5f}}) {
        scene::Primitive p;
        p.positions = {{-h, y, -h}, {-h, y, h}, {h, y, h}, {h, y, -h}};
        p.normals.assign(4, glm::vec3(0, 1, 0));
        p.indices = {0, 1, 2, 0, 2, 3};
        scene::Mesh m;
        m.primitives.push_back(p);
        s.meshes.push_back(m);
        scene::Instance inst;
        inst.mesh = int(s.meshes.size()) - 1;
        inst.object_id = std::uint32_t(s.meshes.size());
        s.instances.push_back(inst);
    }
    s.lights.push_back({glm::vec3(0, 1, 0), glm::vec3(1), 1.0f});
    return s;
}

TEST(PassSteps, APipelineMixesPassesAndStagesAndRunsOnAScene) {
    const Pipeline p = parse_pipeline(kShadowPipeline, "shadow.json");
    ASSERT_EQ(p.steps.size(), 3u);
    EXPECT_TRUE(p.steps[0].pass);
    EXPECT_FALSE(p.steps[1].pass);
    const CompiledPipeline c = compile_pipeline(p);
    EXPECT_TRUE(c.has_passes);
    EXPECT_TRUE(c.external.empty()) << "reads no G-buffer target";

    const scene::Scene sc = two_quads();
    scene::Camera cam;
    cam.view = glm::lookAt(glm::vec3(0, 0.6f, 4), glm::vec3(0), glm::vec3(0, 1, 0));
    const raster::PassScene ps = raster::make_pass_scene(sc, cam, 160, 120);
    std::string hash;
    for (int threads : {1, 2}) {
        Targets t;
        RunOptions o;
        o.exec = Exec::fast(threads);
        o.scene = &ps;
        run_pipeline(c, t, o);
        const ImageF& light = t.get("ld06.light_depth");
        EXPECT_EQ(light.width(), 80);   // square: 0.5 * max(160, 120)
        EXPECT_EQ(light.height(), 80);
        const ImageF& shadow = t.get("ld06.shadow");
        EXPECT_EQ(shadow.width(), 120);  // 0.75 * 160 x 0.75 * 120
        EXPECT_EQ(shadow.height(), 90);
        EXPECT_EQ(t.get("paper").width(), 160) << "the paper is prepared at the output size";
        if (hash.empty()) hash = sha256_hex(shadow);
        else EXPECT_EQ(sha256_hex(shadow), hash) << threads << " threads";
        float sum = 0;
        for (int y = 0; y < 90; ++y)
            for (int x = 0; x < 120; ++x) sum += shadow.at(x, y, 0);
        EXPECT_GT(sum, 50.0f) << "the occluder casts a shadow on the ground";
    }
}

TEST(PassSteps, PassesAreSwappedAndTunedLikeStages) {
    Pipeline p = parse_pipeline(kShadowPipeline, "shadow.json");
    EXPECT_EQ(compile_pipeline(p).steps[2].variant->key(), "shadow/blurred") << "the default variant";
    set_variant(p, "shadow=binary");
    set_param(p, "shadow.beta=0.1");
    set_param(p, "light_depth.scale=0.25");
    const CompiledPipeline c = compile_pipeline(p);
    EXPECT_EQ(c.steps[2].variant->key(), "shadow/binary");
    EXPECT_EQ(c.steps[2].params.at("beta"), 0.1);
    EXPECT_EQ(c.steps[0].params.at("scale"), 0.25);
    EXPECT_NE(error_of([&] { set_param(p, "shadow.beta=3"); }).find("outside"), std::string::npos);
    EXPECT_NE(error_of([&] { set_variant(p, "shadow=nope"); }).find("nope"), std::string::npos);
}

TEST(PassSteps, BadStepsAndMissingScenesAreClearErrors) {
    const std::string both = error_of([] {
        parse_pipeline(R"({"steps": [{"stage": "gaussian_blur", "pass": "depth"}]})", "x.json");
    });
    EXPECT_NE(both.find("either a \"stage\""), std::string::npos) << both;
    EXPECT_NE(both.find("x.json"), std::string::npos) << both;
    const std::string unknown = error_of([] { parse_pipeline(R"({"steps": [{"pass": "teleport"}]})", "x.json"); });
    EXPECT_NE(unknown.find("steps[0].pass"), std::string::npos) << unknown;
    EXPECT_NE(unknown.find("teleport"), std::string::npos) << unknown;
    // A stage name given as a pass (and the reverse) is unknown in that registry.
    EXPECT_NE(error_of([] { parse_pipeline(R"({"steps": [{"pass": "gaussian_blur"}]})", "x.json"); }), "(no error)");
    EXPECT_NE(error_of([] { parse_pipeline(R"({"steps": [{"stage": "depth"}]})", "x.json"); }), "(no error)");

    const CompiledPipeline c = compile_pipeline(parse_pipeline(kShadowPipeline, "shadow.json"));
    Targets t;
    const std::string no_scene = error_of([&] { run_pipeline(c, t, {}); });
    EXPECT_NE(no_scene.find("shadow.json"), std::string::npos) << no_scene;
    EXPECT_NE(no_scene.find("raster passes, which need a scene"), std::string::npos) << no_scene;
}

// The scene's hand-made strokes reach the strokes pass through the render's PassScene.
TEST(PassSteps, SceneStrokesAreDrawnByTheStrokesPass) {
    scene::Scene sc = two_quads();
    sc.strokes.push_back({{{-1.5f, 0.01f, 1.0f}, {1.5f, 0.01f, 1.0f}}, {}, false});
    scene::Camera cam;
    cam.view = glm::lookAt(glm::vec3(0, 3, 4), glm::vec3(0), glm::vec3(0, 1, 0));
    const raster::PassScene ps = raster::make_pass_scene(sc, cam, 120, 90);
    ASSERT_EQ(ps.strokes, &sc.strokes);
    const CompiledPipeline c = compile_pipeline(parse_pipeline(R"({"output": "ld06.strokes", "steps": [
        {"pass": "strokes", "variant": "binary", "params": {"contours": false, "fade_near": 1, "width": 30},
         "in": {"depth_map": "far"}}]})", "strokes.json"));
    Targets t;
    t.set("far", ImageF(120, 90, 1, 1.0f));
    RunOptions o;
    o.scene = &ps;
    run_pipeline(c, t, o);
    float sum = 0;
    const ImageF& s = t.get("ld06.strokes");
    for (int y = 0; y < s.height(); ++y)
        for (int x = 0; x < s.width(); ++x) sum += s.at(x, y, 0);
    EXPECT_GT(sum, 200.0f) << "the scene's stroke was drawn (5 px wide, ~75 px long)";
}

}  // namespace
}  // namespace aq::stylize
