// scenes/noise.cpp — deterministic value noise (see the header).
#include "scenes/noise.h"

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "core/hash.h"

namespace aq::scene {
namespace {

// The lattice value of cell corner (x, y, z) is hash32 chained over seed', x, y, z (24 high bits
// -> [0, 1] -> [-1, 1], exact in float). The chain's prefixes are shared by the eight corners of a
// cell, so value_noise hashes each prefix once: 15 hash32 per call instead of 32, the same values.
std::uint32_t seed_hash(std::uint32_t seed) { return hash32(seed ^ 0x9e3779b9U); }

// Positions are folded into a range where floor() fits an int32 (period 2^20 cells).
constexpr float kWrap = 1048576.0f;

// Lane types: one vertex (float, std::int32_t, std::uint32_t) or eight (GCC vector extensions:
// AVX2 with -mavx2, pairs of SSE registers otherwise). The maths below is written once for both;
// every operation is an IEEE float operation or an exact integer one, so a vertex's value does not
// depend on which path computed it (tests/scenes/procedural_test.cpp checks it bit for bit).
typedef float f8 __attribute__((vector_size(32)));
typedef std::int32_t i8 __attribute__((vector_size(32)));
typedef std::uint32_t u8 __attribute__((vector_size(32)));
constexpr int kLanes = 8;

template <class F> struct Lanes;
template <> struct Lanes<float> {
    using I = std::int32_t;
    using U = std::uint32_t;
    static float splat(float v) { return v; }
    static float select(bool c, float a, float b) { return c ? a : b; }
    static float floor(float v) { return std::floor(v); }
    static I to_int(float v) { return I(v); }
    static float from_u24(U v) { return float(v); }
};
template <> struct Lanes<f8> {
    using I = i8;
    using U = u8;
    static f8 splat(float v) { return f8{v, v, v, v, v, v, v, v}; }
    static f8 select(i8 c, f8 a, f8 b) { return c ? a : b; }
    //! floor for |v| < 2^23 (the caller guarantees |v| < kWrap): truncate, then step down where
    //! truncation rounded up (negative non-integers). Exact, as std::floor.
    static f8 floor(f8 v) {
        const f8 t = __builtin_convertvector(__builtin_convertvector(v, i8), f8);
        return v < t ? t - splat(1.0f) : t;
    }
    static I to_int(f8 v) { return __builtin_convertvector(v, i8); }  // v integral: exact
    static f8 from_u24(U v) { return __builtin_convertvector(i8(v), f8); }  // v < 2^24: exact
};

//! std::clamp(v, lo, hi) per lane: v < lo ? lo : (hi < v ? hi : v).
template <class F>
F clamp_lanes(F v, float lo, float hi) {
    using L = Lanes<F>;
    return L::select(v < L::splat(lo), L::splat(lo), L::select(L::splat(hi) < v, L::splat(hi), v));
}

template <class U>
auto lattice_value(U h) {
    using F = std::conditional_t<std::is_same_v<U, std::uint32_t>, float, f8>;
    return Lanes<F>::from_u24(h >> 8) * (2.0f / 16777215.0f) - 1.0f;
}

template <class F>
F fade(F t) { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); }

template <class F>
F lerp(F a, F b, F t) { return a + (b - a) * t; }

//! Value noise of p already folded (finite, |p| < kWrap), hs = seed_hash(seed).
template <class F>
F value_noise_folded(F px, F py, F pz, std::uint32_t hs) {
    using L = Lanes<F>;
    using U = typename L::U;
    const F fx = L::floor(px), fy = L::floor(py), fz = L::floor(pz);
    const typename L::I x = L::to_int(fx), y = L::to_int(fy), z = L::to_int(fz);
    const F tx = fade(clamp_lanes(px - fx, 0.0f, 1.0f));
    const F ty = fade(clamp_lanes(py - fy, 0.0f, 1.0f));
    const F tz = fade(clamp_lanes(pz - fz, 0.0f, 1.0f));
    const U hx[2] = {hash32_lanes(hs ^ U(x)), hash32_lanes(hs ^ U(x + 1))};
    U hxy[2][2];  // [dy][dx]
    for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) hxy[dy][dx] = hash32_lanes(hx[dx] ^ U(y + dy));
    auto corner = [&](int dx, int dy, int dz) { return lattice_value(hash32_lanes(hxy[dy][dx] ^ U(z + dz))); };
    const F c00 = lerp(corner(0, 0, 0), corner(1, 0, 0), tx);
    const F c10 = lerp(corner(0, 1, 0), corner(1, 1, 0), tx);
    const F c01 = lerp(corner(0, 0, 1), corner(1, 0, 1), tx);
    const F c11 = lerp(corner(0, 1, 1), corner(1, 1, 1), tx);
    return clamp_lanes(lerp(lerp(c00, c10, ty), lerp(c01, c11, ty), tz), -1.0f, 1.0f);  // guards the last ulp of the lerps
}

