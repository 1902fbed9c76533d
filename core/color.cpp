// core/color.cpp — linear_to_srgb8: linear_to_srgb of eight values, the same bits, without eight
// powf calls.
//
// linear_to_srgb's power is glibc's powf(v, 1/2.4f). That powf is not correctly rounded: over the
// 70,439,396 floats of (kSrgbLinearThreshold, 1] it differs from the correctly rounded x^(1/2.4)
// in 45,775 of them, always where the exact power lies within 2^-9.25 float ulp of a midpoint
// between two floats (measured, docs/determinism.md "sRGB encode eight at a time"). So:
//   1. x^y is computed in double (a 128-entry log2 table, a degree-5 series of ln(1 + r), a
//      32-entry 2^(j/32) table, a degree-4 series of exp), relative error < 2^-39;
//   2. where that double lies at least kMidpointMargin (2^-8 float ulp) away from every float
//      midpoint, its rounding to float is the rounding of the exact power, and so glibc's result;
//   3. the other lanes (0.8 % of inputs), and every lane outside (kSrgbLinearThreshold, 1], call
//      linear_to_srgb itself.
// tests/core/color_test.cpp compares all 70,439,396 inputs of the power branch with
// linear_to_srgb, bit for bit: the claim of step 2 is checked for the machine's glibc, not assumed.
#include "core/color.h"

#include <cmath>
#include <cstdint>

