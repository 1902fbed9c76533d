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

namespace {

//! Row y, pixels [x0, x1): c and o are 4-channel rows, paper a row of `pc` channels (R, G = the
//! normal) or null (the flat paper). Flat loops over arrays with the stride a template constant,
//! so GCC vectorises them; the per-pixel function is substrate_light_px itself. One compiled body
//! for both traversals (not inlined into each), so they agree to the bit, NaN payloads included.
template <int PC>
[[gnu::noinline]] void light_row(const float* c, const float* paper, float* o, int x0, int x1, glm::vec3 l, float norm,
                                 const SubstrateLightParams p, bool squared) {
    for (int x = x0; x < x1; ++x) {
        const float tr = PC ? paper[std::size_t(x) * PC] : kFlatPaperNormal;
        const float tg = PC ? paper[std::size_t(x) * PC + 1] : kFlatPaperNormal;
        const float* ci = c + std::size_t(x) * 4;
        const glm::vec4 v = substrate_light_px({ci[0], ci[1], ci[2], ci[3]}, tr, tg, l, norm, p, squared);
        float* oi = o + std::size_t(x) * 4;
        oi[0] = v.x, oi[1] = v.y, oi[2] = v.z, oi[3] = v.w;
    }
}

}  // namespace

void substrate_light(ImageF& dst, const ImageF& color, const ImageF* paper, const SubstrateLightParams& p,
                     bool squared,  const Exec& ex) {
    const std::string st = squared ? "substrate_light/mnpr" : "substrate_light/wc18";
    check_input(&color, 4, Channels::Exactly, st, "color");
    check_paper(paper, color, st, "color");
    check_not_alias(dst, paper, st, "paper");  // dst may be color: a pixel is read before it is written
    const int w = color.width(), h = color.height();
    ensure_output(dst, w, h, 4);
    const glm::vec3 l = substrate_light_dir(p);
    const float norm = substrate_light_norm(l, p, squared);
    const int pc = paper ? paper->channels() : 0;  // 0, 3 or 4 (images hold 1..4; check_paper: >= 3)
    for_each_row(ex, w, h, [&](int y, int x0, int x1) {
        const std::size_t row = std::size_t(y) * std::size_t(w);
        const float* c = color.data() + row * 4;
        float* o = dst.data() + row * 4;
        const float* pr = paper ? paper->data() + row * std::size_t(pc) : nullptr;
        if (pc == 0) light_row<0>(c, pr, o, x0, x1, l, norm, p, squared);
        else if (pc == 3) light_row<3>(c, pr, o, x0, x1, l, norm, p, squared);
        else light_row<4>(c, pr, o, x0, x1, l, norm, p, squared);
    });
}

void register_substrate_light(Registry& r) {
    using L = SubstrateLightParams;
    const ParamTable<L> t = ParamTable<L>()
        .f("direction", &L::direction, 0, 360, "light direction in degrees (MNPR 180)")
        .f("tilt", &L::tilt, 0, 89, "light tilt in degrees, L.z = tilt/89 (MNPR 45)")
        .f("shading", &L::shading, 0, 1, "diffuse shading contribution ds (MNPR 0.5)")
        .f("roughness", &L::roughness, 0, 5, "r: relief scale of the paper normal")
        .b("normalize", &L::normalize, "divide by the flat paper's Id: flat paper keeps the substrate colour (0 = eq. 5 as printed)");
    for (bool squared : {false, true}) {
        r.add(declare({.stage = "substrate_light",
                       .variant = squared ? "mnpr" : "wc18",
                       .doc = squared ? "MNPR substrate lighting: C * (1 - (1 - N.L)^2 ds)"
                                      : "WC18 eq. 5: C * (1 - (1 - L.(rN)) ds), MNPR light (180 deg, tilt 45, ds 0.5)",
                       .inputs = {{"color", target::kColor, 4, false}},
                       .outputs = {{"color", "color.lit", 4, false}},
                       .reference = StageVariant::Reference::SharedMaths,
                       .in_place_input = "color",  // pointwise: no second full-frame image (and its first touch)
                       .in_place_output = "color",
                       .row_halo = pointwise_rows},
                      t, [squared](StageIO& io, const L& p, const Exec& ex) {
                          substrate_light(*io.out[0], *io.in[0], globals_of(io).paper, p, squared, ex);
                      }));
    }
}

}  // namespace aq::stylize
