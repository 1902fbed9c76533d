// stylize/stages/edge_darken.h — stage "edge_darken" (spec §4.6): darkens colour at edges with the
// colour transmittance model C^(1+d).
//
// Variants:
//   dog   WC17 §3.3 eq. 8: I_ed = I_cb^(1 + Ctrl * max_rgb(I_b - I)), I_b the half-resolution 5x5
//         (sigma 1) blur of the colour (stage edge_blur, variant wc17), upsampled bilinearly with
//         pixel centres at +0.5 and clamp to edge (GL texture() + GL_LINEAR on a full-screen quad).
//         The DoG edge is "modulated through a smoothstep" to remove artefacts at colour gradients;
//         the paper gives no numbers, we use E_m = E * smoothstep(kDogSmoothLow, kDogSmoothHigh, E).
//   rgbd  WC18 §3.1 (MNPR gradientEdgesWC): C_dark = C^(1 + E_d), E_d = E_b * intensity * (1 + ci)
//         * sat(5 |C - Cs|) * sat(1 - 3 bleed), ci = ctrl.edge.r (x5 where positive), E_b the
//         blurred Sobel edges (stage edge_blur, variant wc18).
//         Ours (parameter `crowding`, 0 = the paper): E_d / (1 + crowding * N), N the local mean of
//         the edges (optional input `crowd`: a wide Gaussian of E_b). Pigment gathers at the edge of
//         a wash; a crown of a thousand leaves painted as one wash has one outline, not a thousand:
//         where edges crowd each darkens less, an isolated silhouette keeps its strength.
#pragma once

#include <glm/glm.hpp>

#include "core/exec.h"
#include "core/image.h"
#include "stylize/stage.h"
#include "stylize/stages/toolkit.h"

