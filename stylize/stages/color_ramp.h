// stylize/stages/color_ramp.h — stage "color_ramp": LD06 §3.2 colour ramps indexed by the
// lighting map (Gooch et al. 1998): one hue-shifting ramp for the scene (cool to warm by default,
// any two colours) and one object ramp per layer (its colour to a darker tone), each layer with an
// alpha. Output: for each of four layers an RGBA map (ramp colour, alpha) at every lighting-map
// pixel (ramp0..ramp3), read by "glaze". The per-pixel maths is
// stylize/stages/wash.h ramp_color.
//
// The layer colours are parameters, so a pipeline, --set and scene-file style values can set them
// and a manifest records them. `source` tells the render job where to fill them from before those
// overrides (docs/ld06.md "Layers"): 0 = as given, 1 = the scene's layers first..first+3
// (scenes/layers.h: the scene file's "layers", else one per material), 2 = the foliage layer in
// all four (the particle layers, told apart by their tone).
#pragma once

#include "core/exec.h"
#include "core/image.h"
#include "stylize/stage.h"
#include "stylize/stages/wash.h"

namespace aq::stylize {

//! Ours: a layer's ramp alpha (the paper's ramps carry an alpha "describing the transparency").
inline constexpr float kRampAlpha = 0.85f;

struct ColorRampLayer {
    glm::vec3 color{0.5f}, dark{0.275f};
    float alpha = kRampAlpha, tone = 1.0f;
};

struct ColorRampParams {
    RampColors hue;
    ColorRampLayer layer[4];
};

//! dst[k]: 4 channels of lighting's size (layer k's RGB, alpha); lighting: one channel in [0, 1].
void color_ramp(ImageF* const dst[4], const ImageF& lighting, const ColorRampParams& p, const Exec& ex = {});

//! One row of one layer's ramp: n lighting values `t` to n RGBA pixels `o` (ramp_color, alpha) —
//! the fast schedule's row kernel, also run by glaze's fused schedule (glaze.h RampInput), which
//! computes the ramp rows it reads instead of reading color_ramp's images.
void color_ramp_row(const float* t, int n, const ColorRampLayer& layer, const RampColors& hue, float* o);

//! The ramps a compiled color_ramp step's parameter values describe (what the stage runs with).
ColorRampParams color_ramp_params(const ParamValues& pv);

//! The parameter table's fields (names: docs via `aquarelle stages color_ramp`).
struct ColorRampTable {
    int source = 1, first = 0;
    float cool_r = 0.0f, cool_g = 0.0f, cool_b = kRampCoolWarm, warm_r = kRampCoolWarm, warm_g = kRampCoolWarm, warm_b = 0.0f;
    float cool_mix = 0.8f, warm_mix = 1.0f, keep_hue = 1.0f;
    float color0_r = 0.45f;
    float color0_g = 0.35f;
    float color0_b = 0.25f;
    float dark0_r = 0.2475f;
    float dark0_g = 0.1925f;
    float dark0_b = 0.1375f;
    float alpha0 = kRampAlpha;
    float tone0 = 1.0f;
    float color1_r = 0.35f;
    float color1_g = 0.55f;
    float color1_b = 0.25f;
    float dark1_r = 0.1925f;
    float dark1_g = 0.3025f;
    float dark1_b = 0.1375f;
    float alpha1 = kRampAlpha;
    float tone1 = 1.0f;
    float color2_r = 0.55f;
    float color2_g = 0.5f;
    float color2_b = 0.35f;
    float dark2_r = 0.3025f;
    float dark2_g = 0.275f;
    float dark2_b = 0.1925f;
    float alpha2 = kRampAlpha;
    float tone2 = 1.0f;
    float color3_r = 0.45f;
    float color3_g = 0.5f;
    float color3_b = 0.6f;
    float dark3_r = 0.2475f;
    float dark3_g = 0.275f;
    float dark3_b = 0.33f;
    float alpha3 = kRampAlpha;
    float tone3 = 1.0f;
};

void register_color_ramp(Registry& r);

}  // namespace aq::stylize
