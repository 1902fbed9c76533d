// stylize/stages/edge_darken.cpp — WC17 eq. 8 (DoG) and WC18 §3.1 (RGBD) edge darkening: the
// checks, the plain reference loops and the declarations. Pointwise per pixel (plus one bilinear tap
// of a lower-resolution input), so the reference and the fast schedules (edge_darken.schedule.cpp)
// evaluate the same function on the same pixels: bit-exact.
#include "stylize/stages/edge_darken.h"

#include <algorithm>

#include "stylize/kernels.h"

namespace aq::stylize {

using namespace toolkit;

void check_edge_darken_dog_params(const EdgeDarkenDogParams& p) {
    if (!(p.smooth_high > p.smooth_low)) throw Error("edge_darken/dog: smooth_high must exceed smooth_low");
}

void edge_darken_dog(ImageF& dst, const ImageF& color, const ImageF& blurred, const ImageF& ctrl_edge,
                     const EdgeDarkenDogParams& p, const Exec& ex) {
    const std::string st = "edge_darken/dog";
    check_input(&color, 4, Channels::Exactly, st, "color");
    check_input(&blurred, 3, Channels::AtLeast, st, "blurred");
    check_full_or_half(blurred, color, st, "blurred", "color");
    check_input(&ctrl_edge, 1, Channels::AtLeast, st, "ctrl_edge");
    check_same_size(ctrl_edge, color, st, "ctrl_edge", "color");
    check_not_alias(dst, &color, st, "color");
    check_not_alias(dst, &blurred, st, "blurred");
    check_not_alias(dst, &ctrl_edge, st, "ctrl_edge");
    check_edge_darken_dog_params(p);
    const int w = color.width(), h = color.height();
    ensure_output(dst, w, h, 4);
    if (ex.traversal == Traversal::Fast) {
        edge_darken_dog_fast(dst, color, blurred, ctrl_edge, p, ex);
        return;
    }
    // The plain reference: eq. 8 pixel by pixel; the blurred colour (RGB planes of a 3- or
    // 4-channel image) sampled at full or half size.
    const Plane br = plane(blurred, 0), bg = plane(blurred, 1), bb = plane(blurred, 2);
    const View<const glm::vec4> c = color.view<glm::vec4>();
    const Plane ctrl = plane(ctrl_edge, control::kEdgeIntensity.channel);
    const View<glm::vec4> o = dst.view<glm::vec4>();
    plain_loop(w, h, [&](int x, int y) {
        const glm::vec3 b(sample_resampled_plane(br, x, y, w, h), sample_resampled_plane(bg, x, y, w, h),
                          sample_resampled_plane(bb, x, y, w, h));
        o(x, y) = edge_darken_dog_px(c(x, y), b, ctrl(x, y), p);
    });
}

void edge_darken_rgbd(ImageF& dst, const ImageF& color, const ImageF& edges, const ImageF& ctrl_edge,
                      const ImageF* bleed, const ImageF* crowd, glm::vec3 substrate, const EdgeDarkenRgbdParams& p,
                      const Exec& ex) {
    const std::string st = "edge_darken/rgbd";
    check_input(&color, 4, Channels::Exactly, st, "color");
    check_input(&edges, 1, Channels::AtLeast, st, "edges");
    check_same_size(edges, color, st, "edges", "color");
    check_input(&ctrl_edge, 1, Channels::AtLeast, st, "ctrl_edge");
    check_same_size(ctrl_edge, color, st, "ctrl_edge", "color");
    check_bleed_mask(bleed, color, st);
    if (crowd) {
        check_input(crowd, 1, Channels::AtLeast, st, "crowd");
        if (crowd->width() > color.width() || crowd->height() > color.height())
            throw Error(st + ": input 'crowd' is " + std::to_string(crowd->width()) + "x" + std::to_string(crowd->height()) +
                        ", larger than 'color' (" + std::to_string(color.width()) + "x" + std::to_string(color.height()) + ")");
    }
    check_not_alias(dst, &edges, st, "edges");
    check_not_alias(dst, crowd, st, "crowd");
    check_not_alias(dst, &ctrl_edge, st, "ctrl_edge");
    check_not_alias(dst, bleed, st, "bleed");
    // In place (dst is color: StageVariant::in_place_input): a pixel reads only its own colour,
    // before its output is written, and unchanged pixels are not written at all (the fast schedule).
    const int w = color.width(), h = color.height();
    ensure_output(dst, w, h, 4);
    if (ex.traversal == Traversal::Fast) {
        edge_darken_rgbd_fast(dst, color, edges, ctrl_edge, bleed, crowd, substrate, p, ex);
        return;
    }
    // The plain reference: §3.1 pixel by pixel.
    const View<const glm::vec4> c = color.view<glm::vec4>();
    const Plane e = plane(edges, 0), ctrl = plane(ctrl_edge, control::kEdgeIntensity.channel);
    static const float kZero = 0.0f;
    const Plane bm = bleed ? plane(*bleed, bleed->channels() == 4 ? 3 : 0) : constant_plane(&kZero, w, h);
    const Plane cw = crowd ? plane(*crowd, 0) : constant_plane(&kZero, w, h);
    const View<glm::vec4> o = dst.view<glm::vec4>();
    plain_loop(w, h, [&](int x, int y) {
        const float b = sample_resampled_plane(bm, x, y, w, h);
        o(x, y) = edge_darken_rgbd_px(c(x, y), e(x, y), ctrl(x, y), b, sample_resampled_plane(cw, x, y, w, h), substrate, p);
    });
}

void register_edge_darken(Registry& r) {
    using D = EdgeDarkenDogParams;
    using R = EdgeDarkenRgbdParams;
    r.add(declare({.stage = "edge_darken",
                   .variant = "dog",
                   .doc = "WC17 eq. 8: I_cb^(1 + Ctrl*max(I_b - I)) with smoothstep-modulated DoG edges",
                   .inputs = {{"color", target::kColor, 4, false},
                              {"blurred", "color.blurred", 4, false, SizeRule::FullOrHalf, "color"},
                              {"ctrl_edge", target::kCtrlEdge, 4, false, SizeRule::Same, "color"}},
                   .outputs = {{"color", "color.darkened", 4, false}},
                   .reference = StageVariant::Reference::PlainLoop,
                   .row_halo = pointwise_rows},
                  ParamTable<D>()
                      .f("intensity", &D::intensity, 0, 50, "global multiplier of Ctrl * max(I_b - I)")
                      .f("ctrl_bias", &D::ctrl_bias, 0, 1, "Ctrl = ctrl_bias + ctrl.edge.r (0: eq. 8 literal, unpainted = none)")
                      .f("smooth_low", &D::smooth_low, 0, 1, "smoothstep lower edge on the DoG edge (ours)")
                      .f("smooth_high", &D::smooth_high, 0, 1, "smoothstep upper edge on the DoG edge (ours)"),
                  [](StageIO& io, const D& p, const Exec& ex) {
                      edge_darken_dog(*io.out[0], *io.in[0], *io.in[1], *io.in[2], p, ex);
                  },
                  check_edge_darken_dog_params));
    r.add(declare({.stage = "edge_darken",
                   .variant = "rgbd",
                   .doc = "WC18 3.1 (MNPR): C^(1 + E_d), E_d = edges*intensity*(1+ci)*sat(5|C-Cs|)*sat(1-3 bleed)",
                   .inputs = {{"color", target::kColor, 4, false},
                              {"edges", "edges.blurred", 1, false, SizeRule::Same, "color"},
                              {"ctrl_edge", target::kCtrlEdge, 4, false, SizeRule::Same, "color"},
                              {"bleed", "bleed", 4, true, SizeRule::FullOrHalf, "color"},
                              {"crowd", "edges.crowd", 1, true}},
                   .outputs = {{"color", "color.darkened", 4, false}},
                   .reference = StageVariant::Reference::PlainLoop,
                   .in_place_input = "color",  // the background (no edges) is left as it is
                   .in_place_output = "color",
                   .row_halo = pointwise_rows},
                  ParamTable<R>()
                      .f("intensity", &R::intensity, 0, 50, "global edge darkening intensity (MNPR default 1)")
                      .f("crowding", &R::crowding, 0, 50,
                         "ours: E_d / (1 + crowding * crowd), crowd = local mean of the edges (0 = WC18)"),
                  [](StageIO& io, const R& p, const Exec& ex) {
                      edge_darken_rgbd(*io.out[0], *io.in[0], *io.in[1], *io.in[2], io.in.size() > 3 ? io.in[3] : nullptr,
                                       io.in.size() > 4 ? io.in[4] : nullptr, globals_of(io).substrate_color, p, ex);
                  }));
}

}  // namespace aq::stylize
