// stylize/stages/bleed_blend.h — stage "bleed_blend", variant eq7: WC17 eq. (7)
//   I_cb = Ctrl (B - I) + I
// with Ctrl the (expanded) mask in bleed.a, here k = sat(gain * bleed.a): gain = 1 is WC17 as
// published, gain = 5 is MNPR's blendFromAlpha (k = sat(5 bleed.a)) (spec §4.5).
#pragma once

#include <glm/glm.hpp>

#include "core/exec.h"
#include "core/image.h"
#include "stylize/kernels.h"
#include "stylize/stage.h"

namespace aq::stylize {

inline constexpr float kBleedBlendGainWc17 = 1.0f;
inline constexpr float kBleedBlendGainMnpr = 5.0f;

struct BleedBlendParams {
    float gain = kBleedBlendGainWc17;  //!< k = sat(gain * mask) [0, 100]
};

//! Eq. 7 for one pixel: c = I (RGBA), b = the bleed at this pixel (rgb = B, a = mask).
inline glm::vec4 bleed_blend_px(glm::vec4 c, glm::vec4 b, float gain) {
    const float k = sat(gain * b.w);
    return {k * (b.x - c.x) + c.x, k * (b.y - c.y) + c.y, k * (b.z - c.z) + c.z, c.w};
}

//! color: 4 channels; bleed: 4 channels (rgb = B, a = mask), either the size of color or its half
//! resolution (ceil(w/2) x ceil(h/2)), then upsampled bilinearly (kernels.h sample_resampled: pixel
//! centres at +0.5, GL_LINEAR, clamp to edge). Where k = 0 the colour is returned unchanged.
void bleed_blend(ImageF& dst, const ImageF& color, const ImageF& bleed, const BleedBlendParams& p,
                 const Exec& ex = {});

//! The fast schedule (bleed_blend.schedule.cpp), which the stage runs for Traversal::Fast after its
//! checks, with dst allocated (dst may be color: in place, kept pixels are not written).
void bleed_blend_fast(ImageF& dst, const ImageF& color, const ImageF& bleed, float gain, const Exec& ex);

void register_bleed_blend(Registry& r);

}  // namespace aq::stylize
