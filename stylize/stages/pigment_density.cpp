// stylize/stages/pigment_density.cpp — spec §4.3 (WC18 pigment turbulence in image space, MNPR
// form). Pointwise: reference and fast run the same per-pixel function (bit-exact). The powers
// are the deterministic pow_c of core/fastmath.h, taken over chunks of a row so the loop
// vectorises (it needs -fno-trapping-math: FP exception flags only, no value changes).
#pragma GCC optimize("no-trapping-math")
#include "stylize/stages/pigment_density.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cmath>

#include "stylize/kernels.h"
#include "stylize/kernels.h"
#include "stylize/stages/toolkit.h"

namespace aq::stylize {

void pigment_density(ImageF& dst, const ImageF& color, const ImageF& ctrl, glm::vec3 substrate,
                     const PigmentDensityParams& p, const Exec& ex) {
    toolkit::check_input(&color, 4, toolkit::Channels::Exactly, "pigment_density", "color");
    toolkit::check_input(&ctrl, 4, toolkit::Channels::Exactly, "pigment_density", "ctrl_pigment");
    toolkit::check_same_size(ctrl, color, "pigment_density", "ctrl_pigment", "color");
    toolkit::check_not_alias(dst, &ctrl, "pigment_density", "ctrl_pigment");  // dst may be color (in place)
    const int w = color.width(), h = color.height();
    toolkit::ensure_output(dst, w, h, 4);
    const float* c = color.data();
    const float* k = ctrl.data();
    float* o = dst.data();
    if (ex.traversal == Traversal::Reference) {  // the plain reference: the formula pixel by pixel
        const View<const glm::vec4> cv = color.view<glm::vec4>(), kv = ctrl.view<glm::vec4>();
        const View<glm::vec4> ov = dst.view<glm::vec4>();
        toolkit::plain_loop(w, h, [&](int x, int y) { ov(x, y) = pigment_density_px(cv(x, y), kv(x, y)[control::kPigmentDensity.channel], substrate, p); });
        return;
    }
    // Chunks of a row: the exponents, the powers in one vectorised loop (x^1 == x exactly in
    // pow_c, so a chunk without paint skips them and keeps |c| bit for bit), then the blend:
    // value for value the formula of pigment_density.h.
    using toolkit::load8;
    using toolkit::store8;
    using toolkit::v8f;
    using toolkit::v8i;
    const v8i alpha = {0, 0, 0, -1, 0, 0, 0, -1};
    const v8f one = v8f{} + 1.0f;
    const v8f sv = {substrate.x, substrate.y, substrate.z, 0.0f, substrate.x, substrate.y, substrate.z, 0.0f};
    const bool substrate_finite = std::isfinite(substrate.x) && std::isfinite(substrate.y) && std::isfinite(substrate.z);
    constexpr int kFloatInf = 0x7f800000;  // bits of +inf: finite non-negative floats lie below
    toolkit::for_each_row_block(ex, h, [&](int y0, int y1) {
        constexpr std::size_t kChunk = 64;
        float d[kChunk], dexp[3 * kChunk], cp[3 * kChunk];
        const std::size_t end = std::size_t(y1) * w;
        for (std::size_t i0 = std::size_t(y0) * w; i0 < end; i0 += kChunk) {
            const std::size_t n = std::min(kChunk, end - i0);
            const float* ci = c + 4 * i0;
            const float* ki = k + 4 * i0;
            float* oi = o + 4 * i0;
            for (std::size_t j = 0; j < n; ++j) d[j] = 1.0f + p.strength * ki[4 * j + control::kPigmentDensity.channel];
            // Painted regions are contiguous: a chunk is usually all painted or all unpainted, so
            // the powers are taken for the whole chunk when any pixel needs one (d != 1, NaN too).
            v8i ne{};
            std::size_t jd = 0;
            for (; jd + 8 <= n; jd += 8) ne |= load8(d + jd) != one;
            bool any = !toolkit::all_zero(ne);
            for (; jd < n; ++jd) any |= d[jd] != 1.0f;
            if (!any) {
                // Every d is 1: the blend below with t = sat(1) = 1 and c' = |c| (the sign bit
                // cleared, as fabs), straight from the colour, two pixels per register.
                // In place, a chunk whose colour values are all finite and without a sign bit
                // (most of a frame's background) holds that result already: s * 0 + c * 1 == c
                // for a finite substrate s. Nothing is written (schedule only).
                if (o == c && substrate_finite) {
                    v8i bad{};
                    std::size_t q = 0;
                    for (; q + 2 <= n; q += 2) {
                        const v8i b = (v8i)load8(ci + 4 * q);
                        bad |= ~alpha & ((b < 0) | (b >= kFloatInf));
                    }
                    bool keep = toolkit::all_zero(bad);
                    for (; q < n && keep; ++q)
                        for (int ch = 0; ch < 3; ++ch) {
                            const std::uint32_t b = std::bit_cast<std::uint32_t>(ci[4 * q + ch]);
                            keep = keep && b < std::uint32_t(kFloatInf);
                        }
                    if (keep) continue;
                }
                std::size_t j = 0;
                for (; j + 2 <= n; j += 2) {
                    const v8f cv = load8(ci + 4 * j);
                    const v8f c1 = simd::abs8(cv);
                    const v8f r = sv * (one - one) + c1 * one;
                    store8(oi + 4 * j, alpha ? cv : r);
                }
                for (; j < n; ++j) {
                    for (int ch = 0; ch < 3; ++ch) oi[4 * j + ch] = mix(substrate[ch], std::fabs(ci[4 * j + ch]), sat(d[j]));
                    oi[4 * j + 3] = ci[4 * j + 3];
                }
                continue;
            }
            for (std::size_t j = 0; j < n; ++j)
                for (int ch = 0; ch < 3; ++ch) cp[3 * j + ch] = std::fabs(ci[4 * j + ch]);
            {
                for (std::size_t j = 0; j < n; ++j)
                    for (int ch = 0; ch < 3; ++ch) dexp[3 * j + ch] = d[j];
                pow_c_many(cp, dexp, cp, 3 * n);
            }
            // The blend two pixels per register: mix(s, c', t) = s (1 - t) + c' t lane by lane with
            // t = sat(d) of each pixel over its lanes, the alpha lanes from the colour; then one pixel.
            std::size_t j = 0;
            for (; j + 2 <= n; j += 2) {
                const v8f dv = v8f{d[j], d[j], d[j], d[j], d[j + 1], d[j + 1], d[j + 1], d[j + 1]};
                const v8f t = toolkit::sat(dv);
                const v8f c1 = {cp[3 * j], cp[3 * j + 1], cp[3 * j + 2], 0.0f, cp[3 * j + 3], cp[3 * j + 4], cp[3 * j + 5], 0.0f};
                const v8f r = sv * (one - t) + c1 * t;
                store8(oi + 4 * j, alpha ? load8(ci + 4 * j) : r);
            }
            for (; j < n; ++j) {
                const float t = sat(d[j]);
                for (int ch = 0; ch < 3; ++ch) oi[4 * j + ch] = mix(substrate[ch], cp[3 * j + ch], t);
                oi[4 * j + 3] = ci[4 * j + 3];
            }
        }
    });
}

void register_pigment_density(Registry& r) {
    using P = PigmentDensityParams;
    r.add(declare({.stage = "pigment_density",
                   .variant = "mnpr",
                   .doc = "WC18/MNPR image-space turbulence: d = 1 + ctrl.pigment.b, c' = |c|^d, mix(substrate, c', sat(d))",
                   .inputs = {{"color", "color.adjusted", 4, false}, {"ctrl_pigment", target::kCtrlPigment, 4, false}},
                   .outputs = {{"color", "color.density", 4, false}},
                   .reference = StageVariant::Reference::PlainLoop,
                   .in_place_input = "color",  // pointwise: each chunk's colour is read before it is written
                   .in_place_output = "color",
                   .row_halo = pointwise_rows,
                   .image_space_turbulence = true},
                  ParamTable<P>().f("strength", &P::strength, 0, 5, "multiplies ctrl.pigment.b (MNPR 1)"),
                  [](StageIO& io, const P& p, const Exec& ex) {
                      pigment_density(*io.out[0], *io.in[0], *io.in[1], globals_of(io).substrate_color, p, ex);
                  }));
}

}  // namespace aq::stylize
