// stylize/stages/adjust.h — stage "adjust" (spec §4.1, MNPR quadAdjustLoad): linear depth
// normalisation, saturation/contrast/brightness, atmosphere tint, substrate colour as background.
#pragma once

#include <glm/glm.hpp>

#include "core/exec.h"
#include "core/image.h"
#include "stylize/stage.h"

namespace aq::stylize {

//! MNPR's depth range: 8..50 scene units map to 0..1 (unclamped).
inline constexpr float kMnprDepthNear = 8.0f;
inline constexpr float kMnprDepthFar = 50.0f;

struct AdjustParams {
    float depth_near = kMnprDepthNear;  //!< depth mapped to 0 [0, 1e6]
    float depth_far = kMnprDepthFar;    //!< depth mapped to 1 [0, 1e6], must differ from near
    float saturation = 1.0f;            //!< MNPR lerp(luma, c, s) [0, 5]
    float contrast = 1.0f;              //!< MNPR lerp(0.5, c, k*0.5 + 0.5) [0, 5]
    float brightness = 1.0f;            //!< MNPR sat(c + (b - 1)) [0, 5]
    bool atmosphere = false;            //!< enable the atmosphere tint (off: colour untouched by depth)
    float atmosphere_start = 25.0f;     //!< depth (scene units) where the tint starts [0, 1e6]
    float atmosphere_end = 300.0f;      //!< depth where the tint is complete [0, 1e6]
    float tint_r = 1.0f, tint_g = 1.0f, tint_b = 1.0f;  //!< atmosphere tint colour [0, 1]
};

//! Per pixel: depth_out = (z - near) / (far - near), 1 where z is not finite (no geometry, as
//! MNPR's zBuffer == 1 case); rgb = mix(substrate, sat(contrast(saturation(c)) + b - 1) [tinted],
//! alpha) (MNPR: lerp(substrate, result, alpha) -> the substrate where alpha = 0); alpha kept.
//! color: 4 channels; depth_linear: 1 channel, same size. Outputs are (re)allocated.
//! The rules between adjust's parameters (throws aq::Error): depth_near and depth_far differ, and
//! so do the atmosphere's start and end when it is on. adjust checks them; the registry entry's
//! validate too, when a pipeline compiles.
void check_adjust_params(const AdjustParams& p);

void adjust(ImageF& color_out, ImageF& depth_out, const ImageF& color, const ImageF& depth_linear,
            glm::vec3 substrate, const AdjustParams& p, const Exec& ex = {});

void register_adjust(Registry& r);

}  // namespace aq::stylize
