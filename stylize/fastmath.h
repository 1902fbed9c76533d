// stylize/fastmath.h — deterministic, vectorisable replacements for libm calls in stage inner
// loops. Written with plain float multiply/add and selects only (no libm call, no branch), so GCC
// vectorises loops over arrays of values and the scalar and vector forms perform the same IEEE
// operations: the same bits on every machine and in both traversals (our flags forbid FMA
// contraction, docs/determinism.md). Loops that should vectorise them need -fno-trapping-math in
// their translation unit (see docs/stylize.md "Speed").
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

namespace aq::stylize {

// pow for the colour transmittance model C^d (WC17 eq. 8/9, WC18 §3.1 and eq. 2): x in [0,1]
// (values are clamped to >= 0, as MNPR's pow(abs(c), d) for colours), d > 0 in practice.
// exp2(d * log2(x)) with fixed polynomials: branch-light, no libm call, deterministic on every
// machine (plain float multiply/add, no FMA with our flags). The relative error grows with
// |d log2 x| (float rounding of the exponent): below 1e-5 wherever the result exceeds 1e-30
// (tests/stylize/stage_b_registry_test.cpp StageBMath checks it against std::pow), i.e. far below
// one 8-bit output step.

//! max(x,0)^d for d >= 0: 0^d = 0 (d > 0), x^0 = 1, x^1 = x, 1^d = 1, +inf stays inf, NaN in ->
//! NaN out, and x^d <= x for x < 1 <= d (darkening never brightens by an ulp). For d < 0 (a
//! negative painted density) the result is finite: at most 2^127, and 0^d = 0 (GLSL leaves
//! pow(0, d <= 0) undefined; a finite value keeps mix(..., t = 0) exact instead of NaN). Written without
//! branches (selects only) so loops over arrays of values vectorise; the scalar and vector forms
//! are the same IEEE operations, hence the same bits.
inline float pow_c(float x, float d) {
    constexpr float kMin = 1.17549435e-38f, kMax = 3.0e38f;
    const float xs = x > kMin ? (x < kMax ? x : kMax) : kMin;
    // log2(xs): exponent + mantissa in [sqrt(1/2), sqrt(2)), ln(m) = 2 atanh((m-1)/(m+1)).
    std::uint32_t bits = std::bit_cast<std::uint32_t>(xs);
    int e = int(bits >> 23) - 127;
    bits = (bits & 0x007fffffu) | 0x3f800000u;
    float m = std::bit_cast<float>(bits);
    const bool big = m > 1.41421356f;
    const float mh = m * 0.5f;
    const int e1 = e + 1;
    m = big ? mh : m;
    e = big ? e1 : e;
    const float t = (m - 1.0f) / (m + 1.0f);
    const float t2 = t * t;
    // Series 1 + t2/3 + t2^2/5 + t2^3/7 + t2^4/9 in Estrin form: short dependency chains, so the
    // out-of-order core overlaps neighbouring vectors (Horner's 8-deep chain was latency bound).
    const float t4 = t2 * t2;
    const float s = (1.0f + t2 * (1.0f / 3.0f)) + t4 * ((1.0f / 5.0f + t2 * (1.0f / 7.0f)) + t4 * (1.0f / 9.0f));
    const float l = float(e) + (2.0f * 1.44269504f) * t * s;
    // exp2(y), y = d * l, |f| <= 0.5, e^(f ln 2) by Taylor to degree 7 (truncation < 3e-9).
    const float y0 = d * l;
    const bool under = !(y0 > -126.0f);
    const float yc = y0 < 127.0f ? y0 : 127.0f;
    const float y = under ? -126.0f : yc;
    const float n = std::floor(y + 0.5f);
    const float z = (y - n) * 0.69314718f;
    const float z2 = z * z, z4 = z2 * z2;  // Estrin form, as above
    const float p = ((1.0f + z) + z2 * (0.5f + z * (1.0f / 6.0f))) +
                    z4 * ((1.0f / 24.0f + z * (1.0f / 120.0f)) + z2 * (1.0f / 720.0f + z * (1.0f / 5040.0f)));
    float r = p * std::bit_cast<float>(std::uint32_t(int(n) + 127) << 23);
    r = under ? 0.0f : r;
    r = (d >= 1.0f && x < 1.0f && r > x) ? x : r;
    r = (x == 1.0f || d == 0.0f) ? 1.0f : r;
    r = d == 1.0f ? x : r;
    r = x > kMax ? x : r;
    r = !(x > 0.0f) ? (d == 0.0f ? 1.0f : 0.0f) : r;
    const float nan = x + d;
    r = (x != x || d != d) ? nan : r;
    return r;
}

}  // namespace aq::stylize
