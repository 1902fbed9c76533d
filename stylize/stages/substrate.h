// stylize/stages/substrate.h — stages "substrate_distort" (spec §4.9) and "substrate_light"
// (spec §4.10): the paper's relief moving and shading the painted image. The paper comes from
// Globals::paper (3 ch, MNPR layout: R,G = normal x,y encoded n*0.5 + 0.5, B = height); without a
// paper both stages behave as on the flat paper (normal (0,0,1)).
//
// substrate_distort / mnpr  WC17 §3.3 ("sampling the color values at UVs that have been shifted by
//   the surface inclinations") in MNPR's form (quadSubstrate substrateDistortionFrag):
//   n = tex.rg * 2 - 1, k = sat(ctrl.substrate.r + 0.2), offset = n * distortion * 5k pixels; the
//   colour is sampled bilinearly at the pixel centre + offset (pixel centres at +0.5, named border),
//   unless the destination lies in front: depth(x) - depth(x + offset) > 0.01 on normalised depth
//   (MNPR's one-sided test; `both_sides` also refuses destinations behind).
// substrate_light / wc18    WC18 §4.2 eq. 5: Id = 1 - (1 - L.(r N)) ds, with MNPR's light
//   L = (sin t, cos t, tilt / 89) (t = direction in degrees), N = (-r (tex.r - 0.5), -r (tex.g - 0.5), 1)
//   (MNPR substrateLightingFrag; the roughness r scales the relief, i.e. N.xy), output C * Id.
// substrate_light / mnpr    the same with MNPR's curve Id = 1 - (1 - N.L)^2 ds.
#pragma once

#include <cmath>

#include <glm/glm.hpp>

#include "core/exec.h"
#include "core/image.h"
#include "stylize/stage.h"
#include "stylize/stages/toolkit.h"

namespace aq::stylize {

//! MNPR: the painted distortion control is offset by 0.2 so unpainted areas distort a little.
inline constexpr float kDistortCtrlBias = 0.2f;
//! MNPR: lerp(0, distortion, 5 k): 5 pixels per unit distortion at full control.
inline constexpr float kDistortPixelsPerUnit = 5.0f;
//! MNPR: destinations more than this (normalised depth) in front of the pixel are not sampled.
inline constexpr float kDistortDepthThreshold = 0.01f;
//! MNPR substrate lighting defaults.
inline constexpr float kSubstrateLightDirection = 180.0f;  //!< degrees
inline constexpr float kSubstrateLightTilt = 45.0f;        //!< degrees, L.z = tilt / 89
inline constexpr float kSubstrateShading = 0.5f;           //!< ds

struct SubstrateDistortParams {
    float distortion = 1.0f;                          //!< global distortion (MNPR gSubstrateDistortion) [0, 10]
    float depth_threshold = kDistortDepthThreshold;   //!< normalised depth [0, 1]
    bool both_sides = false;                          //!< refuse destinations behind as well as in front
    int border = 0;                                   //!< taps outside the image: 0 clamp, 1 mirror
};

struct SubstrateLightParams {
    float direction = kSubstrateLightDirection;  //!< light direction in degrees [0, 360]
    float tilt = kSubstrateLightTilt;            //!< light tilt in degrees [0, 89]
    float shading = kSubstrateShading;           //!< ds [0, 1]
    float roughness = 1.0f;                      //!< r: relief scale of the normal [0, 5]
    //! Divide Id by the flat paper's Id (N = (0, 0, 1)), so the paper keeps its substrate colour on
    //! average and only the relief shades it (docs/look.md: eq. 5 read literally lights the flat
    //! paper at 1 - (1 - tilt/89) ds = 0.753, a grey paper). false = eq. 5 as printed.
    bool normalize = false;
};

//! Offset in pixels for one pixel (0 for the flat paper exactly; never NaN, |offset| <= 5*distortion).
inline glm::vec2 substrate_offset(float tex_r, float tex_g, float ctrl, const SubstrateDistortParams& p) {
    auto c11 = [](float v) { return v > -1.0f ? (v < 1.0f ? v : 1.0f) : -1.0f; };  // NaN -> -1
    const float nx = c11(tex_r * 2.0f - 1.0f), ny = c11(tex_g * 2.0f - 1.0f);
    float k = ctrl + kDistortCtrlBias;
    k = k > 0.0f ? (k < 1.0f ? k : 1.0f) : 0.0f;  // sat, NaN -> 0
    const float s = p.distortion * kDistortPixelsPerUnit * k;
    return {nx * s, ny * s};
}

//! Light vector of eq. 5 (MNPR form).
inline glm::vec3 substrate_light_dir(const SubstrateLightParams& p) {
    const float rad = p.direction * 3.14159265f / 180.0f;
    return {std::sin(rad), std::cos(rad), p.tilt / 89.0f};
}

//! 1 / Id of the flat paper (N = (0, 0, 1)) when p.normalize, else 1; Id_flat <= 0 (no light on
//! the flat paper) gives 1.
inline float substrate_light_norm(glm::vec3 l, const SubstrateLightParams& p, bool squared) {
    if (!p.normalize) return 1.0f;
    const float u = 1.0f - l.z;
    const float flat = 1.0f - (squared ? u * u : u) * p.shading;
    return flat > 0.0f ? 1.0f / flat : 1.0f;
}

//! Diffuse factor Id for one pixel (squared = MNPR's curve).
inline float substrate_light_factor(float tex_r, float tex_g, glm::vec3 l, float roughness, float shading,
                                    bool squared) {
    const float nx = -(tex_r - 0.5f) * roughness, ny = -(tex_g - 0.5f) * roughness;
    const float nl = nx * l.x + ny * l.y + l.z;
    const float u = 1.0f - nl;
    return 1.0f - (squared ? u * u : u) * shading;
}

//! color: 4 ch; depth: 1 ch normalised (stage adjust's "depth"), same size; ctrl_substrate: >= 1 ch
//! (R); paper: 3 ch same size or nullptr (flat: the identity). dst (re)allocated.
void substrate_distort(ImageF& dst, const ImageF& color, const ImageF& depth, const ImageF& ctrl_substrate,
                       const ImageF* paper, const SubstrateDistortParams& p,  const Exec& ex = {});

//! color: 4 ch; paper: 3 ch same size or nullptr (flat). squared: MNPR curve instead of eq. 5.
void substrate_light(ImageF& dst, const ImageF& color, const ImageF* paper, const SubstrateLightParams& p,
                     bool squared,  const Exec& ex = {});

void register_substrate(Registry& r);

}  // namespace aq::stylize
