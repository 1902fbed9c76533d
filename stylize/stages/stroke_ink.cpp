// stylize/stages/stroke_ink.cpp — see stroke_ink.h. The checks and the reference (a plain loop with
// per-pixel resampling); the fast schedule (oneTBB rows with precomputed taps, the same values) is
// stroke_ink.schedule.cpp.
#include "stylize/stages/stroke_ink.h"

#include "stylize/stages/toolkit.h"
#include "stylize/stages/wash.h"

namespace aq::stylize {

using namespace toolkit;

void stroke_ink(ImageF& dst, const ImageF& color, const ImageF& ink, const StrokeInkParams& p, const Exec& ex) {
    check_input(&color, 4, Channels::Exactly, "stroke_ink", "color");
    check_input(&ink, 1, Channels::Exactly, "stroke_ink", "ink");
    check_not_alias(dst, &ink, "stroke_ink", "ink");
    const bool in_place = &dst == &color;  // only the inked pixels are written
    const int w = color.width(), h = color.height();
    if (!in_place) ensure_output(dst, w, h, 4);
    const Plane ip = plane(ink, 0);
    const float* c = color.data();
    float* o = dst.data();
    if (ex.traversal == Traversal::Reference) {
        plain_loop(w, h, [&](int x, int y) {
            const std::size_t i = std::size_t(y) * w + x;
            const float k = ink_opacity(p.alpha, sample_resampled_plane(ip, x, y, w, h));
            const glm::vec3 d(c[i * 4], c[i * 4 + 1], c[i * 4 + 2]);
            const glm::vec3 r = k == 0.0f ? d : glaze_px(d, p.color, k, false);
            o[i * 4] = r.r, o[i * 4 + 1] = r.g, o[i * 4 + 2] = r.b, o[i * 4 + 3] = c[i * 4 + 3];
        });
        return;
    }
    stroke_ink_fast(dst, color, ink, in_place, p, ex);
}

void register_stroke_ink(Registry& r) {
    using P = StrokeInkParams;
    r.add(declare({.stage = "stroke_ink",
                   .variant = "over",
                   .doc = "LD06 §4.4: the strokes' ink coverage painted last, over the washes, in one ink colour",
                   .inputs = {{"color", "color.shadowed", 4, false}, {"ink", "ld06.strokes", 1, false}},
                   .outputs = {{"color", "color.inked", 4, false}},
                   .reference = StageVariant::Reference::PlainLoop,
                   .in_place_input = "color",  // strokes cover a few per cent of the image
                   .in_place_output = "color"},
                  ParamTable<P>()
                      .f("color_r", field_path(&P::color, &glm::vec3::r), 0, 1, "ink colour (r; display value; ours: dark sepia)")
                      .f("color_g", field_path(&P::color, &glm::vec3::g), 0, 1, "ink colour (g)")
                      .f("color_b", field_path(&P::color, &glm::vec3::b), 0, 1, "ink colour (b)")
                      .f("alpha", &P::alpha, 0, 1, "ink opacity at full coverage (ours: 0.85)"),
                  [](StageIO& io, const P& p, const Exec& ex) { stroke_ink(*io.out[0], *io.in[0], *io.in[1], p, ex); }));
}

}  // namespace aq::stylize
