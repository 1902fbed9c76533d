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

//! sqrt lane by lane (correctly rounded, as std::sqrt).
inline v8f sqrt8(v8f x) {
#ifdef __AVX__
    return v8f(_mm256_sqrt_ps(__m256(x)));
#else
    for (int i = 0; i < 8; ++i) x[i] = __builtin_sqrtf(x[i]);
    return x;
#endif
}

}  // namespace aq::simd
