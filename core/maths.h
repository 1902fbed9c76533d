// core/maths.h — small shared maths of the stages and the raster passes: clamps, smoothstep (scalar
// and 8 lanes), luminance, Gaussian weights, bilinear and resampled sampling. Pure functions, no
// allocation, safe for inner loops. In core so that raster and stylize share it without raster
// including stylize (the layering tests/layering_check.py checks); stylize/kernels.h names them
// in aq::stylize.
#pragma once

#include <cmath>
#include <type_traits>
#include <vector>

#include <glm/glm.hpp>

#ifdef __AVX2__
#include <immintrin.h>
#endif

#include "core/image.h"

namespace aq::maths {

inline float sat(float x) { return x < 0.0f ? 0.0f : (x > 1.0f ? 1.0f : x); }
inline glm::vec3 sat(glm::vec3 v) { return {sat(v.x), sat(v.y), sat(v.z)}; }
inline float lerp(float a, float b, float t) { return a + (b - a) * t; }
inline glm::vec3 lerp(glm::vec3 a, glm::vec3 b, float t) { return a + (b - a) * t; }
//! GLSL smoothstep.
inline float smoothstep(float e0, float e1, float x) {
    const float t = sat((x - e0) / (e1 - e0));
    return t * t * (3.0f - 2.0f * t);
}
#ifdef __AVX2__
//! sat and smoothstep on eight lanes: the scalar forms' operations lane by lane (compare + blend,
//! so a NaN stays NaN as in the scalar code), bit for bit.
inline __m256 sat8(__m256 x) {
    const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f);
    const __m256 v = _mm256_blendv_ps(x, one, _mm256_cmp_ps(x, one, _CMP_GT_OQ));
    return _mm256_blendv_ps(v, zero, _mm256_cmp_ps(x, zero, _CMP_LT_OQ));
}
inline __m256 smoothstep8(float e0, float e1, __m256 x) {
    const __m256 t = sat8(_mm256_div_ps(_mm256_sub_ps(x, _mm256_set1_ps(e0)), _mm256_set1_ps(e1 - e0)));
    return _mm256_mul_ps(_mm256_mul_ps(t, t), _mm256_sub_ps(_mm256_set1_ps(3.0f), _mm256_mul_ps(_mm256_set1_ps(2.0f), t)));
}
#endif
//! Rec. ITU-R BT.709 luma weights (MNPR's luminance(), reference/shaders/common.glsl).
inline constexpr float kLumaR = 0.2126f, kLumaG = 0.7152f, kLumaB = 0.0722f;
inline float luminance(float r, float g, float b) { return kLumaR * r + kLumaG * g + kLumaB * b; }
inline float luminance(glm::vec3 c) { return luminance(c.r, c.g, c.b); }
//! |v| as sqrt(x*x + y*y + z*z) in this order (the GLSL twins' length()).
inline float length3(glm::vec3 v) { return std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z); }

//! Normalised 1-D Gaussian weights for offsets -radius..radius (2*radius+1 taps).
inline std::vector<float> gaussian_weights(int radius, float sigma) {
    std::vector<float> w(2 * radius + 1);
    float sum = 0.0f;
    for (int i = -radius; i <= radius; ++i) {
        w[i + radius] = std::exp(-float(i * i) / (2.0f * sigma * sigma));
        sum += w[i + radius];
    }
    for (float& x : w) x /= sum;
    return w;
}

//! The bilinear blend of four taps — a at (x0, y0), c at (x0 + 1, y0), d at (x0, y0 + 1), e at
//! (x0 + 1, y0 + 1) — by the fractions tx, ty: top = a + (c - a) tx, bot = d + (e - d) tx,
//! top + (bot - top) ty, in this order. The one formula of every bilinear tap (sample_bilinear, the
//! resampling tables, the fast schedules' gathered taps): T is a float, a vector of channels or
//! lanes; tx and ty a float or lanes of T's shape. Each lane and channel gets the scalar's bits.
template <class T, class X, class Y>
inline T bilerp(const T& a, const T& c, const T& d, const T& e, const X& tx, const Y& ty) {
    const T top = a + (c - a) * tx;
    const T bot = d + (e - d) * tx;
    return top + (bot - top) * ty;
}

//! Bilinear sample at continuous pixel coordinates (pixel centres at integer + 0.5, as GL's
//! texture() with GL_LINEAR), with the given border rule for the four taps. V is any view with
//! `at(x, y, border)` (View<const T>, toolkit.h's Plane). Coordinates must be finite.
template <class V>
auto sample_bilinear(const V& v, float px, float py, Border b) {
    using T = std::decay_t<decltype(v.at(0, 0, b))>;
    const float fx = px - 0.5f, fy = py - 0.5f;
    const float x0f = std::floor(fx), y0f = std::floor(fy);
    const float tx = fx - x0f, ty = fy - y0f;
    const int x0 = int(x0f), y0 = int(y0f);
    const T a = v.at(x0, y0, b), c = v.at(x0 + 1, y0, b);
    const T d = v.at(x0, y0 + 1, b), e = v.at(x0 + 1, y0 + 1, b);
    return bilerp(a, c, d, e, tx, ty);
}


//! GLSL mix(): a*(1-t) + b*t. Exact at both ends (t = 0 gives a, t = 1 gives b for finite values),
//! unlike lerp(), which is why stages use it where "zero control leaves the colour unchanged".
inline float mix(float a, float b, float t) { return a * (1.0f - t) + b * t; }
inline glm::vec3 mix(glm::vec3 a, glm::vec3 b, float t) { return a * (1.0f - t) + b * t; }

//! Side of a half-resolution intermediate (WC17 §3.3): ceil(n / 2).
inline int half_size(int n) { return (n + 1) / 2; }

//! Resampling convention between two resolutions (docs/stylize.md): output pixel x of a size-n_out
//! axis samples the source (n_src texels) at continuous coordinate ((x + 0.5) / n_out) * n_src,
//! exactly GL's texture() of a full-screen quad with uv = gl_FragCoord / size, evaluated in this
//! float operation order. Use with sample_bilinear (pixel centres at +0.5, GL_LINEAR).
inline float texel_coord(int x, int n_out, int n_src) {
    return ((float(x) + 0.5f) / float(n_out)) * float(n_src);
}

//! Bilinear resample of v (any size) at output pixel (x, y) of an out_w x out_h image, clamp to
//! edge (GL_CLAMP_TO_EDGE): the up/down-sampling used for half-resolution intermediates. At equal
//! sizes it is exactly the identity (the texel itself, as the GLSL twins' same_or_resample reads it
//! with texelFetch): the bilinear formula is not, since (x + 0.5) / n * n is not always x + 0.5 in
//! float, and a + (c - a) * 0 turns -0 into +0 and a neighbouring infinity into NaN.
template <class T>
T sample_resampled(const View<const T>& v, int x, int y, int out_w, int out_h) {
    if (v.width == out_w && v.height == out_h) return v(x, y);
    return sample_bilinear(v, texel_coord(x, out_w, v.width), texel_coord(y, out_h, v.height),
                           Border::Clamp);
}

}  // namespace aq::maths
