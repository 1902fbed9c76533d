// stylize/stages/substrate_distort.h — stage "substrate_distort" (spec §4.9): the paper's relief
// moving the painted image. The paper comes from Globals::paper (3 ch, MNPR layout: R,G = normal
// x,y encoded n*0.5 + 0.5, B = height); without a paper the stage behaves as on the flat paper
// (normal (0,0,1): the identity).
//
// substrate_distort / mnpr  WC17 §3.3 ("sampling the color values at UVs that have been shifted by
//   the surface inclinations") in MNPR's form (quadSubstrate substrateDistortionFrag):
//   n = tex.rg * 2 - 1, k = sat(ctrl.substrate.r + 0.2), offset = n * distortion * 5k pixels; the
//   colour is sampled bilinearly at the pixel centre + offset (pixel centres at +0.5, named border),
//   unless the destination lies in front: depth(x) - depth(x + offset) > 0.01 on normalised depth
//   (MNPR's one-sided test; `both_sides` also refuses destinations behind).
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

#include "core/exec.h"
#include "core/image.h"
#include "stylize/stage.h"

namespace aq::stylize {

//! MNPR: the painted distortion control is offset by 0.2 so unpainted areas distort a little.
inline constexpr float kDistortCtrlBias = 0.2f;
//! MNPR: lerp(0, distortion, 5 k): 5 pixels per unit distortion at full control.
inline constexpr float kDistortPixelsPerUnit = 5.0f;
//! MNPR: destinations more than this (normalised depth) in front of the pixel are not sampled.
inline constexpr float kDistortDepthThreshold = 0.01f;
struct SubstrateDistortParams {
    float distortion = 1.0f;                          //!< global distortion (MNPR gSubstrateDistortion) [0, 10]
    float depth_threshold = kDistortDepthThreshold;   //!< normalised depth [0, 1]
    bool both_sides = false;                          //!< refuse destinations behind as well as in front
    Border border = Border::Clamp;                    //!< taps outside the image
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

//! Reach of the taps in pixels: |offset| <= 5 * distortion, the bilinear footprint one more, and
//! one of margin for the float rounding of the sample position. Also the stage's row halo.
inline int substrate_distort_reach(const SubstrateDistortParams& p) {
    const float maxoff = std::max(0.0f, p.distortion) * kDistortPixelsPerUnit;
    return int(std::min(std::ceil(maxoff), 1.0e6f)) + 2;
}

//! color: 4 ch; depth: 1 ch normalised (stage adjust's "depth"), same size; ctrl_substrate: >= 1 ch
//! (R); paper: 3 ch same size or nullptr (flat: the identity). dst (re)allocated.
void substrate_distort(ImageF& dst, const ImageF& color, const ImageF& depth, const ImageF& ctrl_substrate,
                       const ImageF* paper, const SubstrateDistortParams& p,  const Exec& ex = {});

//! The fast schedule (substrate_distort.schedule.cpp), which substrate_distort runs for
//! Traversal::Fast after its checks, with dst allocated: the reference's bytes.
void substrate_distort_fast(ImageF& dst, const ImageF& color, const ImageF& depth, const ImageF& ctrl_substrate,
                            const ImageF* paper, const SubstrateDistortParams& p, const Exec& ex);

void register_substrate_distort(Registry& r);

}  // namespace aq::stylize