namespace aq::stylize {

//! MNPR gradientEdgesWC: a positive painted intensity is amplified x5 (negative ones are not).
inline constexpr float kEdgeCtrlPositiveGain = 5.0f;
//! MNPR: edges fade out where the colour is within 1/5 (RGB distance) of the substrate colour.
inline constexpr float kEdgeSubstrateFade = 5.0f;
//! MNPR: edges fade out where the bleeding mask exceeds 1/3.
inline constexpr float kEdgeBleedFade = 3.0f;
//! Our smoothstep thresholds for the WC17 DoG edge (the paper names the smoothstep, not its edges).
inline constexpr float kDogSmoothLow = 0.0f;
inline constexpr float kDogSmoothHigh = 0.1f;

struct EdgeDarkenDogParams {
    float intensity = 1.0f;   //!< global multiplier of Ctrl * E [0, 50]
    float ctrl_bias = 1.0f;   //!< Ctrl = ctrl_bias + ctrl.edge.r: 1 darkens unpainted areas, 0 = eq. 8 literal [0, 1]
    float smooth_low = kDogSmoothLow;    //!< smoothstep lower edge on E [0, 1]
    float smooth_high = kDogSmoothHigh;  //!< smoothstep upper edge on E [0, 1], > smooth_low
};

struct EdgeDarkenRgbdParams {
    float intensity = 1.0f;  //!< global edge intensity (MNPR gEdgeIntensity, default 1) [0, 50]
    float crowding = 0.0f;   //!< ours: E_d / (1 + crowding * crowd) [0, 50]; 0 = WC18 as printed
};

//! WC17 eq. 8 exponent 1 + Ctrl * E_m for one pixel (exactly 1 where nothing darkens).
inline float edge_darken_dog_exponent(glm::vec4 c, glm::vec3 blurred, float ctrl, const EdgeDarkenDogParams& p) {
    const glm::vec3 dog = blurred - glm::vec3(c);
    const float e = std::max(0.0f, std::max(dog.x, std::max(dog.y, dog.z)));
    float t = (e - p.smooth_low) / (p.smooth_high - p.smooth_low);
    t = sat(t);
    const float em = e * (t * t * (3.0f - 2.0f * t));
    const float k = std::max(0.0f, p.ctrl_bias + ctrl) * p.intensity * em;
    return k > 0.0f ? 1.0f + k : 1.0f;  // no edge (or NaN control): unchanged
}

//! WC17 eq. 8 for one pixel: c = I_cb (RGBA), blurred = I_b (RGB), ctrl = ctrl.edge.r.
inline glm::vec4 edge_darken_dog_px(glm::vec4 c, glm::vec3 blurred, float ctrl, const EdgeDarkenDogParams& p) {
    const float d = edge_darken_dog_exponent(c, blurred, ctrl, p);
    if (d == 1.0f) return c;
    return {pow_c(c.x, d), pow_c(c.y, d), pow_c(c.z, d), c.w};
}

//! WC18 §3.1 / MNPR exponent 1 + E_d for one pixel (exactly 1 where nothing darkens). Selects
//! only, no branches: rows evaluate it in a vectorised loop (edge_darken.cpp).
inline float edge_darken_rgbd_exponent(float r, float g, float b, float edge, float ci, float bleed, float crowd,
                                       glm::vec3 substrate, const EdgeDarkenRgbdParams& p) {
    ci = ci > 0.0f ? ci * kEdgeCtrlPositiveGain : ci;
    float e = edge * p.intensity * (1.0f + ci);
    e /= 1.0f + p.crowding * crowd;  // crowding 0: divided by exactly 1
    const float dr = r - substrate.x, dg = g - substrate.y, db = b - substrate.z;
    e *= sat(std::sqrt(dr * dr + dg * dg + db * db) * kEdgeSubstrateFade);
    e *= sat(1.0f - bleed * kEdgeBleedFade);
    return e > 0.0f ? 1.0f + e : 1.0f;  // E_d <= 0 or NaN: C^1 = C
}
inline float edge_darken_rgbd_exponent(glm::vec4 c, float edge, float ci, float bleed, float crowd, glm::vec3 substrate,
                                       const EdgeDarkenRgbdParams& p) {
    return edge_darken_rgbd_exponent(c.x, c.y, c.z, edge, ci, bleed, crowd, substrate, p);
}

//! WC18 §3.1 / MNPR for one pixel: edge = blurred Sobel edge, ci = ctrl.edge.r, bleed = bleeding
//! mask, crowd = local mean of the edges (0 without the `crowd` input).
inline glm::vec4 edge_darken_rgbd_px(glm::vec4 c, float edge, float ci, float bleed, float crowd, glm::vec3 substrate,
                                     const EdgeDarkenRgbdParams& p) {
    const float d = edge_darken_rgbd_exponent(c, edge, ci, bleed, crowd, substrate, p);
    if (d == 1.0f) return c;
    return {pow_c(c.x, d), pow_c(c.y, d), pow_c(c.z, d), c.w};
}

//! WC17 DoG edge darkening. color: 4 ch (I_cb, also the I of the DoG); blurred: >= 3 ch, full or half size
//! (upsampled to color's size by resample convention, clamp to edge); ctrl_edge: >= 1 ch (R used),
//! same size as color. dst: (re)allocated to color's size, 4 ch.
//! The rule between the DoG variant's parameters (throws aq::Error): smooth_high > smooth_low.
void check_edge_darken_dog_params(const EdgeDarkenDogParams& p);

void edge_darken_dog(ImageF& dst, const ImageF& color, const ImageF& blurred, const ImageF& ctrl_edge,
                     const EdgeDarkenDogParams& p,  const Exec& ex = {});

//! WC18 RGBD edge darkening. color: 4 ch; edges: >= 1 ch (channel 0 = blurred edges), same size;
//! ctrl_edge: >= 1 ch (R); bleed: optional, 4 ch (alpha = bleeding mask, as stage "bleed" writes
//! it) full or half size (resampled like the DoG blur), or 1 ch; absent = no bleeding. crowd:
//! optional, >= 1 ch (channel 0), color's size or smaller (resampled like the bleeding mask): the
//! local mean of the edges; absent = 0.
void edge_darken_rgbd(ImageF& dst, const ImageF& color, const ImageF& edges, const ImageF& ctrl_edge,
                      const ImageF* bleed, const ImageF* crowd, glm::vec3 substrate, const EdgeDarkenRgbdParams& p,
                      const Exec& ex = {});

//! The fast schedule of the DoG variant (edge_darken.schedule.cpp), which edge_darken_dog runs for
//! Traversal::Fast after its checks, with dst allocated: the reference's bytes.
void edge_darken_dog_fast(ImageF& dst, const ImageF& color, const ImageF& blurred, const ImageF& ctrl_edge,
                          const EdgeDarkenDogParams& p, const Exec& ex);
//! The fast schedule of the RGBD variant (edge_darken.schedule.cpp), which edge_darken_rgbd runs for
//! Traversal::Fast after its checks, with dst allocated (dst may be color: in place): the
//! reference's bytes.
void edge_darken_rgbd_fast(ImageF& dst, const ImageF& color, const ImageF& edges, const ImageF& ctrl_edge,
                           const ImageF* bleed, const ImageF* crowd, glm::vec3 substrate, const EdgeDarkenRgbdParams& p,
                           const Exec& ex);

void register_edge_darken(Registry& r);

}  // namespace aq::stylize
