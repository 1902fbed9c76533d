// stylize/stages/pigment_density.schedule.cpp — the fast schedule of pigment_density (spec §4.3;
// the formula, pigment_density_px, in pigment_density.h; the checks and the plain reference loop
// in pigment_density.cpp). Chunks of a row: the exponents, the powers in one vectorised loop
// (pow_c of core/fastmath.h; it needs -fno-trapping-math: FP exception flags only, no value
// changes), then the blend; unpainted chunks skip the powers, and in place keep their colour
// unwritten where it provably holds the result. Value for value the formula (the registry-wide
// traversal test and the PigmentDensity tests of tests/stylize/adjust_test.cpp compare the
// schedules, in place too).
#pragma GCC optimize("no-trapping-math")
#include "stylize/stages/pigment_density.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "stylize/kernels.h"
#include "stylize/stages/toolkit.h"

namespace aq::stylize {

using toolkit::load8;
using toolkit::store8;
using toolkit::v8f;
using toolkit::v8i;

namespace {

constexpr std::size_t kChunk = 64;
constexpr int kFloatInf = 0x7f800000;  //!< bits of +inf: finite non-negative floats lie below
const v8i kAlphaLanes = {0, 0, 0, -1, 0, 0, 0, -1};

//! n pixels from ci into oi whose d are all 1: the blend with t = sat(1) = 1 and c' = |c| (the sign
//! bit cleared, as fabs), straight from the colour, two pixels per register. In place, a chunk
//! whose colour values are all finite and without a sign bit (most of a frame's background) holds
//! that result already: s * 0 + c * 1 == c for a finite substrate s. Nothing is written then.
void unpainted_chunk(const float* ci, float* oi, std::size_t n, const float* d, glm::vec3 substrate, bool substrate_finite) {
    const v8f one = v8f{} + 1.0f;
    const v8f sv = {substrate.x, substrate.y, substrate.z, 0.0f, substrate.x, substrate.y, substrate.z, 0.0f};
    if (oi == ci && substrate_finite) {
        v8i bad{};
        std::size_t q = 0;
        for (; q + 2 <= n; q += 2) {
            const v8i b = (v8i)load8(ci + 4 * q);
            bad |= ~kAlphaLanes & ((b < 0) | (b >= kFloatInf));
        }
        bool keep = toolkit::all_zero(bad);
        for (; q < n && keep; ++q)
            for (int ch = 0; ch < 3; ++ch) {
                const std::uint32_t b = std::bit_cast<std::uint32_t>(ci[4 * q + ch]);
                keep = keep && b < std::uint32_t(kFloatInf);
            }
        if (keep) return;
    }
    std::size_t j = 0;
    for (; j + 2 <= n; j += 2) {
        const v8f cv = load8(ci + 4 * j);
        const v8f c1 = simd::abs8(cv);
        const v8f r = sv * (one - one) + c1 * one;
        store8(oi + 4 * j, kAlphaLanes ? cv : r);
    }
    for (; j < n; ++j) {
        for (int ch = 0; ch < 3; ++ch) oi[4 * j + ch] = mix(substrate[ch], std::fabs(ci[4 * j + ch]), sat(d[j]));
        oi[4 * j + 3] = ci[4 * j + 3];
    }
}

//! n pixels from ci into oi with their exponents d: the powers of |c| in one vectorised loop, then
//! the blend two pixels per register: mix(s, c', t) = s (1 - t) + c' t lane by lane with t = sat(d)
//! of each pixel over its lanes, the alpha lanes from the colour; then one pixel.
void painted_chunk(const float* ci, float* oi, std::size_t n, const float* d, glm::vec3 substrate) {
    const v8f one = v8f{} + 1.0f;
    const v8f sv = {substrate.x, substrate.y, substrate.z, 0.0f, substrate.x, substrate.y, substrate.z, 0.0f};
    float dexp[3 * kChunk], cp[3 * kChunk];
    for (std::size_t j = 0; j < n; ++j)
        for (int ch = 0; ch < 3; ++ch) cp[3 * j + ch] = std::fabs(ci[4 * j + ch]);
    for (std::size_t j = 0; j < n; ++j)
        for (int ch = 0; ch < 3; ++ch) dexp[3 * j + ch] = d[j];
    pow_c_many(cp, dexp, cp, 3 * n);
    std::size_t j = 0;
    for (; j + 2 <= n; j += 2) {
        const v8f dv = v8f{d[j], d[j], d[j], d[j], d[j + 1], d[j + 1], d[j + 1], d[j + 1]};
        const v8f t = toolkit::sat(dv);
        const v8f c1 = {cp[3 * j], cp[3 * j + 1], cp[3 * j + 2], 0.0f, cp[3 * j + 3], cp[3 * j + 4], cp[3 * j + 5], 0.0f};
        const v8f r = sv * (one - t) + c1 * t;
        store8(oi + 4 * j, kAlphaLanes ? load8(ci + 4 * j) : r);
    }
    for (; j < n; ++j) {
        const float t = sat(d[j]);
        for (int ch = 0; ch < 3; ++ch) oi[4 * j + ch] = mix(substrate[ch], cp[3 * j + ch], t);
        oi[4 * j + 3] = ci[4 * j + 3];
    }
}

}  // namespace

void pigment_density_fast(ImageF& dst, const ImageF& color, const ImageF& ctrl, glm::vec3 substrate,
                          const PigmentDensityParams& p, const Exec& ex) {
    const int w = color.width(), h = color.height();
    const float* c = color.data();
    const float* k = ctrl.data();
    float* o = dst.data();
    const v8f one = v8f{} + 1.0f;
    const bool substrate_finite = std::isfinite(substrate.x) && std::isfinite(substrate.y) && std::isfinite(substrate.z);
    toolkit::for_each_row_block(ex, h, [&](int y0, int y1) {
        float d[kChunk];
        const std::size_t end = std::size_t(y1) * w;
        for (std::size_t i0 = std::size_t(y0) * w; i0 < end; i0 += kChunk) {
            const std::size_t n = std::min(kChunk, end - i0);
            const float* ki = k + 4 * i0;
            for (std::size_t j = 0; j < n; ++j) d[j] = 1.0f + p.strength * ki[4 * j + control::kPigmentDensity.channel];
            // Painted regions are contiguous: a chunk is usually all painted or all unpainted, so
            // the powers are taken for the whole chunk when any pixel needs one (d != 1, NaN too).
            v8i ne{};
            std::size_t jd = 0;
            for (; jd + 8 <= n; jd += 8) ne |= load8(d + jd) != one;
            bool any = !toolkit::all_zero(ne);
            for (; jd < n; ++jd) any |= d[jd] != 1.0f;
            if (any) painted_chunk(c + 4 * i0, o + 4 * i0, n, d, substrate);
            else unpainted_chunk(c + 4 * i0, o + 4 * i0, n, d, substrate, substrate_finite);
        }
    });
}

}  // namespace aq::stylize
