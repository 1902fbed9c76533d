// stylize/stages/bleed_blend.cpp — WC17 eq. (7). Pointwise (plus a bilinear tap for half-resolution
// bleeds): the checks, the plain reference loop (bleed_blend_px) and the declaration; the fast
// schedule is bleed_blend.schedule.cpp (bit-exact).
#include "stylize/stages/bleed_blend.h"

#include "stylize/kernels.h"
#include "stylize/stages/toolkit.h"

namespace aq::stylize {

void bleed_blend(ImageF& dst, const ImageF& color, const ImageF& bleed, const BleedBlendParams& p, const Exec& ex) {
    toolkit::check_input(&color, 4, toolkit::Channels::Exactly, "bleed_blend", "color");
    toolkit::check_input(&bleed, 4, toolkit::Channels::Exactly, "bleed_blend", "bleed");
    const int w = color.width(), h = color.height();
    toolkit::check_full_or_half(bleed, color, "bleed_blend", "bleed", "color");
    toolkit::check_not_alias(dst, &bleed, "bleed_blend", "bleed");  // dst may be color (in place)
    toolkit::ensure_output(dst, w, h, 4);
    if (ex.traversal == Traversal::Reference) {  // the plain reference: eq. 7 pixel by pixel
        const View<const glm::vec4> c = color.view<glm::vec4>();
        const View<glm::vec4> ov = dst.view<glm::vec4>();
        const toolkit::Plane bp[4] = {toolkit::plane(bleed, 0), toolkit::plane(bleed, 1), toolkit::plane(bleed, 2),
                                      toolkit::plane(bleed, 3)};
        toolkit::plain_loop(w, h, [&](int x, int y) {
            glm::vec4 b;
            for (int ch = 0; ch < 4; ++ch)
                b[ch] = toolkit::sample_resampled_plane(bp[ch], x, y, w, h);
            ov(x, y) = bleed_blend_px(c(x, y), b, p.gain);
        });
        return;
    }
    bleed_blend_fast(dst, color, bleed, p.gain, ex);
}

void register_bleed_blend(Registry& r) {
    using P = BleedBlendParams;
    r.add(declare({.stage = "bleed_blend",
                   .variant = "eq7",
                   .doc = "WC17 eq. 7: I_cb = k (B - I) + I, k = sat(gain * mask); half-res bleeds upsampled bilinearly",
                   .inputs = {{"color", "color.density", 4, false}, {"bleed", "bleed", 4, false, SizeRule::FullOrHalf, "color"}},
                   .outputs = {{"color", "color.bled", 4, false}},
                   .reference = StageVariant::Reference::PlainLoop,
                   .in_place_input = "color",  // pointwise in the colour (the bleed is another image)
                   .in_place_output = "color",
                   .row_halo = pointwise_rows},
                  ParamTable<P>().f("gain", &P::gain, 0, 100, "k = sat(gain * bleed.a): 1 = WC17 eq. 7, 5 = MNPR"),
                  [](StageIO& io, const P& p, const Exec& ex) { bleed_blend(*io.out[0], *io.in[0], *io.in[1], p, ex); }));
}

}  // namespace aq::stylize
