// stylize/stages/pigment_density.cpp — spec §4.3 (WC18 pigment turbulence in image space, MNPR
// form): the checks, the plain reference loop and the declaration. Pointwise: the reference and
// the fast schedule (pigment_density.schedule.cpp) run the same per-pixel function (bit-exact).
#include "stylize/stages/pigment_density.h"

#include "stylize/kernels.h"
#include "stylize/stages/toolkit.h"

namespace aq::stylize {

void pigment_density(ImageF& dst, const ImageF& color, const ImageF& ctrl, glm::vec3 substrate,
                     const PigmentDensityParams& p, const Exec& ex) {
    toolkit::check_input(&color, 4, toolkit::Channels::Exactly, "pigment_density", "color");
    toolkit::check_input(&ctrl, 4, toolkit::Channels::Exactly, "pigment_density", "ctrl_pigment");
    toolkit::check_same_size(ctrl, color, "pigment_density", "ctrl_pigment", "color");
    toolkit::check_not_alias(dst, &ctrl, "pigment_density", "ctrl_pigment");  // dst may be color (in place)
    const int w = color.width(), h = color.height();
    toolkit::ensure_output(dst, w, h, 4);
    if (ex.traversal == Traversal::Fast) {
        pigment_density_fast(dst, color, ctrl, substrate, p, ex);
        return;
    }
    // The plain reference: the formula pixel by pixel.
    const View<const glm::vec4> cv = color.view<glm::vec4>(), kv = ctrl.view<glm::vec4>();
    const View<glm::vec4> ov = dst.view<glm::vec4>();
    toolkit::plain_loop(w, h, [&](int x, int y) {
        ov(x, y) = pigment_density_px(cv(x, y), kv(x, y)[control::kPigmentDensity.channel], substrate, p);
    });
}

void register_pigment_density(Registry& r) {
    using P = PigmentDensityParams;
    r.add(declare({.stage = "pigment_density",
                   .variant = "mnpr",
                   .doc = "WC18/MNPR image-space turbulence: d = 1 + ctrl.pigment.b, c' = |c|^d, mix(substrate, c', sat(d))",
                   .inputs = {{"color", "color.adjusted", 4, false}, {"ctrl_pigment", target::kCtrlPigment, 4, false, SizeRule::Same, "color"}},
                   .outputs = {{"color", "color.density", 4, false}},
                   .reference = StageVariant::Reference::PlainLoop,
                   .in_place_input = "color",  // pointwise: each chunk's colour is read before it is written
                   .in_place_output = "color",
                   .row_halo = pointwise_rows,
                   .image_space_turbulence = true},
                  ParamTable<P>().f("strength", &P::strength, 0, 5, "multiplies ctrl.pigment.b (MNPR 1)"),
                  [](StageIO& io, const P& p, const Exec& ex) {
                      pigment_density(*io.out[0], *io.in[0], *io.in[1], globals_of(io).substrate_color, p, ex);
                  }));
}

}  // namespace aq::stylize
