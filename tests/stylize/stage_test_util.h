// tests/stylize/stage_test_util.h — small synthetic images for the stage tests.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

#include <glm/glm.hpp>

#include "core/hash.h"

#include "core/image.h"

namespace aq::stylize::testb {

inline ImageF constant(int w, int h, glm::vec4 v) {
    ImageF img(w, h, 4);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 4; ++c) img.at(x, y, c) = v[c];
    return img;
}

//! Deterministic pseudo-random values in [lo, hi) (hash of the index, no global state).
inline float hash01(std::uint32_t i) { return float(hash32(i) >> 8) / float(1u << 24); }

inline ImageF noise(int w, int h, int c, float lo, float hi, std::uint32_t seed) {
    ImageF img(w, h, c);
    for (std::size_t i = 0; i < img.num_values(); ++i)
        img.data()[i] = lo + (hi - lo) * hash01(std::uint32_t(i) * 2654435761u + seed);
    return img;
}

//! Copies img, setting every k-th value to NaN, +Inf or -Inf in turn.
//! Same shape and bit-identical values, except that any NaN equals any NaN: IEEE leaves the sign
//! and payload of a NaN result unspecified (a negation, a swapped commutative operand), so two
//! independent computations (a plain reference loop and a vectorised row kernel) may differ there.
inline bool same_values(const ImageF& a, const ImageF& b) {
    if (a.width() != b.width() || a.height() != b.height() || a.channels() != b.channels()) return false;
    for (std::size_t i = 0; i < a.num_values(); ++i) {
        const float x = a.data()[i], y = b.data()[i];
        if (std::isnan(x) && std::isnan(y)) continue;
        if (std::memcmp(&x, &y, sizeof(float)) != 0) return false;
    }
    return true;
}

inline ImageF poison(const ImageF& img, int k = 7) {
    ImageF out = img;
    const float bad[3] = {std::nanf(""), INFINITY, -INFINITY};
    for (std::size_t i = 0; i < out.num_values(); i += std::size_t(k)) out.data()[i] = bad[(i / k) % 3];
    return out;
}

}  // namespace aq::stylize::testb
