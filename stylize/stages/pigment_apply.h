// stylize/stages/pigment_apply.h — stage "pigment_apply" (spec §4.8): how pigment settles on the
// paper — granulation (pigment accumulating in the paper's valleys) and dry-brush (pigment only on
// the peaks). The paper height H is the B channel of the prepared paper (Globals::paper).
//
// Variants:
//   wc17  WC17 §3.3 eq. 9: I_g = I (I - P_iv) + (1 - I) I^(1 + Ctrl d P_iv), P_iv = 1 - Hr the
//         inverted paper. Read literally, the subtractive term removes P_iv even where Ctrl = 0,
//         which contradicts "Ctrl ... art-direct[s] the pigment density at the valleys"; by default
//         we subtract the same controlled amount k = Ctrl d P_iv used in the exponent, so that
//         Ctrl = 0 is the identity (parameter `literal` restores I - P_iv). Parameter
//         `paper_texture` t keeps the printed uncontrolled term at a chosen strength: the subtracted
//         amount becomes k + t P_iv, applied on the bare paper too (alpha < 0.01, Ctrl = 0), where
//         eq. 9 reduces to I (1 - t P_iv): the paper texture visible everywhere, as in WC17's
//         figures (docs/look.md). t = 0 (the stage default) is the controlled reading above.
//   wc18  WC18 §4.1 eq. 1-4 in MNPR's form (quadPigmentApplication pigmentApplicationWCFrag):
//         Hr = (H - 0.5) r + 0.5 (eq. 1); dry-brush where Hr < -a (a = ctrl.pigment.g, negative =
//         dry-brush): C + sat(t_dry |Hr + a|) (Cs - C) (eq. 2 case 1); otherwise granulation:
//         d_g = |a| + d_min (d_min = 0.2), d_g = mix(d_g, 5 d_g, L) (eq. 3), H_iv = 1 - (0.2 Hr + 0.8),
//         d_a = 1 + d_g H_iv D (eq. 4), C^(d_a) (eq. 2 case 2), faded out near the substrate colour
//         (MNPR: mix(C, C^d_a, sat(5 |C - Cs|))). Pixels with alpha < 0.01 are left unchanged (MNPR).
#pragma once

#include <glm/glm.hpp>

#include "core/exec.h"
#include "core/image.h"
#include "stylize/stage.h"
#include "stylize/stages/toolkit.h"

