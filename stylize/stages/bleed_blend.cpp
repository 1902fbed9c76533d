// stylize/stages/bleed_blend.cpp — WC17 eq. (7). Pointwise (plus a bilinear tap for half-resolution
// bleeds): reference and fast run the same per-pixel function (bit-exact).
#include "stylize/stages/bleed_blend.h"

#include "stylize/kernels.h"
#include "stylize/stages/stage_util.h"

namespace aq::stylize {

void bleed_blend(ImageF& dst, const ImageF& color, const ImageF& bleed, const BleedBlendParams& p, const Exec& ex) {
    detail::check_input(color, 4, "bleed_blend", "color");
    detail::check_input(bleed, 4, "bleed_blend", "bleed");
    const int w = color.width(), h = color.height();
    const bool full = bleed.same_size(color);
    if (!full && !(bleed.width() == half_size(w) && bleed.height() == half_size(h)))
        throw Error("bleed_blend: input 'bleed' is " + std::to_string(bleed.width()) + "x" +
                    std::to_string(bleed.height()) + ", expected the size of 'color' (" + std::to_string(w) + "x" +
                    std::to_string(h) + ") or half of it (" + std::to_string(half_size(w)) + "x" +
                    std::to_string(half_size(h)) + ")");
    dst = ImageF(w, h, 4);
    const auto cv = color.view<glm::vec4>();
    const auto bv = bleed.view<glm::vec4>();
    auto ov = dst.view<glm::vec4>();
    detail::for_each_row_block(ex, h, [&](int y0, int y1) {
        for (int y = y0; y < y1; ++y)
            for (int x = 0; x < w; ++x) {
                const glm::vec4 I = cv(x, y);
                const glm::vec4 B = full ? bv(x, y) : sample_resampled(bv, x, y, w, h);
                const float k = sat(p.gain * B.a);
                glm::vec4 o;
                o.r = k * (B.r - I.r) + I.r;
                o.g = k * (B.g - I.g) + I.g;
                o.b = k * (B.b - I.b) + I.b;
                o.a = I.a;
                ov(x, y) = o;
            }
    });
}

void register_bleed_blend(Registry& r) {
    static const ParamTable<BleedBlendParams> t = ParamTable<BleedBlendParams>().f(
        "gain", &BleedBlendParams::gain, 0, 100, "k = sat(gain * bleed.a): 1 = WC17 eq. 7, 5 = MNPR");
    StageVariant v;
    v.stage = "bleed_blend";
    v.variant = "eq7";
    v.doc = "WC17 eq. 7: I_cb = k (B - I) + I, k = sat(gain * mask); half-res bleeds upsampled bilinearly";
    v.inputs = {{"color", "color.density", 4, false}, {"bleed", "bleed", 4, false}};
    v.outputs = {{"color", "color.bled", 4, false}};
    v.params = t.descs();
    v.run = [](StageIO& io, const ParamValues& pv, const Exec& ex) {
        bleed_blend(*io.out[0], *io.in[0], *io.in[1], t.from(pv), ex);
    };
    r.add(std::move(v));
}

}  // namespace aq::stylize
