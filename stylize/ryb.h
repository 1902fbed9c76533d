// stylize/ryb.h — RYB (red, yellow, blue) paint-like colour space for the overlaps of WC18 §3.2.
//
// RYB -> RGB is Gossett & Chen 2004 ("Paint inspired color mixing and compositing for
// visualization", InfoVis): trilinear interpolation inside a cube whose eight RYB corners carry
// hand-picked RGB colours (kRybCorners). RGB -> RYB inverts that map numerically (the trilinear map
// has no closed-form inverse): a fixed number of damped Gauss-Newton steps, projected onto the unit
// cube, started from the solution at the nearest node of a 17^3 RGB seed lattice (solved once,
// on first use, from the best point of a 5^3 RYB lattice) — deterministic. Colours outside the
// cube's image (e.g. RGB black, which no RYB mix reaches) map to the closest reachable colour.
//
// mix_ryb is the brightness-preserving mix of Chen et al. 2015 ("Wetbrush", SIGGRAPH Asia) as used
// by WC18: mix the RYB amounts, convert back, then rescale so the result's brightness
// b(c) = sqrt(c^T M c), M = diag(0.241, 0.691, 0.068), is the mix of the inputs' brightnesses.
#pragma once

#include <array>
#include <cstddef>

#include <glm/glm.hpp>

namespace aq::stylize {

//! RGB colours at the RYB cube corners, indexed r + 2*y + 4*b (Gossett & Chen 2004, Fig. 2).
inline constexpr std::array<glm::vec3, 8> kRybCorners = {{
    {1.0f, 1.0f, 1.0f},        // (0,0,0) white paper
    {1.0f, 0.0f, 0.0f},        // (1,0,0) red
    {1.0f, 1.0f, 0.0f},        // (0,1,0) yellow
    {1.0f, 0.5f, 0.0f},        // (1,1,0) orange
    {0.163f, 0.373f, 0.6f},    // (0,0,1) blue
    {0.5f, 0.0f, 0.5f},        // (1,0,1) purple
    {0.0f, 0.66f, 0.2f},       // (0,1,1) green
    {0.2f, 0.094f, 0.0f},      // (1,1,1) black (all pigments)
}};

//! Chen et al. 2015 brightness weights (the diagonal of M).
inline constexpr glm::vec3 kBrightnessWeights{0.241f, 0.691f, 0.068f};

//! Trilinear RYB -> RGB; the input is clamped to [0,1]^3 (NaN components become 0).
glm::vec3 ryb_to_rgb(glm::vec3 ryb);

//! Inverse of ryb_to_rgb in the least-squares sense, result in [0,1]^3.
glm::vec3 rgb_to_ryb(glm::vec3 rgb);

//! rgb_to_ryb of n colours (ryb[i] for rgb[i]; the arrays may not overlap), four at a time in
//! the lanes of one vector: each result has rgb_to_ryb's bits.
void rgb_to_ryb_many(const glm::vec3* rgb, glm::vec3* ryb, std::size_t n);

//! sqrt(c^T M c) (Chen et al. 2015).
float ryb_brightness(glm::vec3 rgb);

//! Mixes two RGB colours in RYB space: t = 0 gives a's RYB amounts, 0.5 the even mix (WC18).
//! brightness_scale multiplies the target brightness (1 = preserve; MNPR darkens by 0.9).
//! The result is clamped to [0,1].
glm::vec3 mix_ryb(glm::vec3 a, glm::vec3 b, float t = 0.5f, float brightness_scale = 1.0f);

//! mix_ryb given the inputs' RYB amounts ra = rgb_to_ryb(a), rb = rgb_to_ryb(b) (computed many
//! at a time by rgb_to_ryb_many): the same result.
glm::vec3 mix_ryb_converted(glm::vec3 a, glm::vec3 b, glm::vec3 ra, glm::vec3 rb, float t, float brightness_scale);

}  // namespace aq::stylize
