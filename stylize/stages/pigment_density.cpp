// stylize/stages/pigment_density.cpp — spec §4.3 (WC18 pigment turbulence in image space, MNPR
// form). Pointwise: reference and fast run the same per-pixel function (bit-exact).
#include "stylize/stages/pigment_density.h"

#include <cmath>

#include "stylize/kernels.h"
#include "stylize/stages/stage_util.h"

namespace aq::stylize {

void pigment_density(ImageF& dst, const ImageF& color, const ImageF& ctrl, glm::vec3 substrate,
                     const PigmentDensityParams& p, const Exec& ex) {
    detail::check_input(color, 4, "pigment_density", "color");
    detail::check_input(ctrl, 4, "pigment_density", "control");
    detail::check_same_size(ctrl, color, "pigment_density", "control", "color");
    const int w = color.width(), h = color.height();
    detail::ensure_image(dst, w, h, 4);
    const float* c = color.data();
    const float* k = ctrl.data();
    float* o = dst.data();
    detail::for_each_row_block(ex, h, [&](int y0, int y1) {
        for (std::size_t i = std::size_t(y0) * w; i < std::size_t(y1) * w; ++i) {
            const float d = 1.0f + p.strength * k[4 * i + 2];
            const float t = sat(d);
            for (int ch = 0; ch < 3; ++ch) {
                // x^1 == x exactly, so unpainted pixels skip the pow (same value either way).
                const float ac = std::fabs(c[4 * i + ch]);
                const float cp = d == 1.0f ? ac : std::pow(ac, d);
                o[4 * i + ch] = mix(substrate[ch], cp, t);
            }
            o[4 * i + 3] = c[4 * i + 3];
        }
    });
}

void register_pigment_density(Registry& r) {
    static const ParamTable<PigmentDensityParams> t = ParamTable<PigmentDensityParams>().f(
        "strength", &PigmentDensityParams::strength, 0, 5, "multiplies ctrl.pigment.b (MNPR 1)");
    StageVariant v;
    v.stage = "pigment_density";
    v.variant = "mnpr";
    v.doc = "WC18/MNPR image-space turbulence: d = 1 + ctrl.pigment.b, c' = |c|^d, mix(substrate, c', sat(d))";
    v.inputs = {{"color", "color.adjusted", 4, false}, {"control", target::kCtrlPigment, 4, false}};
    v.outputs = {{"color", "color.density", 4, false}};
    v.params = t.descs();
    v.run = [](StageIO& io, const ParamValues& pv, const Exec& ex) {
        pigment_density(*io.out[0], *io.in[0], *io.in[1], detail::globals_of(io).substrate_color, t.from(pv), ex);
    };
    r.add(std::move(v));
}

}  // namespace aq::stylize