namespace aq {

namespace {

using simd::v8f;
using simd::v8i;
typedef double v4d __attribute__((vector_size(32)));
typedef std::uint64_t v4u __attribute__((vector_size(32)));
typedef std::int64_t v4l __attribute__((vector_size(32)));
typedef std::uint32_t v4ui __attribute__((vector_size(16)));
typedef float v4f __attribute__((vector_size(16)));

constexpr int kLogBits = 7;  //!< the log2 table: 128 subintervals of the mantissa [1, 2), |r| < 2^-8
constexpr double kLn2 = 0.693147180559945309417232121458176568;
constexpr int kExpBits = 5;  //!< the exp2 table: 2^(j/32), |f ln 2| < 2^-6.5
//! Distance from a float midpoint, in units of 2^-29 float ulp (the 29 mantissa bits a double has
//! beyond a float), under which a lane is left to linear_to_srgb. glibc's powf misrounds only within
//! 2^19.75 units of a midpoint on this domain (measured); 2^21 leaves room for step 1's error
//! (< 2^-39 relative, i.e. < 2^14 units).
constexpr std::int64_t kMidpointMargin = std::int64_t(1) << 21;

struct Tables {
    double invc[1 << kLogBits];  //!< 1 / c_i, c_i the centre of subinterval i
    double logc[1 << kLogBits];  //!< -log2(invc_i), of the double invc_i (so the identity below is exact)
    double exp2j[1 << kExpBits];
    Tables() {
        for (int i = 0; i < (1 << kLogBits); ++i) {
            const double c = 1.0 + (double(i) + 0.5) / double(1 << kLogBits);
            invc[i] = 1.0 / c;
            logc[i] = double(-std::log2(static_cast<long double>(invc[i])));
        }
        for (int j = 0; j < (1 << kExpBits); ++j)
            exp2j[j] = double(std::exp2(static_cast<long double>(j) / (1 << kExpBits)));
    }
};

const Tables& tables() {
    static const Tables t;
    return t;
}

//! t[i[k]] in lane k (one AVX2 gather where the build has AVX2).
[[gnu::always_inline]] inline v4d gather(const double* t, v4ui i) {
#ifdef __AVX2__
    // The masked form with a zero source: the same loads, without the plain form's undefined
    // source register (GCC 12 warns on it: -Wuninitialized).
    const __m256d all = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
    return (v4d)_mm256_mask_i32gather_pd(_mm256_setzero_pd(), t, (__m128i)i, all, 8);
#else
    return v4d{t[i[0]], t[i[1]], t[i[2]], t[i[3]]};
#endif
}

//! x^y for four positive normal floats (exponent e, mantissa m in [1, 2)):
//!   log2 x = e - log2(invc_i) + log2(m invc_i),  m invc_i = 1 + r,  |r| < 2^-8
//!   x^y = 2^t, t = y log2 x = (k 32 + j + f 32) / 32:  2^k 2^(j/32) exp(f ln 2)
[[gnu::always_inline]] inline v4d pow_positive(v4f x, double y, const Tables& T) {
    const v4ui u = (v4ui)x;
    const v4ui e = (u >> 23) - 127u;  // x < 2^-126 is not passed
    const v4ui i = (u >> (23 - kLogBits)) & ((1u << kLogBits) - 1u);
    const v4d m = __builtin_convertvector((v4f)((u & 0x7fffffu) | 0x3f800000u), v4d);
    const v4d invc = gather(T.invc, i), logc = gather(T.logc, i);
    const v4d r = m * invc - 1.0;  // the product rounded once; the subtraction is exact
    // ln(1 + r) to r^5 (the next term < 2^-50).
    const v4d ln1p = r * (1.0 + r * (-1.0 / 2 + r * (1.0 / 3 + r * (-1.0 / 4 + r * (1.0 / 5)))));
    const v4d log2x = __builtin_convertvector((std::int32_t __attribute__((vector_size(16))))e, v4d) + logc +
                      ln1p * (1.0 / kLn2);
    const v4d t = y * log2x;  // in [-3.5, 0] on the domain
    constexpr double kShift = 0x1.8p52;  // adding it rounds t 32 to an integer n held in the low bits
    const v4d n_shifted = t * double(1 << kExpBits) + kShift;
    const v4u nb = (v4u)n_shifted;
    const v4d n = n_shifted - kShift;
    const v4d g = (t * double(1 << kExpBits) - n) * (kLn2 / (1 << kExpBits));
    // exp(g), |g| < 2^-6.5, to g^4 (the next term < 2^-39.5 relative).
    const v4d eg = 1.0 + g * (1.0 + g * (1.0 / 2 + g * (1.0 / 6 + g * (1.0 / 24))));
    const v4u j = nb & ((1u << kExpBits) - 1u);
    const v4d s = gather(T.exp2j, v4ui{std::uint32_t(j[0]), std::uint32_t(j[1]), std::uint32_t(j[2]), std::uint32_t(j[3])});
    // 2^k: k = (n - j) / 32 added to the exponent field; (nb - j) << (52 - 5) keeps k << 52 only
    // (the shift constant's bits leave at the top), two's complement for k < 0.
    return (v4d)((v4u)(s * eg) + ((nb - j) << (52 - kExpBits)));
}

//! Lanes whose double p lies less than kMidpointMargin from a midpoint between two floats.
inline v4l near_midpoint(v4d p) {
    const v4l low = (v4l)((v4u)p & std::uint64_t(0x1fffffff)) - (std::int64_t(1) << 28);
    return (low < kMidpointMargin) & (low > -kMidpointMargin);
}

//! linear_to_srgb8 of N registers in place, their 2N power chains side by side (each is a chain
//! of dependent multiplies and adds: interleaved, they overlap in the pipeline).
template <int N>
[[gnu::always_inline]] inline void encode(v8f* v) {
    const Tables& T = tables();
    const double y = double(1.0f / kSrgbGamma);  // powf's exponent, exactly
    v8i power[N];
    v4d p[2 * N];
#pragma GCC unroll 8
    for (int k = 0; k < N; ++k) {
        power[k] = (v[k] > kSrgbLinearThreshold) & (v[k] <= 1.0f);  // NaN: neither branch here
        const v8f x = power[k] ? v[k] : v8f{} + 1.0f;               // other lanes: a harmless input
        p[2 * k] = pow_positive(v4f{x[0], x[1], x[2], x[3]}, y, T);
        p[2 * k + 1] = pow_positive(v4f{x[4], x[5], x[6], x[7]}, y, T);
    }
#pragma GCC unroll 8
    for (int k = 0; k < N; ++k) {
        const v4f f0 = __builtin_convertvector(p[2 * k], v4f), f1 = __builtin_convertvector(p[2 * k + 1], v4f);
        const v8f pf = {f0[0], f0[1], f0[2], f0[3], f1[0], f1[1], f1[2], f1[3]};
        const v8f encoded = (1.0f + kSrgbOffset) * pf - kSrgbOffset;  // linear_to_srgb's expression
        v8f out = power[k] ? encoded : v[k] * kSrgbLinearSlope;
        const v4l n0 = near_midpoint(p[2 * k]), n1 = near_midpoint(p[2 * k + 1]);
        const v8i near = {int(n0[0]), int(n0[1]), int(n0[2]), int(n0[3]), int(n1[0]), int(n1[1]), int(n1[2]), int(n1[3])};
        const v8i fallback = ~power[k] & ~(v[k] <= kSrgbLinearThreshold);  // v > 1, NaN
        const v8i slow = fallback | (power[k] & near);
        if (!simd::all_zero(slow))
            for (int i = 0; i < 8; ++i)
                if (slow[i]) out[i] = linear_to_srgb(v[k][i]);
        v[k] = out;
    }
}

}  // namespace

v8f linear_to_srgb8(v8f v) {
    encode<1>(&v);
    return v;
}

void linear_to_srgb8(v8f& a, v8f& b, v8f& c) {
    v8f v[3] = {a, b, c};
    encode<3>(v);
    a = v[0], b = v[1], c = v[2];
}

}  // namespace aq
