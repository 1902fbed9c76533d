// core/hash.h — SHA-256 (OpenSSL) of bytes and of images, for determinism tests and logs.
#pragma once

#include <cstddef>
#include <string>

#include "core/image.h"

namespace aq {

std::string sha256_hex(const void* data, std::size_t bytes);
//! Hash of width, height, channels and the raw float bytes.
std::string sha256_hex(const ImageF& img);

}  // namespace aq
