// core/sine.cpp — the float sine of core/sine.h. The algorithm (ARM optimized-routines sinf):
//   |y| < 2^-12           sin y = y
//   |y| < 120             n = nearest quadrant of y, x = y - n pi/2 (one fused multiply-add)
//   finite, |y| >= 120    x from y's mantissa times 2/pi in 96-bit fixed point (Payne-Hanek)
//   then a degree-7 odd polynomial (sine) or degree-8 even one (cosine) in x, in double, picked
//   and signed by the quadrant, rounded once to float.
// The operation order and the fused multiply-adds are those of glibc 2.36's `__sinf_fma`
// (x86-64), so the results equal what std::sin returned on our machines (docs/determinism.md).
#include "core/sine.h"

#include <bit>
#include <cmath>
#include <cstdint>

#include <immintrin.h>

namespace aq {

namespace {

// The constants of optimized-routines' sincosf_data.c (one quadrant table; the other table of
// that file is this one with the cosine coefficients negated).
constexpr double kHalfPiInv24 = 0x1.45f306dc9c883p+23;  // 2/pi * 2^24 (fast reduction)
constexpr double kHalfPi = 0x1.921fb54442d18p+0;        // pi/2
constexpr double kPi63 = 0x1.921fb54442d18p-62;         // pi/2 * 2^-62 (large reduction)
constexpr double kC0 = 0x1p0, kC1 = -0x1.ffffffd0c621cp-2, kC2 = 0x1.55553e1068f19p-5,
                 kC3 = -0x1.6c087e89a359dp-10, kC4 = 0x1.99343027bf8c3p-16;  // cos
constexpr double kS1 = -0x1.555545995a603p-3, kS2 = 0x1.1107605230bc4p-7,
                 kS3 = -0x1.994eb3774cf24p-13;  // sin
constexpr double kQuadrantSign[4] = {1.0, -1.0, -1.0, 1.0};
// 4/pi in 32-bit words at byte offsets 0..15 of its binary expansion (reduce_large).
constexpr std::uint32_t kInvPio4[24] = {
    0xa2,       0xa2f9,     0xa2f983,   0xa2f9836e, 0xf9836e4e, 0x836e4e44, 0x6e4e4415, 0x4e441529,
    0x441529fc, 0x1529fc27, 0x29fc2757, 0xfc2757d1, 0x2757d1f5, 0x57d1f534, 0xd1f534dd, 0xf534ddc0,
    0x34ddc0db, 0xddc0db62, 0xc0db6295, 0xdb629599, 0x6295993c, 0x95993c43, 0x993c4390, 0x3c439041,
};
// Thresholds on the top 12 bits of |y| (exponent and 3 mantissa bits).
constexpr std::uint32_t kTopTiny = 0x398;    // |y| < 2^-12: sin y = y
constexpr std::uint32_t kTopLarge = 0x42f;   // |y| >= 120: large reduction
constexpr std::uint32_t kTopNonFinite = 0x7f8;

inline std::uint32_t top12(std::uint32_t bits) { return (bits >> 20) & 0x7ff; }

// The polynomial in x (reduced), x2 = x * x, for quadrant n with sign index q (q = n, or n plus
// y's sign bit after the large reduction).
inline float poly(double x, int n, int q) {
    const double x2 = x * x;
    if (n & 1) {  // cosine; the quadrant's sign through the negated table
        const double s = (q & 2) ? -1.0 : 1.0;
        const double c1 = std::fma(x2, s * kC1, s * kC0);
        const double c2 = std::fma(x2, s * kC4, s * kC3);
        const double x4 = x2 * x2;
        const double x6 = x2 * x4;
        return float(std::fma(c2, x6, std::fma(x4, s * kC2, c1)));
    }
    const double xs = x * kQuadrantSign[q & 3];
    const double x3 = x2 * xs;
    const double x5 = x2 * x3;
    return float(std::fma(std::fma(x2, kS3, kS2), x5, std::fma(x3, kS1, xs)));
}

// Payne-Hanek: y's 24-bit mantissa times 4/pi, the bits that matter in 96-bit fixed point;
// returns the reduced x and the quadrant n.
inline double reduce_large(std::uint32_t bits, int& n) {
    const std::uint32_t* a = &kInvPio4[(bits >> 26) & 15];
    const std::uint32_t m = ((bits & 0x7fffff) | 0x800000) << ((bits >> 23) & 7);
    std::uint64_t r0 = std::uint32_t(m * a[0]);
    const std::uint64_t r1 = std::uint64_t(m) * a[4];
    const std::uint64_t r2 = std::uint64_t(m) * a[8];
    r0 = ((r0 << 32) | (r2 >> 32)) + r1;
    const std::uint64_t q = (r0 + (std::uint64_t(1) << 61)) >> 62;
    r0 -= q << 62;
    n = int(q);
    return double(std::int64_t(r0)) * kPi63;
}

#ifdef __x86_64__
#define AQ_AVX2_FMA __attribute__((target("avx2,fma")))
// A 32-bit lane mask widened to the 64-bit lanes of four doubles.
AQ_AVX2_FMA inline __m256d wide(__m128i mask) { return _mm256_castsi256_pd(_mm256_cvtepi32_epi64(mask)); }
// All ones where (v & b) == b.
AQ_AVX2_FMA inline __m128i bit_set(__m128i v, int b) {
    return _mm_cmpeq_epi32(_mm_and_si128(v, _mm_set1_epi32(b)), _mm_set1_epi32(b));
}
// kInvPio4[e] (e in [0, 24)) in eight lanes, from the table in three registers.
AQ_AVX2_FMA inline __m256i inv_pio4(const __m256i t[3], __m256i e) {
    const __m256i p0 = _mm256_permutevar8x32_epi32(t[0], e), p1 = _mm256_permutevar8x32_epi32(t[1], e),
                  p2 = _mm256_permutevar8x32_epi32(t[2], e);
    const __m256i r = _mm256_blendv_epi8(p0, p1, _mm256_cmpgt_epi32(e, _mm256_set1_epi32(7)));
    return _mm256_blendv_epi8(r, p2, _mm256_cmpgt_epi32(e, _mm256_set1_epi32(15)));
}

// |y| < 120 for four lanes: n = (int(y * 2/pi * 2^24) + 2^23) >> 24, x = y - n pi/2.
AQ_AVX2_FMA inline __m256d reduce_fast(__m128 y, __m128i& n) {
    const __m256d xd = _mm256_cvtps_pd(y);
    n = _mm256_cvttpd_epi32(_mm256_mul_pd(xd, _mm256_set1_pd(kHalfPiInv24)));
    n = _mm_srai_epi32(_mm_add_epi32(n, _mm_set1_epi32(0x800000)), 24);
    return _mm256_fnmadd_pd(_mm256_cvtepi32_pd(n), _mm256_set1_pd(kHalfPi), xd);
}

// The large reduction of one set of four lanes, from the products' operands in the even 32-bit
// halves of ms, a4s, a8s and r0 * 2^32 in r0_hi: r = r0 << 32 | (m a8) >> 32, plus m a4; the
// quadrant from its top two bits. Replaces x, n, q in the lanes marked in big (y's sign bits
// enter q).
AQ_AVX2_FMA inline void reduce_large4(__m256i r0_hi, __m256i ms, __m256i a4s, __m256i a8s, __m128 y,
                                      __m128i big, __m256d& x, __m128i& n, __m128i& q) {
    __m256i r = _mm256_add_epi64(_mm256_or_si256(r0_hi, _mm256_srli_epi64(_mm256_mul_epu32(ms, a8s), 32)),
                                 _mm256_mul_epu32(ms, a4s));
    const __m256i nl = _mm256_srli_epi64(_mm256_add_epi64(r, _mm256_set1_epi64x(std::int64_t(1) << 61)), 62);
    r = _mm256_sub_epi64(r, _mm256_slli_epi64(nl, 62));
    // int64 -> double, rounded once: hi * 2^32 and lo are exact, so is their sum's rounding.
    const __m256i halves = _mm256_permutevar8x32_epi32(r, _mm256_setr_epi32(1, 3, 5, 7, 0, 2, 4, 6));
    const __m256d h = _mm256_cvtepi32_pd(_mm256_castsi256_si128(halves));
    const __m256d l = _mm256_add_pd(
        _mm256_cvtepi32_pd(_mm_xor_si128(_mm256_extracti128_si256(halves, 1), _mm_set1_epi32(INT32_MIN))),
        _mm256_set1_pd(0x1p31));
    const __m256d xl = _mm256_mul_pd(_mm256_add_pd(_mm256_mul_pd(h, _mm256_set1_pd(0x1p32)), l), _mm256_set1_pd(kPi63));
    const __m128i nl32 = _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(nl, _mm256_setr_epi32(0, 2, 4, 6, 0, 2, 4, 6)));
    x = _mm256_blendv_pd(x, xl, wide(big));
    n = _mm_blendv_epi8(n, nl32, big);
    q = _mm_blendv_epi8(q, _mm_add_epi32(nl32, _mm_srli_epi32(_mm_castps_si128(y), 31)), big);
}

// Four lanes (one set: the even or the odd lanes of eight) of the polynomial and the special
// cases, given y's top 12 bits, the reduced x, the quadrant n and the sign index q.
AQ_AVX2_FMA inline __m128 finish4(__m128 y, __m128i top, __m256d x, __m128i n, __m128i q) {
    const __m256d sign = _mm256_set1_pd(-0.0);
    const __m256d x2 = _mm256_mul_pd(x, x);
    // Sine: x signed where kQuadrantSign[q & 3] is -1 (q & 3 = 1 or 2).
    const __m256d xs = _mm256_xor_pd(x, _mm256_and_pd(sign, wide(bit_set(_mm_xor_si128(q, _mm_srli_epi32(q, 1)), 1))));
    const __m256d x3 = _mm256_mul_pd(x2, xs);
    const __m256d x5 = _mm256_mul_pd(x2, x3);
    const __m256d rs = _mm256_fmadd_pd(_mm256_fmadd_pd(x2, _mm256_set1_pd(kS3), _mm256_set1_pd(kS2)), x5,
                                       _mm256_fmadd_pd(x3, _mm256_set1_pd(kS1), xs));
    // Cosine, negated where q & 2.
    const __m256d c1 = _mm256_fmadd_pd(x2, _mm256_set1_pd(kC1), _mm256_set1_pd(kC0));
    const __m256d c2 = _mm256_fmadd_pd(x2, _mm256_set1_pd(kC4), _mm256_set1_pd(kC3));
    const __m256d x4 = _mm256_mul_pd(x2, x2);
    const __m256d x6 = _mm256_mul_pd(x2, x4);
    __m256d rc = _mm256_fmadd_pd(c2, x6, _mm256_fmadd_pd(x4, _mm256_set1_pd(kC2), c1));
    rc = _mm256_xor_pd(rc, _mm256_and_pd(sign, wide(bit_set(q, 2))));
    __m128 out = _mm256_cvtpd_ps(_mm256_blendv_pd(rs, rc, wide(bit_set(n, 1))));
    // |y| < 2^-12: y; infinities and NaN: (y - y) / (y - y), as sine().
    const __m128i tiny = _mm_cmplt_epi32(top, _mm_set1_epi32(int(kTopTiny)));
    const __m128i nonfinite = _mm_cmpgt_epi32(top, _mm_set1_epi32(int(kTopNonFinite - 1)));
    out = _mm_blendv_ps(out, y, _mm_castsi128_ps(tiny));
    const __m128 d = _mm_sub_ps(y, y);
    return _mm_blendv_ps(out, _mm_div_ps(d, d), _mm_castsi128_ps(nonfinite));
}

// Eight lanes of sine() in AVX2 + FMA. The large reduction's 32 x 32 -> 64-bit products
// (_mm256_mul_epu32) take the even lanes, then the odd ones, so the double work runs on those two
// sets of four (even: lanes 0 2 4 6, odd: 1 3 5 7) and the results are interleaved at the end.
// Both reductions are computed (the large one only when a lane needs it) and selected; the
// quadrant signs are sign-bit flips, which equal glibc's multiplications by +-1 and its negated
// cosine table (round to nearest is symmetric, and neither polynomial's terms are zero there).
// Equal to sine() for every input (tests/core/sine_test.cpp).
AQ_AVX2_FMA void sine8_avx2(const float* in, float* out) {
    const __m256 y = _mm256_loadu_ps(in);
    const __m256i bits = _mm256_castps_si256(y);
    const __m256 ysets = _mm256_permutevar8x32_ps(y, _mm256_setr_epi32(0, 2, 4, 6, 1, 3, 5, 7));
    const __m128 ye = _mm256_castps256_ps128(ysets), yo = _mm256_extractf128_ps(ysets, 1);
    const __m256i top = _mm256_and_si256(_mm256_srli_epi32(_mm256_castps_si256(ysets), 20), _mm256_set1_epi32(0x7ff));
    const __m128i tope = _mm256_castsi256_si128(top), topo = _mm256_extracti128_si256(top, 1);
    __m128i ne, no;
    __m256d xe = reduce_fast(ye, ne), xo = reduce_fast(yo, no);
    __m128i qe = ne, qo = no;
    const __m256i large = _mm256_cmpgt_epi32(top, _mm256_set1_epi32(int(kTopLarge - 1)));
    if (!_mm256_testz_si256(large, large)) {
        const __m256i t[3] = {_mm256_loadu_si256(reinterpret_cast<const __m256i*>(kInvPio4)),
                              _mm256_loadu_si256(reinterpret_cast<const __m256i*>(kInvPio4 + 8)),
                              _mm256_loadu_si256(reinterpret_cast<const __m256i*>(kInvPio4 + 16))};
        const __m256i idx = _mm256_and_si256(_mm256_srli_epi32(bits, 26), _mm256_set1_epi32(15));
        const __m256i shift = _mm256_and_si256(_mm256_srli_epi32(bits, 23), _mm256_set1_epi32(7));
        const __m256i m = _mm256_sllv_epi32(
            _mm256_or_si256(_mm256_and_si256(bits, _mm256_set1_epi32(0x7fffff)), _mm256_set1_epi32(0x800000)), shift);
        const __m256i a0 = inv_pio4(t, idx);
        const __m256i a4 = inv_pio4(t, _mm256_add_epi32(idx, _mm256_set1_epi32(4)));
        const __m256i a8 = inv_pio4(t, _mm256_add_epi32(idx, _mm256_set1_epi32(8)));
        const __m256i r0 = _mm256_mullo_epi32(m, a0);  // the low 32 bits of m * a0
        const __m256i hi32 = _mm256_set1_epi64x(std::int64_t(0xffffffff00000000ull));
        reduce_large4(_mm256_slli_epi64(r0, 32), m, a4, a8, ye, _mm256_castsi256_si128(large), xe, ne, qe);
        reduce_large4(_mm256_and_si256(r0, hi32), _mm256_srli_epi64(m, 32), _mm256_srli_epi64(a4, 32),
                      _mm256_srli_epi64(a8, 32), yo, _mm256_extracti128_si256(large, 1), xo, no, qo);
    }
    const __m128 re = finish4(ye, tope, xe, ne, qe), ro = finish4(yo, topo, xo, no, qo);
    // One 32-byte store: a caller's vector load of out then forwards from it.
    _mm256_storeu_ps(out, _mm256_set_m128(_mm_unpackhi_ps(re, ro), _mm_unpacklo_ps(re, ro)));
}

#undef AQ_AVX2_FMA

bool cpu_has_avx2_fma() {
    static const bool ok = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    return ok;
}
#endif

}  // namespace

float sine(float y) {
    const std::uint32_t bits = std::bit_cast<std::uint32_t>(y);
    const std::uint32_t top = top12(bits);
    if (top < kTopTiny) return y;
    if (top < kTopLarge) {
        const double xd = y;
        const int n = (int(xd * kHalfPiInv24) + 0x800000) >> 24;
        return poly(std::fma(-double(n), kHalfPi, xd), n, n);
    }
    if (top < kTopNonFinite) {
        int n = 0;
        const double x = reduce_large(bits, n);
        return poly(x, n, n + int(bits >> 31));
    }
    const float d = y - y;
    return d / d;
}

void sine8(const float* in, float* out) {
#ifdef __x86_64__
    if (cpu_has_avx2_fma()) {
        sine8_avx2(in, out);
        return;
    }
#endif
    for (int l = 0; l < 8; ++l) out[l] = sine(in[l]);
}

}  // namespace aq
