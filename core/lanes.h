// core/lanes.h — the one lane layer: the vocabulary a kernel is written in once, over a number
// type F that is one float (glm::vec3 for three) or eight lanes (simd::v8f, Lanes3 for three;
// core/simd.h). Every lane operation is the scalar one — element-wise IEEE, operands in the same
// order, branches as selects of both computed values — and our flags forbid FMA contraction
// (docs/determinism.md), so a lane computes the scalar's bits. Used by the material
// (raster/material.cpp shade_lanes) and the deterministic power (core/fastmath.h pow_lanes).
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

#include "core/maths.h"
#include "core/simd.h"

namespace aq::lanes {

using simd::v8f;
using simd::v8i;

// ---- the number type: what a kernel needs of F beyond + - * / and comparisons ------------------

//! Broadcast constants, bit casts, int <-> float conversions and floor, for one float and for
//! eight lanes. Each is exact (or, for floor, the one correctly defined value).
template <class F>
struct Num;
template <>
struct Num<float> {
    using I = int;
    using U = std::uint32_t;
    static float k(float v) { return v; }
    static U bits(float x) { return std::bit_cast<U>(x); }
    static float from_bits(U b) { return std::bit_cast<float>(b); }
    static float to_float(I i) { return float(i); }
    static I to_int(float x) { return I(x); }
    static float floor(float x) { return std::floor(x); }
};
template <>
struct Num<v8f> {
    using I = v8i;
    typedef std::uint32_t U __attribute__((vector_size(32)));
    static v8f k(float v) { return v8f{} + v; }
    static U bits(v8f x) { return U(x); }
    static v8f from_bits(U b) { return v8f(b); }
    static v8f to_float(I i) { return __builtin_convertvector(i, v8f); }
    static I to_int(v8f x) { return __builtin_convertvector(x, v8i); }
    static v8f floor(v8f x) { return simd::floor8(x); }
};

inline v8f bcast(float x) { return v8f{x, x, x, x, x, x, x, x}; }  // (not 0 + x: keeps -0)
//! x in every lane of F, bit for bit.
template <class F> inline F splat(float x);
template <> inline float splat<float>(float x) { return x; }
template <> inline v8f splat<v8f>(float x) { return bcast(x); }

// ---- three coordinates ---------------------------------------------------------------------

//! Three coordinates of eight lanes (the lane form of glm::vec3).
struct Lanes3 {
    v8f x, y, z;
};
inline Lanes3 bcast(glm::vec3 v) { return {bcast(v.x), bcast(v.y), bcast(v.z)}; }
inline Lanes3 operator+(const Lanes3& a, const Lanes3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Lanes3 operator-(const Lanes3& a, const Lanes3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Lanes3 operator*(const Lanes3& a, const Lanes3& b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
inline Lanes3 operator*(const Lanes3& a, v8f s) { return {a.x * s, a.y * s, a.z * s}; }
inline Lanes3 operator*(v8f s, const Lanes3& a) { return {s * a.x, s * a.y, s * a.z}; }
inline Lanes3 operator*(const Lanes3& a, float s) { return a * bcast(s); }
inline Lanes3 operator-(const Lanes3& a) { return {-a.x, -a.y, -a.z}; }
// Uniform glm vectors on either side, in the operand order of the glm expression.
inline Lanes3 operator+(glm::vec3 a, const Lanes3& b) { return bcast(a) + b; }
inline Lanes3 operator+(const Lanes3& a, glm::vec3 b) { return a + bcast(b); }
inline Lanes3 operator-(glm::vec3 a, const Lanes3& b) { return bcast(a) - b; }
inline Lanes3 operator*(glm::vec3 a, v8f s) { return bcast(a) * s; }

// ---- selects and the functions of both forms -------------------------------------------------

inline float select(bool m, float a, float b) { return m ? a : b; }
inline v8f select(v8i m, v8f a, v8f b) { return m ? a : b; }
inline glm::vec3 select(bool m, glm::vec3 a, glm::vec3 b) { return m ? a : b; }
inline Lanes3 select(v8i m, const Lanes3& a, const Lanes3& b) { return {m ? a.x : b.x, m ? a.y : b.y, m ? a.z : b.z}; }
//! Mask negation: !m for one lane, ~m for eight (-1 where true).
inline bool mask_not(bool m) { return !m; }
inline v8i mask_not(v8i m) { return ~m; }
//! The mask of type M (bool or v8i) true in every lane.
template <class M> inline M mask_all();
template <> inline bool mask_all<bool>() { return true; }
template <> inline v8i mask_all<v8i>() { return v8i{} - 1; }
template <class F> inline F min_of(F a, F b) { return select(b < a, b, a); }  // std::min(a, b)
template <class F> inline F max_of(F a, F b) { return select(a < b, b, a); }  // std::max(a, b)
inline float root(float x) { return std::sqrt(x); }
inline v8f root(v8f x) { return simd::sqrt8(x); }

//! Clamp to [0, 1] (NaN stays NaN, -0 stays -0: the same values as std::min(std::max(x, 0), 1)).
using maths::sat;
inline v8f sat(v8f x) { return min_of(max_of(x, bcast(0.0f)), bcast(1.0f)); }
inline Lanes3 sat(const Lanes3& v) { return {sat(v.x), sat(v.y), sat(v.z)}; }
template <class F> inline F clamp1_of(F v) { return min_of(max_of(v, splat<F>(-1.0f)), splat<F>(1.0f)); }

inline float dot3(glm::vec3 a, glm::vec3 b) { return (a.x * b.x + a.y * b.y) + a.z * b.z; }
inline v8f dot3(const Lanes3& a, const Lanes3& b) { return (a.x * b.x + a.y * b.y) + a.z * b.z; }
//! v * (1 / sqrt(dot(v, v))); the zero vector is returned unchanged.
inline glm::vec3 normalize3(glm::vec3 v) {
    const float l2 = dot3(v, v);
    if (!(l2 > 0.0f)) return v;
    return v * (1.0f / std::sqrt(l2));
}
inline Lanes3 normalize3(const Lanes3& v) {
    const v8f l2 = dot3(v, v);
    return select(l2 > 0.0f, v * (1.0f / root(l2)), v);
}
inline glm::vec3 cross3(glm::vec3 a, glm::vec3 b) { return glm::cross(a, b); }
inline Lanes3 cross3(const Lanes3& a, const Lanes3& b) {  // glm::cross's order of operations
    return {a.y * b.z - b.y * a.z, a.z * b.x - b.z * a.x, a.x * b.y - b.x * a.y};
}
inline float sign_of(float w) { return w < 0.0f ? -1.0f : 1.0f; }
inline v8f sign_of(v8f w) { return select(w < 0.0f, bcast(-1.0f), bcast(1.0f)); }

//! f(value, lane index) applied to each lane (scalar calls: powf, texture fetches).
template <class Fn> inline float each_lane(float x, Fn&& f) { return f(x, 0); }
template <class Fn> inline v8f each_lane(v8f x, Fn&& f) {
    for (int i = 0; i < 8; ++i) x[i] = f(x[i], i);
    return x;
}

}  // namespace aq::lanes
