// stylize/stages/gaps_overlaps.cpp — WC18 Algorithm 1 (see gaps_overlaps.h): the checks, the plain
// reference loop over GapsOverlapsKernel and the declaration; the fast schedule is
// gaps_overlaps.schedule.cpp. Each output pixel reads a neighbourhood of at most m+1 pixels of its
// inputs and writes only itself: reference and fast traversals are bit-exact. Marches are bounded
// by the integer parameter m, never by float->int conversions of image values; a zero or
// non-finite gradient leaves the pixel unchanged.
#include "stylize/stages/gaps_overlaps.h"

#include <string>

namespace aq::stylize {

using namespace toolkit;

namespace {

//! Rows a pixel's taps reach: the march of up to `steps` pixels along the unit gradient (its
//! rounding can add a little), the bilinear footprint and the 3 x 3 gradient one more each.
int gaps_overlaps_reach(const GapsOverlapsParams& p) { return p.steps + 2; }

}  // namespace

void gaps_overlaps(ImageF& dst, const ImageF& color, const ImageF& edges_ext, const ImageF& ctrl_edge,
                   const ImageF* bleed, glm::vec3 substrate, const GapsOverlapsParams& p, const Exec& ex) {
    const std::string st = "gaps_overlaps/wc18";
    check_input(&color, 4, Channels::Exactly, st, "color");
    check_input(&edges_ext, 1, Channels::AtLeast, st, "edges");
    check_same_size(edges_ext, color, st, "edges", "color");
    check_input(&ctrl_edge, 3, Channels::AtLeast, st, "ctrl_edge");
    check_same_size(ctrl_edge, color, st, "ctrl_edge", "color");
    check_bleed_mask(bleed, color, st);
    if (p.steps < 1 || p.steps > 16) throw Error(st + ": steps must be in [1, 16]");
    check_not_alias(dst, &edges_ext, st, "edges");
    check_not_alias(dst, &ctrl_edge, st, "ctrl_edge");
    check_not_alias(dst, bleed, st, "bleed");
    // In place (dst is color: StageVariant::in_place_input): a pixel reads its neighbours' colours
    // (the overlap march), so nothing is written until every changed pixel is computed from the
    // unchanged image; pixels without an edge are not written at all.
    const bool in_place = &dst == &color;
    const int w = color.width(), h = color.height();
    ensure_output(dst, w, h, 4);
    static const float kZero = 0.0f;
    const Resampler up = bleed ? Resampler(w, h, bleed->width(), bleed->height()) : Resampler(w, h, w, h);
    const GapsOverlapsKernel k{color.view<glm::vec4>(),
                               plane(edges_ext, 0),
                               plane(ctrl_edge, control::kEdgeTransition.channel),
                               bleed ? plane(*bleed, bleed->channels() == 4 ? 3 : 0) : constant_plane(&kZero, w, h),
                               &up,
                               w,
                               h,
                               substrate,
                               p,
                               p.border};
    const View<glm::vec4> o = dst.view<glm::vec4>();
    if (ex.traversal == Traversal::Reference) {  // the kernel pixel by pixel
        if (in_place) {  // on a copy of the colour: every pixel reads the unchanged image
            const ImageF before = color;
            GapsOverlapsKernel kc = k;
            kc.c = before.view<glm::vec4>();
            plain_loop(w, h, [&](int x, int y) { o(x, y) = kc(x, y); });
            return;
        }
        plain_loop(w, h, [&](int x, int y) { o(x, y) = k(x, y); });
        return;
    }
    gaps_overlaps_fast(o, k, edges_ext.channels() == 1 ? edges_ext.data() : nullptr, in_place, ex);
}

void register_gaps_overlaps(Registry& r) {
    using P = GapsOverlapsParams;
    static const ParamTable<P> t = ParamTable<P>()
        .i("steps", &P::steps, 1, 16, "m: widest gap/overlap in pixels (WC18 5); p = ctrl.edge.b * m")
        .f("color_difference", &P::color_difference, 0, 2, "RGBA distance that ends the march (MNPR 0.33)")
        .f("substrate_proximity", &P::substrate_proximity, 0, 2, "no overlap with colours this close to the substrate (MNPR 0.1)")
        .f("alpha_threshold", &P::alpha_threshold, 0, 1, "only pixels with alpha above (MNPR 0.1)")
        .f("bleed_threshold", &P::bleed_threshold, 0, 1, "only pixels with bleeding mask below (MNPR 0.01)")
        .f("edge_threshold", &P::edge_threshold, 0, 1, "only pixels with extended edge above (MNPR 0.1, WC18 0.2)")
        .f("mix_brightness", &P::mix_brightness, 0, 2, "brightness scale of the RYB mix (1 preserves; MNPR 0.9)")
        .b("transparent_gaps", &P::transparent_gaps, "gaps zero alpha instead of painting the substrate colour")
        .border(&P::border);
    r.add(declare({.stage = "gaps_overlaps",
                   .variant = "wc18",
                   .doc = "WC18 Algorithm 1: march along the extended-edge gradient; overlaps mix in RYB, gaps show the substrate",
                   .inputs = {{"color", target::kColor, 4, false},
                              {"edges", "edges.extended", 1, false, SizeRule::Same, "color"},
                              {"ctrl_edge", target::kCtrlEdge, 4, false, SizeRule::Same, "color"},
                              {"bleed", "bleed", 4, true, SizeRule::FullOrHalf, "color"}},
                   .outputs = {{"color", "color.gaps_overlaps", 4, false}},
                   .reference = StageVariant::Reference::SharedMaths,
                   .in_place_input = "color",  // pixels without an edge are left as they are
                   .in_place_output = "color",
                   .row_halo = [](const ParamValues& pv) { return gaps_overlaps_reach(t.from(pv)); }},
                  t, [](StageIO& io, const P& p, const Exec& ex) {
                      gaps_overlaps(*io.out[0], *io.in[0], *io.in[1], *io.in[2], io.in.size() > 3 ? io.in[3] : nullptr,
                                    globals_of(io).substrate_color, p, ex);
                  }));
}

}  // namespace aq::stylize
