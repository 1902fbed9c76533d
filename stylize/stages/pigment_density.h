// stylize/stages/pigment_density.h — stage "pigment_density", variant mnpr: image-space pigment
// turbulence (WC18 / MNPR quadPigmentManipulation pigmentDensityWC; spec §4.3).
#pragma once

#include <glm/glm.hpp>

#include "core/exec.h"
#include "core/image.h"
#include "stylize/stage.h"

namespace aq::stylize {

struct PigmentDensityParams {
    float strength = 1.0f;  //!< multiplies ctrl.pigment.b (1 = MNPR) [0, 5]
};

//! d = 1 + strength * ctrl.pigment.b;  c' = |c|^d;  out.rgb = mix(substrate, c', sat(d));
//! alpha kept. With zero control, d = 1 and the colour is returned unchanged (|c| for negative
//! inputs). color, ctrl: 4 channels, same size.
void pigment_density(ImageF& dst, const ImageF& color, const ImageF& ctrl_pigment, glm::vec3 substrate,
                     const PigmentDensityParams& p, const Exec& ex = {});

void register_pigment_density(Registry& r);

}  // namespace aq::stylize
