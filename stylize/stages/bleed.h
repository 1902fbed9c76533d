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

#include <vector>

#include "core/exec.h"
#include "core/image.h"
#include "core/lanes.h"
#include "stylize/stage.h"
#include "stylize/stages/toolkit.h"

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

//! The stage's working planes at the working resolution: R, G, B, the bleeding control C and
//! the depth Z.
struct BleedPlanes {
    int w = 0, h = 0;
    std::vector<float> p[5];  // R, G, B, C, Z
    //! Sizes the planes; contents are unspecified (every pass writes all of its output). Reusing
    //! the same Planes across calls avoids re-faulting ~100 MB of fresh pages per 1080p frame.
    void alloc(int w_, int h_, int n) {
        w = w_;
        h = h_;
        for (int k = 0; k < n; ++k) p[k].resize(std::size_t(w) * h);
    }
};

//! The filter: radius, normalised Gaussian weights, MNPR's scope per tap, the depth threshold.
struct BleedKernel {
    int r;
    std::vector<float> w;      // W[a + r], normalised
    std::vector<float> scope;  // |a| / r (MNPR filterScope)
    float t;
};

//! The bleeding rule, written once over lanes (F = float, the mask a bool; F = v8f, the mask a
//! v8i): whether the tap d bleeds into the pixel s. zst = zs - t (the pixel's depth minus the
//! threshold), cs / cd the controls, scope |a| / r (MNPR filterScope). Naive: always; WC17
//! (JointBilateral): the tap's control where the pixel is behind it, else the pixel's; MNPR also
//! needs max(cd, cs) >= scope.
template <BleedRule R, class F>
inline auto bleeds(F cs, F cd, F zst, F zd, float scope) {
    using M = decltype(cs > cd);
    if constexpr (R == BleedRule::Naive) {
        (void)cs, (void)cd, (void)zst, (void)zd, (void)scope;
        return lanes::mask_all<M>();
    } else {
        const M behind = zst > zd;
        M b = ((cd > 0.0f) & behind) | ((cs > 0.0f) & lanes::mask_not(behind));
        if constexpr (R == BleedRule::Mnpr) b = b & ((cd >= scope) | (cs >= scope));
        return b;
    }
}

//! The fast schedule (bleed.schedule.cpp) of the two 1-D passes, src -> tmp (horizontal) -> dst
//! (vertical): rows, eight pixels per register, taps innermost; the reference passes' bytes.
void bleed_passes_fast(BleedRule rule, const BleedPlanes& src, BleedPlanes& tmp, BleedPlanes& dst, const BleedKernel& k,
                       Border border, const Exec& ex);
//! The half-resolution planes where both axes halve exactly (ResampleAxis::pairs: output pixel x
//! reads source pixels 2x and 2x + 1, row y rows 2y and 2y + 1): per plane
//!   top = s(2x, 2y) + (s(2x + 1, 2y) - s(2x, 2y)) * tx,  bot likewise on row 2y + 1,
//!   out = top + (bot - top) * ty
//! — RowResampler's operations in its order, so the values of the tabled path (which stays the
//! reference traversal's) — eight outputs per register, the colour's and control's RGBA pixels
//! transposed into planes on the way: no row buffers, no de-interleaving pass, one read of each
//! source row. zd null: the depth plane is 0.
void bleed_halve_into_planes(BleedPlanes& src, const float* cd, const float* kd, const float* zd, int w,
                             const toolkit::ResampleAxis& ax, const toolkit::ResampleAxis& ay, const Exec& ex);

void register_bleed(Registry& r);

}  // namespace aq::stylize