namespace aq::stylize {

//! WC18 §4.1: "d_min = 0.2 the default amount of granulation".
inline constexpr float kGranulationDefault = 0.2f;
//! WC18 eq. 3: brighter colours get up to x5 the granulation density.
inline constexpr float kGranulationLuminanceGain = 5.0f;
//! WC18 §4.1: heightmap "reduced, shifted and inverted": H_iv = 1 - (Hr * 0.2 + 0.8).
inline constexpr float kGranulationHeightScale = 0.2f;
inline constexpr float kGranulationHeightShift = 0.8f;
//! MNPR gPigmentDensity default (WC18's global density D).
inline constexpr float kPigmentDensity = 5.0f;
//! MNPR gDryBrushThreshold default (WC18's t_dry).
inline constexpr float kDryBrushThreshold = 5.0f;
//! MNPR: pigment application skips pixels whose alpha is below this (no painted surface).
inline constexpr float kPigmentAlphaMask = 0.01f;
//! MNPR: granulation fades out within 1/5 (RGB distance) of the substrate colour.
inline constexpr float kPigmentSubstrateFade = 5.0f;

struct PigmentApplyWc17Params {
    float density = 1.0f;    //!< d of eq. 9 [0, 10]
    float roughness = 1.0f;  //!< paper roughness r: Hr = (H - 0.5) r + 0.5 [0, 5]
    bool literal = false;    //!< subtract P_iv as printed (true) or Ctrl d P_iv (false, identity at Ctrl = 0)
    //! t: strength of eq. 9's uncontrolled subtractive term, k + t P_iv, also on the bare paper
    //! (docs/look.md) [0, 1]. 0 = off (identity at Ctrl = 0); ignored when `literal`.
    float paper_texture = 0.0f;
};

struct PigmentApplyWc18Params {
    float density = kPigmentDensity;             //!< D of eq. 4 [0, 20]
    float dry_brush_threshold = kDryBrushThreshold;  //!< t_dry of eq. 2 [0, 100]
    float roughness = 1.0f;                      //!< r of eq. 1 (the prepared paper already has the global roughness) [0, 5]
    float granulation_min = kGranulationDefault;  //!< d_min [0, 1]
};

//! WC17 eq. 9 amounts for one pixel: the exponent 1 + k and the subtracted amount (k + t P_iv, or
//! P_iv when literal); `apply` false where the pixel is left unchanged (alpha mask without paper
//! texture, or nothing to subtract and not literal). Uncovered pixels (alpha < 0.01) get only the
//! paper texture term (their control is 0).
struct PigmentWc17Prep {
    float d = 1.0f, sub = 0.0f;
    bool apply = false;
};

inline PigmentWc17Prep pigment_apply_wc17_prepare(glm::vec4 c, float height, float ctrl,
                                                  const PigmentApplyWc17Params& p) {
    const bool covered = c.w >= kPigmentAlphaMask;
    if (!covered && (p.literal || !(p.paper_texture > 0.0f))) return {};
    const float hr = (height - 0.5f) * p.roughness + 0.5f;
    const float piv = 1.0f - hr;
    const float k = covered ? std::max(ctrl, 0.0f) * p.density * piv : 0.0f;
    const float tex = p.paper_texture * piv;
    if (!p.literal && k == 0.0f && tex == 0.0f) return {};  // Ctrl = 0, no texture: exactly unchanged
    return {1.0f + k, p.literal ? piv : k + tex, true};
}

//! I_g = sat(I (I - sub) + (1 - I) I^(1 + k)) for one channel, pw = I^(1 + k).
inline float pigment_apply_wc17_channel(float i, float sub, float pw) {
    return sat(i * (i - sub) + (1.0f - i) * pw);
}

//! WC17 eq. 9 for one pixel: c RGBA, height H in [0,1], ctrl = ctrl.pigment.g (negative values
//! clamp to 0: WC17's granulation control is in [0, 1]). Output clamped to [0, 1] per channel.
inline glm::vec4 pigment_apply_wc17_px(glm::vec4 c, float height, float ctrl, const PigmentApplyWc17Params& p) {
    const PigmentWc17Prep q = pigment_apply_wc17_prepare(c, height, ctrl, p);
    if (!q.apply) return c;
    return {pigment_apply_wc17_channel(c.x, q.sub, pow_c(c.x, q.d)),
            pigment_apply_wc17_channel(c.y, q.sub, pow_c(c.y, q.d)),
            pigment_apply_wc17_channel(c.z, q.sub, pow_c(c.z, q.d)), c.w};
}

//! WC18 eq. 1-4 but the three powers, for a covered pixel: what the reference
//! (pigment_apply_wc18_px) and the fast schedule's chunks (pigment_apply.schedule.cpp, which calls
//! it over arrays and so lets GCC vectorise it) both compute, written once.
struct PigmentWc18Terms {
    float dry;      //!< hr + a: < 0 where the paper lies below the dry-brush level (eq. 2, case 1)
    glm::vec3 dry_brushed;  //!< the colour there: mixed towards the substrate (eq. 2, case 1)
    float da;       //!< eq. 4 exponent of |C| where the pixel granulates (eq. 2, case 2)
    float fade;     //!< MNPR substrate fade: how much of |C|^(d_a) is blended in
};

inline PigmentWc18Terms pigment_apply_wc18_terms(glm::vec3 rgb, float height, float a, glm::vec3 substrate,
                                                 const PigmentApplyWc18Params& p) {
    const float hr = (height - 0.5f) * p.roughness + 0.5f;  // eq. 1
    const float dry = hr + a;
    const float t = sat(-dry * p.dry_brush_threshold);
    float dg = std::fabs(a) + p.granulation_min;
    dg = mix(dg, dg * kGranulationLuminanceGain, luminance(rgb));  // eq. 3
    const float hiv = 1.0f - (hr * kGranulationHeightScale + kGranulationHeightShift);
    return {dry, mix(rgb, substrate, t), 1.0f + dg * hiv * p.density,  // eq. 4
            sat(length3(rgb - substrate) * kPigmentSubstrateFade)};
}

//! WC18 eq. 1-4 for one pixel: c RGBA, height H, a = ctrl.pigment.g, substrate colour Cs.
inline glm::vec4 pigment_apply_wc18_px(glm::vec4 c, float height, float a, glm::vec3 substrate,
                                       const PigmentApplyWc18Params& p) {
    if (!(c.w >= kPigmentAlphaMask)) return c;
    const glm::vec3 rgb(c);
    const PigmentWc18Terms q = pigment_apply_wc18_terms(rgb, height, a, substrate, p);
    if (q.dry < 0.0f) return {q.dry_brushed, c.w};
    const glm::vec3 g(pow_c(std::fabs(c.x), q.da), pow_c(std::fabs(c.y), q.da), pow_c(std::fabs(c.z), q.da));
    return {mix(rgb, g, q.fade), c.w};
}

//! color: 4 ch; ctrl_pigment: >= 2 ch (G used), same size; paper: 3 ch (B = height) same size, or
//! nullptr for the flat paper (height 0.5). dst (re)allocated to color's size.
void pigment_apply_wc17(ImageF& dst, const ImageF& color, const ImageF& ctrl_pigment, const ImageF* paper,
                        const PigmentApplyWc17Params& p,  const Exec& ex = {});
void pigment_apply_wc18(ImageF& dst, const ImageF& color, const ImageF& ctrl_pigment, const ImageF* paper,
                        glm::vec3 substrate, const PigmentApplyWc18Params& p, 
                        const Exec& ex = {});

//! The checked inputs both variants read: the colour, the pigment control's application channel
//! and the paper height (flat without a paper).
struct PigmentInputs {
    View<const glm::vec4> c;
    toolkit::Plane ctrl, height;
};

//! The fast schedules (pigment_apply.schedule.cpp), which the variants run for Traversal::Fast
//! after their checks, with the output allocated: the references' bytes. in_place: o is the
//! colour's image (uncovered pixels are not written).
void pigment_apply_wc17_fast(const View<glm::vec4>& o, const PigmentInputs& in, const PigmentApplyWc17Params& p,
                             const Exec& ex);
void pigment_apply_wc18_fast(const View<glm::vec4>& o, const PigmentInputs& in, bool in_place, glm::vec3 substrate,
                             const PigmentApplyWc18Params& p, const Exec& ex);

void register_pigment_apply(Registry& r);

}  // namespace aq::stylize
