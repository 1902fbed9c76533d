// stylize/stages/wash.h — the per-pixel maths of LD06's watercolor layers (../shared/spec/ld06.md
// §4, reconstructed; docs/ld06.md "Layers"), written once and used by the stages layer_wash,
// shadow_layer, glaze and stroke_ink and restated only by their GLSL twins (reference/shaders/
// ld06_wash.glsl).
#pragma once

#include <algorithm>
#include <cstring>

#include <glm/glm.hpp>

#include "stylize/kernels.h"
#include "stylize/stages/toolkit.h"

namespace aq::stylize {

//! Spec §4.3-4.5 defaults (ours: the paper gives no values): the smoothstep centre κ and half
//! width w (narrow = wet-on-dry, wide = wet-on-wet), the edge-darkening gain, the paper's border
//! perturbation and granulation gains.
inline constexpr float kWashKappa = 0.5f;
inline constexpr float kWashWidth = 0.2f;
inline constexpr float kWashEdge = 1.0f;
inline constexpr float kWashBorder = 0.3f;
inline constexpr float kWashGranulation = 0.35f;

struct WashShape {
    float kappa = kWashKappa;              //!< [0, 1]
    float width = kWashWidth;              //!< [0.001, 1]
    float edge = kWashEdge;                //!< edge-darkening gain, [0, 8]
    float border = kWashBorder;            //!< paper perturbation of the borders, [0, 2]
    float granulation = kWashGranulation;  //!< paper modulation of the pigment, [0, 1]
    bool paper_before = true;              //!< perturb ρ before shaping (ragged borders); false: after
    bool additive_edge = false;            //!< edge term added (true) or multiplied (false)
};

//! Pigment amount of one wash at a pixel (>= 0; 1 = a full wash, more at darkened edges).
//! I: the layer's intensity, rho: its Gaussian blur, h: paper height in [0, 1] (0.5 = flat).
//! Spec §4: a = smoothstep(κ - w, κ + w, ρ') with ρ' = ρ + border·(h - ½) (paper before the shaping)
//! or the transition band of a perturbed afterwards; edge term e = edge·max(I - ρ, 0) (pigment
//! gathers where the blurred value falls below the unblurred one), p = a·(1 + e) or a + e; then
//! granulation p·(1 - 2·granulation·(h - ½)): more pigment in the paper's valleys.
inline float wash_amount(float I, float rho, float h, const WashShape& s) {
    const float hp = h - 0.5f;
    const float r = s.paper_before ? rho + s.border * hp : rho;
    float a = smoothstep(s.kappa - s.width, s.kappa + s.width, r);
    if (!s.paper_before) a = sat(a + 4.0f * s.border * hp * a * (1.0f - a));
    const float d = I - rho;
    const float e = s.edge * (d > 0.0f ? d : 0.0f);
    const float p = s.additive_edge ? a + e : a * (1.0f + e);
    const float g = p * (1.0f - 2.0f * s.granulation * hp);
    return g > 0.0f ? g : 0.0f;
}

//! Spec §4.7 glazing of one wash of colour c and opacity k = sat(alpha·p) over dst.
//! Multiplicative (subtractive-like, the watercolor default): dst·(1 - k·(1 - c)); over: mix(dst, c, k).
//! Written once over any colour type: glm::vec3, or a pixel's RGB in the first three lanes of a
//! 4-lane register (the fast schedules; the fourth lane is computed and callers replace it), each
//! lane bit for bit the vec3 form.
template <bool Multiplicative, class V>
inline V glaze_of(V dst, V c, float k) {
    if constexpr (Multiplicative) return dst * (1.0f - k * (1.0f - c));
    else return dst * (1.0f - k) + c * k;
}

//! glaze_of of one pixel, the mode chosen at run time.
inline glm::vec3 glaze_px(glm::vec3 dst, glm::vec3 c, float k, bool multiplicative) {
    return multiplicative ? glaze_of<true>(dst, c, k) : glaze_of<false>(dst, c, k);
}

//! glaze_px of one colour over a row of w RGBA pixels: o[x].rgb = glaze_px(dst[x].rgb, c,
//! sat(alpha·p[x·stride]), multiplicative), o[x].a = dst[x].a (shadow_layer), through
//! glaze_of over 4-lane registers.
template <bool Multiplicative>
inline void glaze_row_of(float* __restrict o, const float* __restrict dst, const float* __restrict p, std::size_t stride,
                         int w, glm::vec3 c, float alpha) {
    const toolkit::v4f col = {c.r, c.g, c.b, 0.0f};
    for (int x = 0; x < w; ++x) {
        toolkit::v4f d;
        std::memcpy(&d, dst + std::size_t(x) * 4, sizeof d);
        toolkit::v4f r = glaze_of<Multiplicative>(d, col, sat(alpha * p[std::size_t(x) * stride]));
        r[3] = d[3];
        std::memcpy(o + std::size_t(x) * 4, &r, sizeof r);
    }
}

//! LD06 §3.2 colour of a layer at lighting-map value t (Gooch et al. 1998 with the object colour
//! replaced by the layer's object ramp): obj = tone·mix(dark, color, t), the temperature weight
//! w = 1 − keep_hue·s with s = (max − min) / max of obj (HSV saturation), k_cool = w·cool +
//! cool_mix·obj, k_warm = w·warm + warm_mix·obj, colour = sat(mix(k_cool, k_warm, t)).
//! keep_hue = 0 is Gooch's additive cool/warm shift; 1 (the default) fades the shift out with the
//! colour's saturation, so a grey object gets the full cool-to-warm ramp and a saturated one keeps
//! its hue (a red apple stays red; docs/ld06.md "color_ramp").
//! Defaults (ours): Gooch's b = y = 0.1 (published 0.4); docs/ld06.md "color_ramp" says why.
inline constexpr float kRampCoolWarm = 0.1f;
struct RampColors {
    glm::vec3 cool{0.0f, 0.0f, kRampCoolWarm}, warm{kRampCoolWarm, kRampCoolWarm, 0.0f};
    float cool_mix = 0.8f, warm_mix = 1.0f;
    float keep_hue = 1.0f;
};
inline glm::vec3 ramp_color(float t, glm::vec3 color, glm::vec3 dark, float tone, const RampColors& r) {
    const float u = sat(t);
    const glm::vec3 obj = tone * mix(dark, color, u);
    const float mx = std::max(obj.r, std::max(obj.g, obj.b)), mn = std::min(obj.r, std::min(obj.g, obj.b));
    const float s = mx > 0.0f ? (mx - mn) / mx : 0.0f;
    const float w = 1.0f - r.keep_hue * s;
    return sat(mix(w * r.cool + r.cool_mix * obj, w * r.warm + r.warm_mix * obj, u));
}

}  // namespace aq::stylize
