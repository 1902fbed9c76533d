// tests/stylize/scene_inputs_test.cpp — the parameter values stages take from the scene
// (StageVariant::scene_params, stylize::apply_scene_inputs): the automatic depth range of adjust,
// the LD06 layer colours of color_ramp, and the image-space turbulence declaration.
#include <gtest/gtest.h>

#include "core/image.h"
#include "scenes/scene.h"
#include "stylize/pipeline.h"
#include "stylize/scene_inputs.h"

namespace aq::stylize {
namespace {

double param(const Pipeline& p, const std::string& id, const std::string& name) {
    for (std::size_t i = 0; i < p.steps.size(); ++i)
        if ((p.steps[i].id.empty() ? p.steps[i].stage : p.steps[i].id) == id) return resolve_step(p, i).params.at(name);
    ADD_FAILURE() << "no step " << id;
    return 0;
}

TEST(SceneInputs, AFramedCameraGivesAdjustItsDepthRangeAPlacedOneDoesNot) {
    const scene::Scene sc;
    Pipeline framed = load_pipeline("wc18"), placed = load_pipeline("wc18");
    const double near0 = param(placed, "adjust", "depth_near"), far0 = param(placed, "adjust", "depth_far");
    apply_scene_inputs(framed, SceneInputs(sc, std::make_pair(2.5f, 40.0f)));
    apply_scene_inputs(placed, SceneInputs(sc, std::nullopt));
    EXPECT_EQ(param(framed, "adjust", "depth_near"), 2.5);
    EXPECT_EQ(param(framed, "adjust", "depth_far"), 40.0);
    EXPECT_EQ(param(placed, "adjust", "depth_near"), near0);
    EXPECT_EQ(param(placed, "adjust", "depth_far"), far0);
    // A later value (the scene file's style values, --set) overrides the scene's.
    set_param(framed, "adjust.depth_near=3");
    EXPECT_EQ(param(framed, "adjust", "depth_near"), 3.0);
}

TEST(SceneInputs, AnOutOfRangeSceneValueNamesWhereItCameFrom) {
    const scene::Scene sc;
    Pipeline p = load_pipeline("wc18");
    try {
        apply_scene_inputs(p, SceneInputs(sc, std::make_pair(-1.0f, 40.0f)));
        FAIL() << "a negative near plane was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("the automatic depth range of the framed camera"), std::string::npos) << e.what();
    }
}

TEST(SceneInputs, LayerColoursFillTheRampsThatAskForThem) {
    scene::Scene sc;
    for (int k = 0; k < 2; ++k) {
        scene::LayerSpec s;
        s.name = "layer" + std::to_string(k);
        s.color = glm::vec3(0.1f + 0.2f * float(k), 0.3f, 0.7f);
        s.alpha = 0.5f;
        sc.layers.push_back(s);
    }
    Pipeline p = load_pipeline("ld06");
    const double alpha0 = param(p, "ramp", "alpha0"), color2 = param(p, "ramp", "color2_r");
    const double particle_color = param(p, "particle_ramp", "color0_r");
    apply_scene_inputs(p, SceneInputs(sc, std::nullopt));
    // source 1, first 0: layers 0 and 1 fill ramps 0 and 1 (colour, dark = colour x the dark tone,
    // alpha = the layer's x the step's); ramps 2 and 3 have no layer and keep their values.
    EXPECT_FLOAT_EQ(float(param(p, "ramp", "color0_r")), 0.1f);
    EXPECT_FLOAT_EQ(float(param(p, "ramp", "color1_r")), 0.3f);
    EXPECT_FLOAT_EQ(float(param(p, "ramp", "color1_b")), 0.7f);
    EXPECT_FLOAT_EQ(float(param(p, "ramp", "dark1_g")), 0.3f * scene::kLayerDarkTone);
    EXPECT_FLOAT_EQ(float(param(p, "ramp", "alpha0")), float(0.5 * alpha0));
    EXPECT_EQ(param(p, "ramp", "color2_r"), color2);
    // source 2 takes the foliage layer, and this scene has no foliage: unchanged.
    EXPECT_EQ(param(p, "particle_ramp", "color0_r"), particle_color);
}

TEST(SceneInputs, OnlyAnImageSpaceDensityStepTakesTheTurbulenceFromTheMaterial) {
    EXPECT_TRUE(has_image_space_turbulence(load_pipeline("wc18")));
    EXPECT_TRUE(has_image_space_turbulence(load_pipeline("mnpr")));
    EXPECT_FALSE(has_image_space_turbulence(load_pipeline("wc17")));
    EXPECT_FALSE(has_image_space_turbulence(load_pipeline("wc16")));
}

}  // namespace
}  // namespace aq::stylize
