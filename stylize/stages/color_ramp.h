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

//! Ours: the four layers' object ramps until the scene's layers fill them (RampColorSource::Layers):
//! earth, leaf green, sand and sky, each unlit end 0.55 x its lit colour.
inline constexpr ColorRampLayer kDefaultRampLayers[4] = {
    {{0.45f, 0.35f, 0.25f}, {0.2475f, 0.1925f, 0.1375f}, kRampAlpha, 1.0f},
    {{0.35f, 0.55f, 0.25f}, {0.1925f, 0.3025f, 0.1375f}, kRampAlpha, 1.0f},
    {{0.55f, 0.5f, 0.35f}, {0.3025f, 0.275f, 0.1925f}, kRampAlpha, 1.0f},
    {{0.45f, 0.5f, 0.6f}, {0.2475f, 0.275f, 0.33f}, kRampAlpha, 1.0f},
};

//! Where the render job takes the layer colours from before a pipeline's, a scene file's and
//! --set's values (StageVariant::scene_params; docs/ld06.md "Layers").
enum class RampColorSource {
    Given,    //!< the parameters as given
    Layers,   //!< the scene's layers first..first+3
    Foliage,  //!< the foliage layer in all four (particle layers, told apart by their tone)
};

struct ColorRampParams {
    RampColorSource source = RampColorSource::Layers;
    int first = 0;  //!< the scene layer of layer[0] with RampColorSource::Layers
    RampColors hue;
    ColorRampLayer layer[4] = {kDefaultRampLayers[0], kDefaultRampLayers[1], kDefaultRampLayers[2], kDefaultRampLayers[3]};
};

//! dst[k]: 4 channels of lighting's size (layer k's RGB, alpha); lighting: one channel in [0, 1].
void color_ramp(ImageF* const dst[4], const ImageF& lighting, const ColorRampParams& p, const Exec& ex = {});

//! One row of one layer's ramp: n lighting values `t` to n RGBA pixels `o` (ramp_color, alpha) —
//! the fast schedule's row kernel, also run by glaze's fused schedule (glaze.h RampInput), which
//! computes the ramp rows it reads instead of reading color_ramp's images.
void color_ramp_row(const float* t, int n, const ColorRampLayer& layer, const RampColors& hue, float* o);

//! The ramps a compiled color_ramp step's parameter values describe (what the stage runs with).
ColorRampParams color_ramp_params(const ParamValues& pv);

void register_color_ramp(Registry& r);

}  // namespace aq::stylize
