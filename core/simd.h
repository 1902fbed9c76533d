// core/simd.h — eight-lane registers as GCC vector types, shared by the kernels that compute lane
// by lane (stylize/stages/toolkit.h, raster/material.cpp). Element-wise IEEE operations: a lane
// computes exactly what the scalar expression computes (our flags forbid FMA contraction,
// docs/determinism.md), so a vector schedule gives the scalar schedule's bits.
#pragma once

#include <cstring>

#include <immintrin.h>

namespace aq::simd {

//! Eight floats / ints (one AVX2 register with -mavx2, two SSE ones without).
typedef float v8f __attribute__((vector_size(32)));
typedef int v8i __attribute__((vector_size(32)));
typedef float v4f __attribute__((vector_size(16)));  //!< one RGBA pixel in an SSE register

//! Lane indices 0..7 (pixel offsets of a lane in an eight-pixel step).
inline constexpr v8i kLaneIndex8 = {0, 1, 2, 3, 4, 5, 6, 7};

inline v8f load8(const float* p) {
    v8f v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
inline void store8(float* p, v8f v) { std::memcpy(p, &v, sizeof v); }

//! True when every bit of v is 0 (one vptest with AVX).
inline bool all_zero(v8i v) {
#ifdef __AVX__
    return _mm256_testz_si256(__m256i(v), __m256i(v)) != 0;
#else
    long long q[4];
    std::memcpy(q, &v, sizeof q);
    return (q[0] | q[1] | q[2] | q[3]) == 0;
#endif
}

//! Bit i set when lane i of the mask m (all ones or all zeros per lane, as comparisons give) is set.
inline unsigned bits8(v8i m) {
#ifdef __AVX__
    return unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(__m256i(m))));
#else
    unsigned b = 0;
    for (int i = 0; i < 8; ++i) b |= unsigned(m[i] != 0) << i;
    return b;
#endif
}

//! sqrt lane by lane (correctly rounded, as std::sqrt).
inline v8f sqrt8(v8f x) {
#ifdef __AVX__
    return v8f(_mm256_sqrt_ps(__m256(x)));
#else
    for (int i = 0; i < 8; ++i) x[i] = __builtin_sqrtf(x[i]);
    return x;
#endif
}

//! |x| lane by lane: the sign bit cleared, as std::fabs (NaN payloads kept).
inline v8f abs8(v8f x) { return v8f(v8i(x) & 0x7fffffff); }

//! floor lane by lane (one vroundps with AVX: the same value as std::floor for every input,
//! -0, infinities and NaN included).
inline v8f floor8(v8f x) {
#ifdef __AVX__
    return v8f(_mm256_floor_ps(__m256(x)));
#else
    for (int i = 0; i < 8; ++i) x[i] = __builtin_floorf(x[i]);
    return x;
#endif
}

//! base[idx[i]] lane by lane (one vgatherdps with AVX2). Values are loaded, never computed.
inline v8f gather8(const float* base, v8i idx) {
#ifdef __AVX2__
    return v8f(_mm256_i32gather_ps(base, __m256i(idx), 4));
#else
    v8f v;
    for (int i = 0; i < 8; ++i) v[i] = base[idx[i]];
    return v;
#endif
}

//! Lane i: (lo, hi)[idx[i]], the sixteen values of lo then hi, for idx[i] in [0, 16) (two
//! vpermps and a blend with AVX2). Values are moved, never computed.
inline v8f permute16(v8f lo, v8f hi, v8i idx) {
#ifdef __AVX2__
    const __m256i i = __m256i(idx);
    const __m256 a = _mm256_permutevar8x32_ps(__m256(lo), i), b = _mm256_permutevar8x32_ps(__m256(hi), i);
    return v8f(_mm256_blendv_ps(a, b, _mm256_castsi256_ps(_mm256_slli_epi32(i, 28))));  // bit 3: from hi
#else
    v8f v;
    for (int k = 0; k < 8; ++k) v[k] = idx[k] < 8 ? lo[idx[k]] : hi[idx[k] - 8];
    return v;
#endif
}

//! q[0], q[S], ..., q[7 S] (S = 1, 3 or 4: one channel of eight pixels with S interleaved
//! channels), reading only q[0 .. 7 S] (so it is safe at the end of an image). Shuffles only.
template <int S>
inline v8f strided8(const float* q) {
    static_assert(S == 1 || S == 3 || S == 4);
    if constexpr (S == 1) {
        return load8(q);
    } else if constexpr (S == 3) {  // q[0..7], q[8..15], q[14..21]
        const v8f r0 = load8(q), r1 = load8(q + 8), r2 = load8(q + 14);
        const v8f a = __builtin_shufflevector(r0, r1, 0, 3, 6, 9, 12, 15, 0, 0);
        return __builtin_shufflevector(a, r2, 0, 1, 2, 3, 4, 5, 12, 15);
    } else {  // q[0..7], q[8..15], q[16..23], q[21..28]
        const v8f r0 = load8(q), r1 = load8(q + 8), r2 = load8(q + 16), r3 = load8(q + 21);
        const v8f lo = __builtin_shufflevector(r0, r1, 0, 4, 8, 12, 0, 4, 8, 12);
        const v8f hi = __builtin_shufflevector(r2, r3, 0, 4, 11, 15, 0, 4, 11, 15);
        return __builtin_shufflevector(lo, hi, 0, 1, 2, 3, 8, 9, 10, 11);
    }
}

//! Transposes the 8 x 8 matrix held in r[0..7] (row k = r[k]) in place: afterwards r[c][k] is the
//! old r[k][c]. Shuffles only (values are moved, never computed). Eight RGBA pixel pairs become
//! planes: with r[k] = pixels 2k and 2k + 1 of a row (RGBA RGBA), r[c] holds channel c of the even
//! pixels and r[4 + c] that of the odd ones.
inline void transpose8x8(v8f r[8]) {
    v8f t[8];
    for (int k = 0; k < 8; k += 2) {  // unpacklo / unpackhi of row pairs
        t[k] = __builtin_shufflevector(r[k], r[k + 1], 0, 8, 1, 9, 4, 12, 5, 13);
        t[k + 1] = __builtin_shufflevector(r[k], r[k + 1], 2, 10, 3, 11, 6, 14, 7, 15);
    }
    for (int k = 0; k < 8; k += 4) {  // shuffle_ps 0x44 / 0xEE of the pairs' results
        r[k] = __builtin_shufflevector(t[k], t[k + 2], 0, 1, 8, 9, 4, 5, 12, 13);
        r[k + 1] = __builtin_shufflevector(t[k], t[k + 2], 2, 3, 10, 11, 6, 7, 14, 15);
        r[k + 2] = __builtin_shufflevector(t[k + 1], t[k + 3], 0, 1, 8, 9, 4, 5, 12, 13);
        r[k + 3] = __builtin_shufflevector(t[k + 1], t[k + 3], 2, 3, 10, 11, 6, 7, 14, 15);
    }
    for (int c = 0; c < 4; ++c) {  // the 128-bit halves: rows 0-3 low, 4-7 high
        t[c] = __builtin_shufflevector(r[c], r[c + 4], 0, 1, 2, 3, 8, 9, 10, 11);
        t[c + 4] = __builtin_shufflevector(r[c], r[c + 4], 4, 5, 6, 7, 12, 13, 14, 15);
    }
    for (int k = 0; k < 8; ++k) r[k] = t[k];
}

}  // namespace aq::simd
