// stylize/stages/stroke_ink.cpp — see stroke_ink.h. Reference: plain loop with per-pixel
// resampling; fast: oneTBB rows with precomputed taps (the same values).
#include "stylize/stages/stroke_ink.h"

#include "stylize/stages/toolkit.h"
#include "stylize/stages/wash.h"

namespace aq::stylize {

using namespace toolkit;

void stroke_ink(ImageF& dst, const ImageF& color, const ImageF& ink, const StrokeInkParams& p, const Exec& ex) {
    check_input(&color, 4, Channels::Exactly, "stroke_ink", "color");
    check_input(&ink, 1, Channels::Exactly, "stroke_ink", "ink");
    check_not_alias(dst, &color, "stroke_ink", "color");
    check_not_alias(dst, &ink, "stroke_ink", "ink");
    const int w = color.width(), h = color.height();
    ensure_output(dst, w, h, 4);
    const Plane ip = plane(ink, 0);
    const float* c = color.data();
    float* o = dst.data();
    auto px = [&](int x, int y, float cov) {
        const std::size_t i = std::size_t(y) * w + x;
        const glm::vec3 r = glaze_px(glm::vec3(c[i * 4], c[i * 4 + 1], c[i * 4 + 2]), p.color, sat(p.alpha * cov), false);
        o[i * 4] = r.r, o[i * 4 + 1] = r.g, o[i * 4 + 2] = r.b, o[i * 4 + 3] = c[i * 4 + 3];
    };
    if (ex.traversal == Traversal::Reference) {
        plain_loop(w, h, [&](int x, int y) { px(x, y, sample_resampled_plane(ip, x, y, w, h)); });
        return;
    }
    // Fast: the ink row resampled once (RowResampler; the ink itself at the same size), then the
    // row glazed in registers (glaze_row_of: glaze_px's values).
    const ResampleAxis ax(w, ink.width()), ay(h, ink.height());
    for_each_row_block(ex, h, [&](int y0, int y1) {
        RowResampler<1> up(ink.data(), ink.width(), w, ax, ay);
        std::vector<float> buf(static_cast<std::size_t>(w));
        for (int y = y0; y < y1; ++y) {
            const std::size_t r = std::size_t(y) * w * 4;
            glaze_row_of<false>(o + r, c + r, up.row_or_source(y, buf.data()), 1, w, p.color, p.alpha);
        }
    });
}

namespace {
struct Table {
    float color_r = kInkColor.r, color_g = kInkColor.g, color_b = kInkColor.b, alpha = kInkAlpha;
};
}  // namespace

void register_stroke_ink(Registry& r) {
    static const ParamTable<Table> t = ParamTable<Table>()
        .f("color_r", &Table::color_r, 0, 1, "ink colour (r; display value; ours: dark sepia)")
        .f("color_g", &Table::color_g, 0, 1, "ink colour (g)")
        .f("color_b", &Table::color_b, 0, 1, "ink colour (b)")
        .f("alpha", &Table::alpha, 0, 1, "ink opacity at full coverage (ours: 0.85)");
    StageVariant v;
    v.stage = "stroke_ink";
    v.variant = "over";
    v.doc = "LD06 §4.4: the strokes' ink coverage painted last, over the washes, in one ink colour";
    v.inputs = {{"color", "color.shadowed", 4, false}, {"ink", "ld06.strokes", 1, false}};
    v.outputs = {{"color", "color.inked", 4, false}};
    v.params = t.descs();
    v.run = with_port_check(v, [](StageIO& io, const ParamValues& pv, const Exec& ex) {
        const auto tp = t.from(pv);
        stroke_ink(*io.out[0], *io.in[0], *io.in[1], {{tp.color_r, tp.color_g, tp.color_b}, tp.alpha}, ex);
    });
    v.reference = StageVariant::Reference::PlainLoop;
    r.add(std::move(v));
}

}  // namespace aq::stylize
