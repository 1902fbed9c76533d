// stylize/stages/pigment_apply.cpp — WC17 eq. 9 granulation and WC18 eq. 1-4 dry-brush +
// granulation: the checks, the plain reference loops and the declarations. Pointwise: the
// reference and the fast schedules (pigment_apply.schedule.cpp) are bit-exact.
#include "stylize/stages/pigment_apply.h"
#include "stylize/paper.h"

#include <algorithm>
#include <cstring>

namespace aq::stylize {

using namespace toolkit;

namespace {

using Inputs = PigmentInputs;

//! in_place: dst may be color (a pointwise schedule that reads a pixel's colour before writing it).
Inputs check(ImageF& dst, const ImageF& color, const ImageF& ctrl_pigment, const ImageF* paper,
             const std::string& st, bool in_place = false) {
    check_input(&color, 4, Channels::Exactly, st, "color");
    check_input(&ctrl_pigment, 2, Channels::AtLeast, st, "ctrl_pigment");
    check_same_size(ctrl_pigment, color, st, "ctrl_pigment", "color");
    check_paper(paper, color, st, "color");
    if (!in_place) check_not_alias(dst, &color, st, "color");
    check_not_alias(dst, &ctrl_pigment, st, "ctrl_pigment");
    check_not_alias(dst, paper, st, "paper");
    ensure_output(dst, color.width(), color.height(), 4);
    return {color.view<glm::vec4>(), plane(ctrl_pigment, control::kPigmentApplication.channel),
            paper ? plane(*paper, 2) : constant_plane(&kFlatPaperHeight, color.width(), color.height())};
}

}  // namespace

void pigment_apply_wc17(ImageF& dst, const ImageF& color, const ImageF& ctrl_pigment, const ImageF* paper,
                        const PigmentApplyWc17Params& p,  const Exec& ex) {
    const Inputs in = check(dst, color, ctrl_pigment, paper, "pigment_apply/wc17");
    const View<glm::vec4> o = dst.view<glm::vec4>();
    if (ex.traversal == Traversal::Fast) {
        pigment_apply_wc17_fast(o, in, p, ex);
        return;
    }
    // The plain reference: eq. 9 pixel by pixel.
    plain_loop(color.width(), color.height(),
               [&](int x, int y) { o(x, y) = pigment_apply_wc17_px(in.c(x, y), in.height(x, y), in.ctrl(x, y), p); });
}

void pigment_apply_wc18(ImageF& dst, const ImageF& color, const ImageF& ctrl_pigment, const ImageF* paper,
                        glm::vec3 substrate, const PigmentApplyWc18Params& p,  const Exec& ex) {
    // In place (dst is color: StageVariant::in_place_input): uncovered pixels are not written
    // (the fast schedule).
    const Inputs in = check(dst, color, ctrl_pigment, paper, "pigment_apply/wc18", true);
    const View<glm::vec4> o = dst.view<glm::vec4>();
    if (ex.traversal == Traversal::Fast) {
        pigment_apply_wc18_fast(o, in, &dst == &color, substrate, p, ex);
        return;
    }
    // The plain reference: eq. 1-4 pixel by pixel.
    plain_loop(color.width(), color.height(), [&](int x, int y) {
        o(x, y) = pigment_apply_wc18_px(in.c(x, y), in.height(x, y), in.ctrl(x, y), substrate, p);
    });
}

void register_pigment_apply(Registry& r) {
    using P17 = PigmentApplyWc17Params;
    using P18 = PigmentApplyWc18Params;
    const std::vector<Port> inputs = {{"color", target::kColor, 4, false}, {"ctrl_pigment", target::kCtrlPigment, 4, false, SizeRule::Same, "color"}};
    const std::vector<Port> outputs = {{"color", "color.pigment", 4, false}};
    r.add(declare({.stage = "pigment_apply",
                   .variant = "wc18",
                   .doc = "WC18 eq. 1-4: dry-brush where the paper is below -ctrl.pigment.g, else granulation C^(d_a)",
                   .inputs = inputs,
                   .outputs = outputs,
                   .reference = StageVariant::Reference::PlainLoop,
                   .in_place_input = "color",  // uncovered pixels (the background) are left as they are
                   .in_place_output = "color",
                   .row_halo = pointwise_rows},
                  ParamTable<P18>()
                      .f("density", &P18::density, 0, 20, "D: global pigment density (eq. 4, MNPR 5)")
                      .f("dry_brush_threshold", &P18::dry_brush_threshold, 0, 100, "t_dry: dry-brush edge sharpness (eq. 2, MNPR 5)")
                      .f("roughness", &P18::roughness, 0, 5, "r: (H - 0.5) r + 0.5 (eq. 1)")
                      .f("granulation_min", &P18::granulation_min, 0, 1, "d_min: default granulation (WC18 0.2)"),
                  [](StageIO& io, const P18& p, const Exec& ex) {
                      const Globals& g = globals_of(io);
                      pigment_apply_wc18(*io.out[0], *io.in[0], *io.in[1], g.paper, g.substrate_color, p, ex);
                  }));
    r.add(declare({.stage = "pigment_apply",
                   .variant = "wc17",
                   .doc = "WC17 eq. 9: I(I - k - t P_iv) + (1 - I) I^(1 + k), k = Ctrl d P_iv (split granulation model)",
                   .inputs = inputs,
                   .outputs = outputs,
                   .reference = StageVariant::Reference::PlainLoop,
                   .row_halo = pointwise_rows},
                  ParamTable<P17>()
                      .f("density", &P17::density, 0, 10, "d: pigment density at the paper's valleys (eq. 9)")
                      .f("roughness", &P17::roughness, 0, 5, "r: paper height (H - 0.5) r + 0.5")
                      .b("literal", &P17::literal, "subtract P_iv as printed in eq. 9 (darkens even at Ctrl = 0)")
                      .f("paper_texture", &P17::paper_texture, 0, 1,
                         "t: eq. 9's uncontrolled term at strength t, k + t P_iv, also on the bare paper (0 = off)"),
                  [](StageIO& io, const P17& p, const Exec& ex) {
                      pigment_apply_wc17(*io.out[0], *io.in[0], *io.in[1], globals_of(io).paper, p, ex);
                  }));
}

}  // namespace aq::stylize
