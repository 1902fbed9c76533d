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
    detail::ensure_image(dst, w, h, 4);
    // A half-resolution bleed is upsampled first (detail::resample: the sample_resampled
    // convention, value for value); then eq. 7 per pixel.
    ImageF up;
    if (!full) up = detail::resample(bleed, w, h, ex);
    const float* I = color.data();
    const float* B = full ? bleed.data() : up.data();
    float* o = dst.data();
    const float gain = p.gain;
    detail::for_each_row_block(ex, h, [&](int y0, int y1) {
        for (std::size_t i = std::size_t(y0) * w; i < std::size_t(y1) * w; ++i) {
            const float k = sat(gain * B[4 * i + 3]);
            o[4 * i + 0] = k * (B[4 * i + 0] - I[4 * i + 0]) + I[4 * i + 0];
            o[4 * i + 1] = k * (B[4 * i + 1] - I[4 * i + 1]) + I[4 * i + 1];
            o[4 * i + 2] = k * (B[4 * i + 2] - I[4 * i + 2]) + I[4 * i + 2];
            o[4 * i + 3] = I[4 * i + 3];
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
