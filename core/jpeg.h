// core/jpeg.h — the JPEG decoder of grey and colour (YCbCr/RGB) JPEG files, on libjpeg-turbo (a
// Debian library; core/io.h's decode_image calls it).
//
// Why not OpenImageIO, which reads every other format: the papers of every style are JPEG files
// (../shared/assets/paper), and loading OpenImageIO costs a process 0.25-0.30 s (core/oiio_module.h).
// With this decoder a render that writes PNG and reads no other image (a bare model through WC18,
// the one-shot of issue 13 item 3) never loads it. OpenImageIO's JPEG reader is libjpeg with its
// defaults (islow IDCT, fancy upsampling, warnings not fatal: a truncated file decodes with the
// missing part grey), and so is this one: the decoded values are the same floats, v x float(1/255)
// (tests/core/jpeg_test.cpp compares both on the real papers, grey and colour files and damaged
// ones). CMYK and YCCK files, and any other component count, are left to OpenImageIO (its CMYK to
// RGB conversion is not repeated here).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "core/image_header.h"

namespace aq {

//! Decodes a grey or colour JPEG held in memory: `accept` (core/image_header.h) checks the header
//! (1 or 3 channels) and says where the values go (v x float(1/255)). Returns false, without
//! calling `accept`, for a JPEG this decoder leaves to OpenImageIO (CMYK, YCCK, other component
//! counts). Throws aq::Error (prefixed with `where`) when libjpeg cannot read the file, and
//! whatever `accept` throws.
bool decode_jpeg(const unsigned char* bytes, std::size_t size, const std::string& where, AcceptHeader accept,
                 void* ctx);

class ImageF;

//! The quality of preview JPEGs (the live view while the camera or a slider moves; docs/serve.md):
//! libjpeg's scale, with its default 4:2:0 chroma subsampling.
inline constexpr int kPreviewJpegQuality = 85;

//! Encodes a grey or RGB image, its values quantised with to_unorm8 as encode_png does, as a
//! baseline JPEG of `quality` (1-100) into `out`; `rows` is scratch, both keep their capacity. For
//! previews only: every file Aquarelle writes is lossless. Throws aq::Error.
void encode_jpeg(const ImageF& img, int quality, std::vector<unsigned char>& out, std::vector<unsigned char>& rows);

}  // namespace aq
