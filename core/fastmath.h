// core/fastmath.h — deterministic, vectorisable replacements for libm calls in inner loops (the
// stages' colour transmittance powers; stylize/kernels.h names them in aq::stylize). Written once over the number type (one float, or eight lanes of core/simd.h) with plain
// float multiply/add and selects only (no libm call, no branch), so the scalar and the lane forms
// perform the same IEEE operations: the same bits on every machine and in both traversals (our
// flags forbid FMA contraction, docs/determinism.md). Loops over arrays of values call the array
// form (pow_c_many) rather than relying on GCC's vectorisation of the scalar.
#pragma once

#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "core/lanes.h"
#include "core/simd.h"

namespace aq::maths {

// pow for the colour transmittance model C^d (WC17 eq. 8/9, WC18 §3.1 and eq. 2): x in [0,1]
// (values are clamped to >= 0, as MNPR's pow(abs(c), d) for colours), d > 0 in practice.
// exp2(d * log2(x)) with fixed polynomials: branch-light, no libm call, deterministic on every
// machine (plain float multiply/add, no FMA with our flags). The relative error grows with
// |d log2 x| (float rounding of the exponent): below 1e-5 wherever the result exceeds 1e-30
// (tests/stylize/stage_b_registry_test.cpp StageBMath checks it against std::pow), i.e. far below
// one 8-bit output step.

namespace fastmath_detail {
using lanes::Num;

// pow_c's operations for F = float or eight lanes (simd::v8f): written once, so a lane performs
// exactly the scalar's IEEE operations (conditions combine with & and |, selects are ?:).
template <class F>
inline F pow_lanes(F x, F d) {
    using N = Num<F>;
    using I = typename N::I;
    constexpr float kMin = 1.17549435e-38f, kMax = 3.0e38f;
    const F one = N::k(1.0f), zero = N::k(0.0f);
    const F xs = x > kMin ? (x < kMax ? x : N::k(kMax)) : N::k(kMin);
    // log2(xs): exponent + mantissa in [sqrt(1/2), sqrt(2)), ln(m) = 2 atanh((m-1)/(m+1)).
    auto bits = N::bits(xs);
    I e = I(bits >> 23) - 127;
    bits = (bits & 0x007fffffu) | 0x3f800000u;
    F m = N::from_bits(bits);
    const auto big = m > 1.41421356f;
    const F mh = m * 0.5f;
    const I e1 = e + 1;
    m = big ? mh : m;
    e = big ? e1 : e;
    const F t = (m - 1.0f) / (m + 1.0f);
    const F t2 = t * t;
    // Series 1 + t2/3 + t2^2/5 + t2^3/7 + t2^4/9 in Estrin form: short dependency chains, so the
    // out-of-order core overlaps neighbouring vectors (Horner's 8-deep chain was latency bound).
    const F t4 = t2 * t2;
    const F s = (1.0f + t2 * (1.0f / 3.0f)) + t4 * ((1.0f / 5.0f + t2 * (1.0f / 7.0f)) + t4 * (1.0f / 9.0f));
    const F l = N::to_float(e) + (2.0f * 1.44269504f) * t * s;
    // exp2(y), y = d * l, |f| <= 0.5, e^(f ln 2) by Taylor to degree 7 (truncation < 3e-9).
    const F y0 = d * l;
    const auto over = y0 > -126.0f;  // not underflowing (NaN: underflowing)
    const F yc = y0 < 127.0f ? y0 : N::k(127.0f);
    const F y = over ? yc : N::k(-126.0f);
    const F n = N::floor(y + 0.5f);
    const F z = (y - n) * 0.69314718f;
    const F z2 = z * z, z4 = z2 * z2;  // Estrin form, as above
    const F p = ((1.0f + z) + z2 * (0.5f + z * (1.0f / 6.0f))) +
                z4 * ((1.0f / 24.0f + z * (1.0f / 120.0f)) + z2 * (1.0f / 720.0f + z * (1.0f / 5040.0f)));
    F r = p * N::from_bits(decltype(bits)(N::to_int(n) + 127) << 23);
    r = over ? r : zero;
    r = ((d >= 1.0f) & (x < 1.0f) & (r > x)) ? x : r;
    r = ((x == 1.0f) | (d == 0.0f)) ? one : r;
    r = d == 1.0f ? x : r;
    r = x > kMax ? x : r;
    r = x > 0.0f ? r : (d == 0.0f ? one : zero);
    // A NaN in gives a quiet NaN with the payload of x if x is NaN, else of d: x + x and d + d
    // (x + d would leave the payload of two NaNs to the compiler's choice of operand order).
    const F nan = x != x ? x + x : d + d;
    r = ((x != x) | (d != d)) ? nan : r;
    return r;
}
}  // namespace fastmath_detail

//! max(x,0)^d for d >= 0: 0^d = 0 (d > 0), x^0 = 1, x^1 = x, 1^d = 1, +inf stays inf, NaN in ->
//! NaN out, and x^d <= x for x < 1 <= d (darkening never brightens by an ulp). For d < 0 (a
//! negative painted density) the result is finite: at most 2^127, and 0^d = 0 (GLSL leaves
//! pow(0, d <= 0) undefined; a finite value keeps mix(..., t = 0) exact instead of NaN). Written without
//! branches (selects only); the scalar and the lane forms (pow_c8) are the same IEEE operations,
//! hence the same bits.
inline float pow_c(float x, float d) { return fastmath_detail::pow_lanes(x, d); }

//! pow_c of eight values in lanes (the same bits as pow_c lane by lane).
inline simd::v8f pow_c8(simd::v8f x, simd::v8f d) { return fastmath_detail::pow_lanes(x, d); }

//! r[i] = pow_c(x[i], d[i]) for i < n: eight at a time in pow_c8, the rest one by one. r may be x
//! or d (each group of eight is loaded before it is stored). The loops of the stages' powers call
//! this (GCC's own vectorisation of a pow_c loop evaluated the log series for both candidate
//! mantissas: two divisions per vector instead of one; docs/performance.md).
inline void pow_c_many(const float* x, const float* d, float* r, std::size_t n) {
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8) simd::store8(r + i, pow_c8(simd::load8(x + i), simd::load8(d + i)));
    for (; i < n; ++i) r[i] = pow_c(x[i], d[i]);
}

}  // namespace aq::maths
