// stylize/stages/pigment_apply.cpp — WC17 eq. 9 granulation and WC18 eq. 1-4 dry-brush +
// granulation. Pointwise: reference and fast traversals are bit-exact.
// The power loops vectorise only when GCC may evaluate both sides of a select; that needs
// -fno-trapping-math (FP exception flags only — no value changes, unlike -ffast-math: no
// reassociation, no FMA, no reciprocal approximations). See docs/stylize.md "Speed".
#pragma GCC optimize("no-trapping-math")
#include "stylize/stages/pigment_apply.h"
#include "stylize/paper.h"

#include <algorithm>
#include <cstring>

namespace aq::stylize {

using namespace toolkit;

namespace {


struct Inputs {
    View<const glm::vec4> c;
    Plane ctrl, height;
};

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
    if (ex.traversal == Traversal::Reference) {  // the plain reference: eq. 9 pixel by pixel
        plain_loop(color.width(), color.height(),
                   [&](int x, int y) { o(x, y) = pigment_apply_wc17_px(in.c(x, y), in.height(x, y), in.ctrl(x, y), p); });
        return;
    }
    // Rows in chunks as in wc18: the same operations as pigment_apply_wc17_px, pixel by pixel.
    for_each_row(ex, color.width(), color.height(), [&](int y, int x0, int x1) {
        constexpr int kChunk = 64;
        PigmentWc17Prep q[kChunk];
        float base[3 * kChunk], dexp[3 * kChunk], g[3 * kChunk];
        for (int xs = x0; xs < x1; xs += kChunk) {
            const int n = std::min(kChunk, x1 - xs);
            for (int i = 0; i < n; ++i) {
                const int x = xs + i;
                const glm::vec4 cv = in.c(x, y);
                q[i] = pigment_apply_wc17_prepare(cv, in.height(x, y), in.ctrl(x, y), p);
                for (int k = 0; k < 3; ++k) base[3 * i + k] = cv[k], dexp[3 * i + k] = q[i].d;
            }
            pow_c_many(base, dexp, g, std::size_t(3 * n));
            for (int i = 0; i < n; ++i) {
                const glm::vec4 cv = in.c(xs + i, y);
                o(xs + i, y) = q[i].apply ? glm::vec4(pigment_apply_wc17_channel(cv.x, q[i].sub, g[3 * i]),
                                                      pigment_apply_wc17_channel(cv.y, q[i].sub, g[3 * i + 1]),
                                                      pigment_apply_wc17_channel(cv.z, q[i].sub, g[3 * i + 2]), cv.w)
                                          : cv;
            }
        }
    });
}

void pigment_apply_wc18(ImageF& dst, const ImageF& color, const ImageF& ctrl_pigment, const ImageF* paper,
                        glm::vec3 substrate, const PigmentApplyWc18Params& p,  const Exec& ex) {
    // In place (dst is color: StageVariant::in_place_input): uncovered pixels are not written.
    const bool in_place = &dst == &color;
    const Inputs in = check(dst, color, ctrl_pigment, paper, "pigment_apply/wc18", true);
    const View<glm::vec4> o = dst.view<glm::vec4>();
    if (ex.traversal == Traversal::Reference) {  // the plain reference: eq. 1-4 pixel by pixel
        plain_loop(color.width(), color.height(), [&](int x, int y) {
            o(x, y) = pigment_apply_wc18_px(in.c(x, y), in.height(x, y), in.ctrl(x, y), substrate, p);
        });
        return;
    }
    // Rows in chunks of 64 pixels, each step a simple loop over arrays: gather (eight pixels per
    // register), pigment_apply_wc18_prepare written with selects (GCC vectorises it), the powers
    // per channel plane in pow_c_many (for chunks where a pixel granulates), the blend. Value for value the operations of
    // pigment_apply_wc18_px (tests/stylize/row_kernels_test.cpp checks it bit for bit).
    for_each_row(ex, color.width(), color.height(), [&](int y, int x0, int x1) {
        constexpr int kChunk = 64;
        float cr[kChunk], cg[kChunk], cb[kChunk], ca[kChunk], ht[kChunk], av[kChunk];
        float outr[kChunk], outg[kChunk], outb[kChunk], da[kChunk], fade[kChunk];
        int mode[kChunk];
        float base[3 * kChunk], g[3 * kChunk];
        const float sr = substrate.x, sg = substrate.y, sb = substrate.z;
        for (int xs = x0; xs < x1; xs += kChunk) {
            const int n = std::min(kChunk, x1 - xs);
            // Every pixel uncovered (mode 0 below; NaN alpha is uncovered): the colour as it is.
            // The alphas are tested two pixels per register (lanes 3 and 7), the chunk copied whole.
            const float* crow = &in.c(xs, y).x;
            v8i covered{};
            const v8i alpha_lanes{0, 0, 0, -1, 0, 0, 0, -1};
            const v8f mask = v8f{} + kPigmentAlphaMask;
            int i2 = 0;
            for (; i2 + 2 <= n; i2 += 2) covered |= (load8(crow + 4 * i2) >= mask) & alpha_lanes;
            const bool any_covered = !all_zero(covered) || (i2 < n && crow[4 * i2 + 3] >= kPigmentAlphaMask);
            if (!any_covered) {
                if (!in_place) std::memcpy(&o(xs, y).x, crow, sizeof(float) * 4 * std::size_t(n));
                continue;
            }
            int i8 = 0;
            for (; i8 + 8 <= n; i8 += 8) {
                const float* cp = crow + 4 * i8;
                store8(cr + i8, simd::strided8<4>(cp));
                store8(cg + i8, simd::strided8<4>(cp + 1));
                store8(cb + i8, simd::strided8<4>(cp + 2));
                store8(ca + i8, simd::strided8<4>(cp + 3));
                store8(ht + i8, plane8(in.height, xs + i8, y));
                store8(av + i8, plane8(in.ctrl, xs + i8, y));
            }
            for (int i = i8; i < n; ++i) {
                const glm::vec4 cv = in.c(xs + i, y);
                cr[i] = cv.x, cg[i] = cv.y, cb[i] = cv.z, ca[i] = cv.w;
                ht[i] = in.height(xs + i, y);
                av[i] = in.ctrl(xs + i, y);
            }
            for (int i = 0; i < n; ++i) {
                const float hr = (ht[i] - 0.5f) * p.roughness + 0.5f;  // eq. 1
                const float dry = hr + av[i];
                const float t = sat(-dry * p.dry_brush_threshold);   // eq. 2, case 1
                const float u = 1.0f - t;
                outr[i] = cr[i] * u + sr * t, outg[i] = cg[i] * u + sg * t, outb[i] = cb[i] * u + sb * t;
                float dg = std::fabs(av[i]) + p.granulation_min;      // eq. 3
                const float l = luminance(cr[i], cg[i], cb[i]);
                dg = dg * (1.0f - l) + (dg * kGranulationLuminanceGain) * l;
                const float hiv = 1.0f - (hr * kGranulationHeightScale + kGranulationHeightShift);
                da[i] = 1.0f + dg * hiv * p.density;                   // eq. 4
                const float dr = cr[i] - sr, dgr = cg[i] - sg, db = cb[i] - sb;
                fade[i] = sat(std::sqrt(dr * dr + dgr * dgr + db * db) * kPigmentSubstrateFade);
                // 0: uncovered (unchanged), 1: dry-brushed, 2: granulates
                mode[i] = !(ca[i] >= kPigmentAlphaMask) ? 0 : (dry < 0.0f ? 1 : 2);
            }
            // Covered pixels come in runs: when any pixel of the chunk granulates, the powers are
            // taken for the whole chunk (one vectorised loop) and blended where mode == 2.
            bool any = false;
            for (int i = 0; i < n; ++i) any |= mode[i] == 2;
            if (any) {
                // Channel planes (base[c * kChunk + i]): the exponent plane da serves all three.
                for (int i = 0; i < n; ++i) base[i] = std::fabs(cr[i]);
                for (int i = 0; i < n; ++i) base[kChunk + i] = std::fabs(cg[i]);
                for (int i = 0; i < n; ++i) base[2 * kChunk + i] = std::fabs(cb[i]);
                for (int ch = 0; ch < 3; ++ch) pow_c_many(base + ch * kChunk, da, g + ch * kChunk, std::size_t(n));
                for (int i = 0; i < n; ++i) {  // eq. 2, case 2, blended by the substrate fade
                    const float f = fade[i], u = 1.0f - f;
                    const bool gr = mode[i] == 2;
                    outr[i] = gr ? cr[i] * u + g[i] * f : outr[i];
                    outg[i] = gr ? cg[i] * u + g[kChunk + i] * f : outg[i];
                    outb[i] = gr ? cb[i] * u + g[2 * kChunk + i] * f : outb[i];
                }
            }
            for (int i = 0; i < n; ++i)
                o(xs + i, y) = mode[i] == 0 ? glm::vec4(cr[i], cg[i], cb[i], ca[i])
                                            : glm::vec4(outr[i], outg[i], outb[i], ca[i]);
        }
    });
}

void register_pigment_apply(Registry& r) {
    using P17 = PigmentApplyWc17Params;
    using P18 = PigmentApplyWc18Params;
    const std::vector<Port> inputs = {{"color", target::kColor, 4, false}, {"ctrl_pigment", target::kCtrlPigment, 4, false}};
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
