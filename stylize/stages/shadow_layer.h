// stylize/stages/shadow_layer.h — stage "shadow_layer": LD06 §3.3 "another watercolor layer that
// is semi-transparently painted onto the existing watercolor layers": the shadow intensity map
// (raster pass "shadow") shaded as a wash (layer_wash's blur and wash_amount) in one colour and
// glazed over the picture (glaze_px). Variants: the glaze, multiplicative (default) or over.
#pragma once

#include "core/exec.h"
#include "core/image.h"
#include "stylize/stage.h"
#include "stylize/stages/layer_wash.h"

namespace aq::stylize {

//! Ours: a cool blue-grey shadow, half transparent.
inline constexpr glm::vec3 kShadowColor{0.45f, 0.5f, 0.68f};
inline constexpr float kShadowAlpha = 0.5f;

//! The shadow's wash is softer than a layer's (ours): a wider smoothstep (a wet-on-wet shadow) and
//! half the edge darkening.
inline constexpr float kShadowWashWidth = 0.3f;
inline constexpr float kShadowWashEdge = 0.5f;

struct ShadowLayerParams {
    LayerWashParams wash = {kGaussianBlurRadius, kGaussianBlurSigma,
                            {kWashKappa, kShadowWashWidth, kShadowWashEdge, kWashBorder, kWashGranulation, true, false}};
    glm::vec3 color = kShadowColor;
    float alpha = kShadowAlpha;
};

//! dst (4 channels, color's size): color glazed with the shadow wash. shadow: one channel, any
//! size; paper: the prepared paper of color's size or null.
void shadow_layer(ImageF& dst, const ImageF& color, const ImageF& shadow, const ImageF* paper, const ShadowLayerParams& p,
                  bool multiplicative, const Exec& ex = {}, float paper_spread = -1.0f);  // layer_wash's paper_spread

void register_shadow_layer(Registry& r);

}  // namespace aq::stylize
