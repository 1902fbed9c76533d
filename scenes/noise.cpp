// scenes/noise.cpp — deterministic value noise (see the header).
#include "scenes/noise.h"

#include <algorithm>
#include <cmath>

#include "core/hash.h"

namespace aq::scene {
namespace {

using aq::hash32;  // core/hash.h: lowbias32

// The lattice value of cell corner (x, y, z) is hash32 chained over seed', x, y, z (24 high bits
// -> [0, 1] -> [-1, 1], exact in float). The chain's prefixes are shared by the eight corners of a
// cell, so value_noise hashes each prefix once: 15 hash32 per call instead of 32, the same values.
std::uint32_t seed_hash(std::uint32_t seed) { return hash32(seed ^ 0x9e3779b9U); }
float lattice_value(std::uint32_t h) { return float(h >> 8) * (2.0f / 16777215.0f) - 1.0f; }

float fade(float t) { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); }

// Positions are folded into a range where floor() fits an int32 (period 2^20 cells).
constexpr float kWrap = 1048576.0f;

}  // namespace

float value_noise(const glm::vec3& p0, std::uint32_t seed) {
    if (!std::isfinite(p0.x) || !std::isfinite(p0.y) || !std::isfinite(p0.z)) return 0.0f;
    const glm::vec3 p(std::fmod(p0.x, kWrap), std::fmod(p0.y, kWrap), std::fmod(p0.z, kWrap));
    const glm::vec3 f = glm::floor(p);
    const std::int32_t x = std::int32_t(f.x), y = std::int32_t(f.y), z = std::int32_t(f.z);
    const float tx = fade(std::clamp(p.x - f.x, 0.0f, 1.0f));
    const float ty = fade(std::clamp(p.y - f.y, 0.0f, 1.0f));
    const float tz = fade(std::clamp(p.z - f.z, 0.0f, 1.0f));
    auto lerp = [](float a, float b, float t) { return a + (b - a) * t; };
    const std::uint32_t hs = seed_hash(seed);
    const std::uint32_t hx[2] = {hash32(hs ^ std::uint32_t(x)), hash32(hs ^ std::uint32_t(x + 1))};
    std::uint32_t hxy[2][2];  // [dy][dx]
    for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) hxy[dy][dx] = hash32(hx[dx] ^ std::uint32_t(y + dy));
    auto corner = [&](int dx, int dy, int dz) { return lattice_value(hash32(hxy[dy][dx] ^ std::uint32_t(z + dz))); };
    const float c00 = lerp(corner(0, 0, 0), corner(1, 0, 0), tx);
    const float c10 = lerp(corner(0, 1, 0), corner(1, 1, 0), tx);
    const float c01 = lerp(corner(0, 0, 1), corner(1, 0, 1), tx);
    const float c11 = lerp(corner(0, 1, 1), corner(1, 1, 1), tx);
    const float v = lerp(lerp(c00, c10, ty), lerp(c01, c11, ty), tz);
    return std::clamp(v, -1.0f, 1.0f);  // guards the last ulp of the lerps
}

float noise_field(const NoiseField& f, const glm::vec3& p) {
    const int oct = std::clamp(f.octaves, 1, 8);
    float sum = 0.0f, wsum = 0.0f, w = 1.0f, freq = f.frequency;
    for (int o = 0; o < oct; ++o) {
        sum += w * value_noise(p * freq, f.seed + std::uint32_t(o) * 1013U);
        wsum += w;
        w *= 0.5f;
        freq *= 2.0f;
    }
    return f.offset + f.amplitude * std::clamp(sum / wsum, -1.0f, 1.0f);
}

}  // namespace aq::scene
