// stylize/stages/gaps_overlaps.h — stage "gaps_overlaps" (spec §4.7): WC18 §3.2 Algorithm 1.
//
// Variant wc18, in MNPR's form (quadGapsOverlaps gapsOverlapsFrag) with the paper's loop bounds:
// only pixels with alpha > 0.1, bleeding mask < 0.01 and extended edge E_e > 0.1 (paper: 0.2) are
// touched. p = ctrl.edge.b * m (m = 5 steps, paper and MNPR). G = normalize(Sobel-like gradient of
// E_e over the 3x3 neighbourhood: d/du = (r + (tr + br)/2) - (l + (tl + bl)/2), same for v).
//   Overlaps (p > 0.1): for i = 1..m while i <= p: C_n = colour at x + i G (bilinear); if
//     |C_n - C| > 0.33 (RGBA distance; paper "RGBD" 0.5): unless C_n is within 0.1 of the substrate,
//     C = mixRYB(C, C_n) (ryb.h); stop. If all m steps found nothing (the gradient did not converge),
//     C = mixRYB(C, colour at x - G) (Algorithm 1 lines 22-26).
//   Gaps (p < -0.1): if E_e > 2/m (MNPR's "direct edge"; the paper tests the unextended edge > 0.7)
//     the pixel becomes a gap; else for i = 1..m while i <= |p|: if E_e(x + i G) > 1/m: gap; stop.
//   A gap writes the substrate colour, or (transparent_gaps) keeps the colour and writes alpha 0
//   ("transparent gaps are obtained by zeroing the output color alpha channel").
#pragma once

#include <glm/glm.hpp>

#include "core/exec.h"
#include "core/image.h"
#include "stylize/stage.h"
#include "stylize/stages/toolkit.h"

namespace aq::stylize {

inline constexpr int kGapsOverlapsSteps = 5;              //!< m: WC18 "m = 5 in our experiments" (MNPR gGORadius 5)
inline constexpr float kGoColorDifference = 0.33f;        //!< MNPR (paper: 0.5 in RGBD)
inline constexpr float kGoSubstrateProximity = 0.1f;      //!< MNPR: no overlap with the substrate colour
inline constexpr float kGoAlphaThreshold = 0.1f;          //!< MNPR: only painted pixels
inline constexpr float kGoBleedThreshold = 0.01f;         //!< MNPR: not where colours bleed
inline constexpr float kGoEdgeThreshold = 0.1f;           //!< MNPR (paper: 0.2)
inline constexpr float kGoCtrlThreshold = 0.1f;           //!< MNPR: |p| must exceed this

struct GapsOverlapsParams {
    int steps = kGapsOverlapsSteps;                  //!< m, the widest gap/overlap in pixels [1, 16]
    float color_difference = kGoColorDifference;     //!< [0, 2]
    float substrate_proximity = kGoSubstrateProximity;  //!< [0, 2]
    float alpha_threshold = kGoAlphaThreshold;       //!< [0, 1]
    float bleed_threshold = kGoBleedThreshold;       //!< [0, 1]
    float edge_threshold = kGoEdgeThreshold;         //!< [0, 1]
    float mix_brightness = 1.0f;                     //!< brightness scale of the RYB mix (MNPR 0.9) [0, 2]
    bool transparent_gaps = false;                   //!< gaps zero alpha instead of painting the substrate
    Border border = Border::Clamp;                   //!< taps outside the image
};

//! color: 4 ch; edges_ext: >= 1 ch (channel 0 = extended edges E_e), same size; ctrl_edge: >= 3 ch
//! (B = gaps/overlaps), same size; bleed: optional, 1 ch or 4 ch (alpha), full or half size (resampled,
//! clamp to edge). dst (re)allocated to color's size, 4 ch.
void gaps_overlaps(ImageF& dst, const ImageF& color, const ImageF& edges_ext, const ImageF& ctrl_edge,
                   const ImageF* bleed, glm::vec3 substrate, const GapsOverlapsParams& p, 
                   const Exec& ex = {});

void register_gaps_overlaps(Registry& r);

}  // namespace aq::stylize
