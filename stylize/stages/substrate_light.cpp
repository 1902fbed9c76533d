// stylize/stages/substrate_light.cpp — substrate lighting (WC18 eq. 5, MNPR's curve): a pointwise
// stage.
#pragma GCC optimize("no-trapping-math")
#include "stylize/stages/substrate_light.h"

#include <algorithm>
#include <cmath>

#include "stylize/kernels.h"
#include "stylize/paper.h"
#include "stylize/stages/toolkit.h"

namespace aq::stylize {

using namespace toolkit;

void substrate_light(ImageF& dst, const ImageF& color, const ImageF* paper, const SubstrateLightParams& p,
                     bool squared,  const Exec& ex) {
    const std::string st = squared ? "substrate_light/mnpr" : "substrate_light/wc18";
    check_input(&color, 4, Channels::Exactly, st, "color");
    check_paper(paper, color, st, "color");
    check_not_alias(dst, &color, st, "color");
    check_not_alias(dst, paper, st, "paper");
    const int w = color.width(), h = color.height();
    ensure_output(dst, w, h, 4);
    const View<const glm::vec4> c = color.view<glm::vec4>();
    const Plane nr = paper ? plane(*paper, 0) : constant_plane(&kFlatPaperNormal, w, h);
    const Plane ng = paper ? plane(*paper, 1) : constant_plane(&kFlatPaperNormal, w, h);
    const glm::vec3 l = substrate_light_dir(p);
    const float norm = substrate_light_norm(l, p, squared);
    const View<glm::vec4> o = dst.view<glm::vec4>();
    for_each_row(ex, w, h, [&](int y, int x0, int x1) {
        for (int x = x0; x < x1; ++x) o(x, y) = substrate_light_px(c(x, y), nr(x, y), ng(x, y), l, norm, p, squared);
    });
}

void register_substrate_light(Registry& r) {
    using L = SubstrateLightParams;
    static const ParamTable<L> tl = ParamTable<L>()
        .f("direction", &L::direction, 0, 360, "light direction in degrees (MNPR 180)")
        .f("tilt", &L::tilt, 0, 89, "light tilt in degrees, L.z = tilt/89 (MNPR 45)")
        .f("shading", &L::shading, 0, 1, "diffuse shading contribution ds (MNPR 0.5)")
        .f("roughness", &L::roughness, 0, 5, "r: relief scale of the paper normal")
        .b("normalize", &L::normalize, "divide by the flat paper's Id: flat paper keeps the substrate colour (0 = eq. 5 as printed)");
    for (bool squared : {false, true}) {
        StageVariant v;
        v.stage = "substrate_light";
        v.variant = squared ? "mnpr" : "wc18";
        v.doc = squared ? "MNPR substrate lighting: C * (1 - (1 - N.L)^2 ds)"
                        : "WC18 eq. 5: C * (1 - (1 - L.(rN)) ds), MNPR light (180 deg, tilt 45, ds 0.5)";
        v.inputs = {{"color", target::kColor, 4, false}};
        v.outputs = {{"color", "color.lit", 4, false}};
        v.params = tl.descs();
        v.run = with_port_check(v, [squared](StageIO& io, const ParamValues& pv, const Exec& ex) {
            substrate_light(*io.out[0], *io.in[0], globals_of(io).paper, tl.from(pv), squared, ex);
        });
        v.reference = StageVariant::Reference::SharedMaths;
        r.add(std::move(v));
    }
}

}  // namespace aq::stylize
