// core/color.h — colour-space transfer functions (IEC 61966-2-1 sRGB) and the working spaces of
// the watercolor maths (docs/look.md "Colour management").
//
// glTF 2.0 (§3.9.2, §3.9.3): baseColorFactor and COLOR_n are linear, base-colour textures are
// sRGB-encoded, normal maps are linear data. The watercolor equations of the papers (WC17 eq. 3-9,
// WC18) act on display-referred colour, so the default working space is display-referred sRGB:
// linear inputs are combined in linear, then encoded once (raster/material.cpp).
#pragma once

#include <cmath>

#include "core/simd.h"

namespace aq {

//! sRGB piecewise curve constants (IEC 61966-2-1).
inline constexpr float kSrgbLinearThreshold = 0.0031308f;  //!< linear value where the curve changes
inline constexpr float kSrgbEncodedThreshold = 0.04045f;   //!< encoded value where the curve changes
inline constexpr float kSrgbLinearSlope = 12.92f;
inline constexpr float kSrgbGamma = 2.4f;
inline constexpr float kSrgbOffset = 0.055f;

//! sRGB-encoded value -> linear. Values <= 0 map to themselves scaled (negative stays negative),
//! NaN stays NaN.
inline float srgb_to_linear(float v) {
    if (!(v > kSrgbEncodedThreshold)) return v / kSrgbLinearSlope;
    return std::pow((v + kSrgbOffset) / (1.0f + kSrgbOffset), kSrgbGamma);
}

//! Linear value -> sRGB-encoded. Inverse of srgb_to_linear within float rounding.
inline float linear_to_srgb(float v) {
    if (!(v > kSrgbLinearThreshold)) return v * kSrgbLinearSlope;
    return (1.0f + kSrgbOffset) * std::pow(v, 1.0f / kSrgbGamma) - kSrgbOffset;
}

//! linear_to_srgb of each lane, bit for bit, about 8x faster than eight calls: the powers of the
//! lanes in (kSrgbLinearThreshold, 1] computed in double at once and rounded to float where that
//! rounding is provably powf's, linear_to_srgb itself for the rest (core/color.cpp).
simd::v8f linear_to_srgb8(simd::v8f v);
//! linear_to_srgb8 of three registers at once (an RGB batch: the three computations overlap).
void linear_to_srgb8(simd::v8f& a, simd::v8f& b, simd::v8f& c);

//! Colour space the watercolor maths (G-buffer colour, stylization stages) runs in.
enum class WorkingSpace {
    Display,  //!< display-referred sRGB values, as the papers and MNPR (default; docs/look.md)
    Linear,   //!< linear sRGB primaries; the output is encoded to sRGB at the end
};

}  // namespace aq
