// stylize/stages/substrate_distort.cpp — paper distortion (WC17 §3.3 / MNPR): the checks, the
// plain reference loop and the registry entry. Each output pixel reads a bounded neighbourhood of
// its inputs only (offsets are at most 5*distortion pixels), so the reference and the fast
// schedule (substrate_distort.schedule.cpp) are bit-exact.
#include "stylize/stages/substrate_distort.h"

#include <cmath>
#include <string>

#include "stylize/kernels.h"
#include "stylize/paper.h"
#include "stylize/stages/toolkit.h"

namespace aq::stylize {

using namespace toolkit;

void substrate_distort(ImageF& dst, const ImageF& color, const ImageF& depth, const ImageF& ctrl_substrate,
                       const ImageF* paper, const SubstrateDistortParams& p,  const Exec& ex) {
    const std::string st = "substrate_distort/mnpr";
    check_input(&color, 4, Channels::Exactly, st, "color");
    check_input(&depth, 1, Channels::AtLeast, st, "depth");
    check_same_size(depth, color, st, "depth", "color");
    check_input(&ctrl_substrate, 1, Channels::AtLeast, st, "ctrl_substrate");
    check_same_size(ctrl_substrate, color, st, "ctrl_substrate", "color");
    check_paper(paper, color, st, "color");
    check_not_alias(dst, &color, st, "color");
    check_not_alias(dst, &depth, st, "depth");
    check_not_alias(dst, &ctrl_substrate, st, "ctrl_substrate");
    check_not_alias(dst, paper, st, "paper");
    const int w = color.width(), h = color.height();
    ensure_output(dst, w, h, 4);
    if (ex.traversal == Traversal::Fast) {
        substrate_distort_fast(dst, color, depth, ctrl_substrate, paper, p, ex);
        return;
    }
    const View<const glm::vec4> c = color.view<glm::vec4>();
    const Plane z = plane(depth, 0), ctrl = plane(ctrl_substrate, control::kSubstrateDistortion.channel);
    const Plane nr = paper ? plane(*paper, 0) : constant_plane(&kFlatPaperNormal, w, h);
    const Plane ng = paper ? plane(*paper, 1) : constant_plane(&kFlatPaperNormal, w, h);
    const Border b = p.border;
    const View<glm::vec4> o = dst.view<glm::vec4>();
    // The plain reference: WC17 §3.3 pixel by pixel.
    plain_loop(w, h, [&](int x, int y) {
        const glm::vec2 off = substrate_offset(nr(x, y), ng(x, y), ctrl(x, y), p);
        if (off.x == 0.0f && off.y == 0.0f) {
            o(x, y) = c(x, y);
            return;
        }
        const float px = float(x) + 0.5f + off.x, py = (float(y) + 0.5f) + off.y;
        const float dz = z(x, y) - sample_bilinear(z, px, py, b);
        const bool blocked = p.both_sides ? !(std::fabs(dz) <= p.depth_threshold) : (dz > p.depth_threshold);
        o(x, y) = blocked ? c(x, y) : sample_bilinear(c, px, py, b);
    });
}

void register_substrate_distort(Registry& r) {
    using D = SubstrateDistortParams;
    static const ParamTable<D> t = ParamTable<D>()
        .f("distortion", &D::distortion, 0, 10, "global paper distortion: 5 px per unit at full control (MNPR 1)")
        .f("depth_threshold", &D::depth_threshold, 0, 1, "no sampling across this normalised depth step (MNPR 0.01)")
        .b("both_sides", &D::both_sides, "also refuse destinations behind the pixel (MNPR: only in front)")
        .border(&D::border);
    r.add(declare({.stage = "substrate_distort",
                   .variant = "mnpr",
                   .doc = "WC17 3.3 / MNPR: sample colour at +n*distortion*5*sat(ctrl.substrate.r+0.2) px, depth-guarded",
                   .inputs = {{"color", target::kColor, 4, false},
                              {"depth", "depth", 1, false, SizeRule::Same, "color"},
                              {"ctrl_substrate", target::kCtrlSubstrate, 4, false, SizeRule::Same, "color"}},
                   .outputs = {{"color", "color.distorted", 4, false}},
                   .reference = StageVariant::Reference::PlainLoop,
                   .row_halo = [](const ParamValues& pv) { return substrate_distort_reach(t.from(pv)); }},
                  t, [](StageIO& io, const D& p, const Exec& ex) {
                      substrate_distort(*io.out[0], *io.in[0], *io.in[1], *io.in[2], globals_of(io).paper, p, ex);
                  }));
}

}  // namespace aq::stylize
