// core/hash.h — SHA-256 (OpenSSL) of bytes and of images, for determinism tests and logs.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "core/image.h"

namespace aq {

//! Lowbias32 integer hash (Chris Wellons): well mixed, cheap, platform independent. Every
//! procedural value (noise fields, synthetic test images) is keyed by position and seed through
//! it, never by thread or time, so it is deterministic by construction.
//! Written once for any unsigned 32-bit lane type: std::uint32_t, or a GCC vector of them
//! (scenes/noise.cpp hashes eight vertices at once with the same steps).
template <class U>
constexpr U hash32_lanes(U x) {
    x ^= x >> 16;
    x *= 0x7feb352dU;
    x ^= x >> 15;
    x *= 0x846ca68bU;
    x ^= x >> 16;
    return x;
}
constexpr std::uint32_t hash32(std::uint32_t x) { return hash32_lanes(x); }

std::string sha256_hex(const void* data, std::size_t bytes);
//! Hash of width, height, channels and the raw float bytes.
std::string sha256_hex(const ImageF& img);

}  // namespace aq
