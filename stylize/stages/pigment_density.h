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

//! The maths of one pixel (defined below): the formula that follows.
inline glm::vec4 pigment_density_px(glm::vec4 c, float ctrl_b, glm::vec3 substrate, const PigmentDensityParams& p);

//! d = 1 + strength * ctrl.pigment.b;  c' = |c|^d;  out.rgb = mix(substrate, c', sat(d));
//! alpha kept. With zero control, d = 1 and the colour is returned unchanged (|c| for negative
//! inputs). color, ctrl: 4 channels, same size.
void pigment_density(ImageF& dst, const ImageF& color, const ImageF& ctrl_pigment, glm::vec3 substrate,
                     const PigmentDensityParams& p, const Exec& ex = {});

//! The fast schedule (pigment_density.schedule.cpp), which pigment_density runs for
//! Traversal::Fast after its checks, with dst allocated (dst may be color: in place): the
//! reference's bytes.
void pigment_density_fast(ImageF& dst, const ImageF& color, const ImageF& ctrl, glm::vec3 substrate,
                          const PigmentDensityParams& p, const Exec& ex);

void register_pigment_density(Registry& r);

}  // namespace aq::stylize

#include "stylize/kernels.h"
#include "stylize/kernels.h"

namespace aq::stylize {

inline glm::vec4 pigment_density_px(glm::vec4 c, float ctrl_b, glm::vec3 substrate, const PigmentDensityParams& p) {
    const float d = 1.0f + p.strength * ctrl_b;
    const float t = sat(d);
    glm::vec4 o;
    for (int ch = 0; ch < 3; ++ch) o[ch] = mix(substrate[ch], pow_c(std::fabs(c[ch]), d), t);
    o.w = c.w;
    return o;
}

}  // namespace aq::stylize