//! The octave loop of noise_field, written once: noise(q, seed) is value noise at q.
template <class F, class Noise>
F fbm(const NoiseField& f, const Noise& noise) {
    const int oct = std::clamp(f.octaves, 1, 8);
    F sum = Lanes<F>::splat(0.0f);
    float wsum = 0.0f, w = 1.0f, freq = f.frequency;
    for (int o = 0; o < oct; ++o) {
        sum += w * noise(freq, f.seed + std::uint32_t(o) * 1013U);
        wsum += w;
        w *= 0.5f;
        freq *= 2.0f;
    }
    return f.offset + f.amplitude * clamp_lanes(sum / wsum, -1.0f, 1.0f);
}

}  // namespace

float value_noise(const glm::vec3& p0, std::uint32_t seed) {
    if (!std::isfinite(p0.x) || !std::isfinite(p0.y) || !std::isfinite(p0.z)) return 0.0f;
    const glm::vec3 p(std::fmod(p0.x, kWrap), std::fmod(p0.y, kWrap), std::fmod(p0.z, kWrap));
    return value_noise_folded(p.x, p.y, p.z, seed_hash(seed));
}

float noise_field(const NoiseField& f, const glm::vec3& p) {
    return fbm<float>(f, [&](float freq, std::uint32_t seed) { return value_noise(p * freq, seed); });
}

void noise_field_n(const NoiseField& f, const glm::vec3* p, std::size_t n, float scale, float* out) {
    std::size_t i = 0;
    const int oct = std::clamp(f.octaves, 1, 8);
    for (; i + kLanes <= n; i += kLanes) {
        f8 x, y, z;
        for (int k = 0; k < kLanes; ++k) {
            const glm::vec3 q = p[i + std::size_t(k)] * scale;
            x[k] = q.x, y[k] = q.y, z[k] = q.z;
        }
        // The lanes take the folded path when every octave's position is finite and inside
        // (-kWrap, kWrap), where fmod is the identity (NaN fails the compare); else the scalar one.
        i8 inside = i8{} - 1;  // every lane true
        float freq = f.frequency;
        for (int o = 0; o < oct; ++o, freq *= 2.0f) {
            const f8 lim = Lanes<f8>::splat(kWrap);
            auto in = [&](f8 v) { const f8 a = v * freq; return (a < lim) & (-lim < a); };
            inside &= in(x) & in(y) & in(z);
        }
        bool all = true;
        for (int k = 0; k < kLanes; ++k) all = all && inside[k] != 0;
        if (!all) {
            for (int k = 0; k < kLanes; ++k) out[i + std::size_t(k)] = noise_field(f, p[i + std::size_t(k)] * scale);
            continue;
        }
        const f8 v = fbm<f8>(f, [&](float fq, std::uint32_t seed) {
            return value_noise_folded(x * fq, y * fq, z * fq, seed_hash(seed));
        });
        for (int k = 0; k < kLanes; ++k) out[i + std::size_t(k)] = v[k];
    }
    for (; i < n; ++i) out[i] = noise_field(f, p[i] * scale);
}

}  // namespace aq::scene
