// stylize/stages/bleed.h — stage "bleed": the blurred colour B and the (expanded) bleeding mask
// that bleed_blend mixes in (spec §4.4 "Bleeding").
//
// Variants:
//   naive            WC16 (NPAR 2016, slides "Color bleeding"): 21x21 separable Gaussian of the whole
//                    colour image; the mask is the painted bleeding control, unexpanded.
//   joint_bilateral  WC17 §3.3 Algorithm 1: 21 taps, sigma 20, depth threshold T, the two rules
//                    ("bled pixels should not leak from un-bled foreground pixels"; "bled pixels
//                    should bleed into/from un-bled background pixels"); the H pass expands the
//                    control mask (Algorithm 1, last line) and the V pass uses the expanded mask
//                    ("Compute another pass with a vertical kernel using the modified control
//                    image mask"). At half resolution as published (WC17 §3.3 "the resolution of
//                    these intermediates is half the size").
//   mnpr             MNPR quadSeparable colorBleeding: full resolution, r = 10, sigma = 2r, a tap a is
//                    considered only when max(ctrl_d, ctrl_s) >= |a| / r, T = 0.0002.
//
// Output "bleed": 4 channels, rgb = B, a = bleeding mask (expanded for the bilateral variants).
// Its size is the working resolution (half: ceil(w/2) x ceil(h/2)); bleed_blend upsamples it.
#pragma once

#include "core/exec.h"
#include "core/image.h"
#include "stylize/stage.h"

namespace aq::stylize {

inline constexpr int kBleedTaps = 21;                    //!< WC17 Algorithm 1 input: "size = 21"
inline constexpr int kBleedRadius = (kBleedTaps - 1) / 2;  //!< i in [-10 : 10] (Algorithm 1, line 2)
inline constexpr float kBleedSigma = 20.0f;              //!< WC17 Algorithm 1 input: "sigma = 20"
//! Depth threshold T on normalised depth. WC17 leaves T unspecified; 0.0002 is MNPR's
//! gBleedingThreshold, used for both bilateral variants.
inline constexpr float kBleedDepthThreshold = 0.0002f;

enum class BleedRule {
    Naive,           //!< every tap bleeds (plain Gaussian)
    JointBilateral,  //!< WC17 Algorithm 1
    Mnpr,            //!< Algorithm 1 + MNPR's control scope max(ctrl_d, ctrl_s) >= |a|/r
};

struct BleedParams {
    int radius = kBleedRadius;                     //!< taps = 2r + 1 [1, 40]
    float sigma = kBleedSigma;                     //!< Gaussian sigma in (working-resolution) pixels [0.1, 100]
    float depth_threshold = kBleedDepthThreshold;  //!< T on normalised depth [0, 1]
    bool half_res = false;                         //!< run at ceil(w/2) x ceil(h/2) (WC17)
    Border border = Border::Clamp;                 //!< taps outside the image (GL clamp-to-edge)
};

//! One 1-D pass of Algorithm 1 for output pixel s and tap a (destination d), "delta" form:
//!   out = s + sum_a W[a] * (bleed(a) ? d - s : 0)
//! which equals Algorithm 1's sum_a W[a] * (bleed ? I(x+a) : I(x)) for normalised W, and leaves
//! un-bled pixels exactly unchanged. bleed(a):
//!   sourceBehind = (Z_s - T) > Z_d                                  (Algorithm 1, "source is behind")
//!   bleed = (C_d > 0 and sourceBehind) or (C_s > 0 and not sourceBehind)   (the two rules)
//! The mask channel is filtered with the same selection (the expanded mask: a pixel that took a
//! bled neighbour's colour also takes its control value; MNPR carries it in alpha).
//!
//! color: 4 channels (alpha ignored); depth: 1 channel normalised; ctrl_abstraction: 4 channels,
//! bleeding in B (spec §1). All the same size. dst is allocated at the working resolution.
void bleed(ImageF& dst, const ImageF& color, const ImageF& depth, const ImageF& ctrl_abstraction, BleedRule rule,
           const BleedParams& p, const Exec& ex = {});

void register_bleed(Registry& r);

}  // namespace aq::stylize
