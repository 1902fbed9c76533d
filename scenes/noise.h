// scenes/noise.h — deterministic 3D value noise for procedural control fields (WC17 §3.2: "a
// procedural noise field may fill a channel automatically").
//
// Keyed only by the (object-space) position and a seed: the same vertex always gets the same value,
// whatever the thread, platform or load order. Lattice values come from an integer hash, the
// interpolation is a quintic fade; results are convex combinations of lattice values, so they
// stay inside [-1, 1] exactly.
#pragma once

#include <cstddef>
#include <cstdint>

#include <glm/glm.hpp>

namespace aq::scene {

//! Value noise in [-1, 1] with unit lattice spacing. Non-finite input gives 0.
float value_noise(const glm::vec3& p, std::uint32_t seed);

//! Parameters of a noise control field: offset + amplitude * fbm(p * frequency).
struct NoiseField {
    float frequency = 1.0f;  //!< lattice cells per object-space unit, > 0
    float amplitude = 1.0f;  //!< scale of the [-1, 1] noise
    float offset = 0.0f;     //!< added after scaling
    std::uint32_t seed = 0;
    int octaves = 1;         //!< fBm octaves [1, 8], each at twice the frequency and half the weight
    //! Positions are object-space coordinates (false) or divided by the diagonal of the mesh's
    //! object-space bounding box first (true: frequency = cells per model size, whatever the
    //! model's units; scene files: "space": "bounds"). Either way the field sticks to the surface.
    bool bounds_relative = false;
};

//! Normalised fBm (weights sum to 1) in [-1, 1], then offset + amplitude * value.
float noise_field(const NoiseField& f, const glm::vec3& p);

//! out[i] = noise_field(f, p[i] * scale) for i < n, bit for bit, eight vertices at a time (the
//! default control of a bare 871k-triangle model evaluates ~2.2 million value noises:
//! docs/performance.md "Stylization" times both). noise_field is its plain reference.
void noise_field_n(const NoiseField& f, const glm::vec3* p, std::size_t n, float scale, float* out);

}  // namespace aq::scene
