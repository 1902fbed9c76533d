// stylize/stages/substrate_light.h — stage "substrate_light" (spec §4.10): the paper's relief
// shading the painted image. The paper comes from Globals::paper (3 ch, MNPR layout); without a
// paper the stage shades as on the flat paper (normal (0,0,1)).
//
// substrate_light / wc18    WC18 §4.2 eq. 5: Id = 1 - (1 - L.(r N)) ds, with MNPR's light
//   L = (sin t, cos t, tilt / 89) (t = direction in degrees), N = (-r (tex.r - 0.5), -r (tex.g - 0.5), 1)
//   (MNPR substrateLightingFrag; the roughness r scales the relief, i.e. N.xy), output C * Id.
// substrate_light / mnpr    the same with MNPR's curve Id = 1 - (1 - N.L)^2 ds.
#pragma once

#include <cmath>

#include <glm/glm.hpp>

#include "core/exec.h"
#include "core/image.h"
#include "stylize/stage.h"

namespace aq::stylize {

//! MNPR substrate lighting defaults.
inline constexpr float kSubstrateLightDirection = 180.0f;  //!< degrees
inline constexpr float kSubstrateLightTilt = 45.0f;        //!< degrees, L.z = tilt / 89
inline constexpr float kSubstrateShading = 0.5f;           //!< ds

struct SubstrateLightParams {
    float direction = kSubstrateLightDirection;  //!< light direction in degrees [0, 360]
    float tilt = kSubstrateLightTilt;            //!< light tilt in degrees [0, 89]
    float shading = kSubstrateShading;           //!< ds [0, 1]
    float roughness = 1.0f;                      //!< r: relief scale of the normal [0, 5]
    //! Divide Id by the flat paper's Id (N = (0, 0, 1)), so the paper keeps its substrate colour on
    //! average and only the relief shades it (docs/look.md: eq. 5 read literally lights the flat
    //! paper at 1 - (1 - tilt/89) ds = 0.753, a grey paper). false = eq. 5 as printed.
    bool normalize = false;
};

//! Light vector of eq. 5 (MNPR form).
inline glm::vec3 substrate_light_dir(const SubstrateLightParams& p) {
    const float rad = p.direction * 3.14159265f / 180.0f;
    return {std::sin(rad), std::cos(rad), p.tilt / 89.0f};
}

//! 1 / Id of the flat paper (N = (0, 0, 1)) when p.normalize, else 1; Id_flat <= 0 (no light on
//! the flat paper) gives 1.
inline float substrate_light_norm(glm::vec3 l, const SubstrateLightParams& p, bool squared) {
    if (!p.normalize) return 1.0f;
    const float u = 1.0f - l.z;
    const float flat = 1.0f - (squared ? u * u : u) * p.shading;
    return flat > 0.0f ? 1.0f / flat : 1.0f;
}

//! Diffuse factor Id for one pixel (squared = MNPR's curve).
inline float substrate_light_factor(float tex_r, float tex_g, glm::vec3 l, float roughness, float shading,
                                    bool squared) {
    const float nx = -(tex_r - 0.5f) * roughness, ny = -(tex_g - 0.5f) * roughness;
    const float nl = nx * l.x + ny * l.y + l.z;
    const float u = 1.0f - nl;
    return 1.0f - (squared ? u * u : u) * shading;
}

//! Eq. 5 (or MNPR's curve) for one pixel: c RGBA, tex_r/tex_g the paper's encoded normal, l the
//! light (substrate_light_dir), norm = substrate_light_norm(l, p, squared).
inline glm::vec4 substrate_light_px(glm::vec4 c, float tex_r, float tex_g, glm::vec3 l, float norm,
                                    const SubstrateLightParams& p, bool squared) {
    float id = substrate_light_factor(tex_r, tex_g, l, p.roughness, p.shading, squared);
    if (p.normalize) id = id * norm;
    return {c.x * id, c.y * id, c.z * id, c.w};
}

//! color: 4 ch; paper: 3 ch same size or nullptr (flat). squared: MNPR curve instead of eq. 5.
void substrate_light(ImageF& dst, const ImageF& color, const ImageF* paper, const SubstrateLightParams& p,
                     bool squared,  const Exec& ex = {});

void register_substrate_light(Registry& r);

}  // namespace aq::stylize
