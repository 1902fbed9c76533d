// core/png.h — the PNG encoder of display images (issue 13: animations at 1080p).
//
// Every other format, and PNG images with alpha, are encoded by OpenImageIO (core/oiio_module.cpp),
// told that memory holds straight alpha as PNG does; this encoder writes grey and RGB only. Grey and RGB PNG (every stylised --out image) are written here because the
// deflate step is most of an animation's writing time and OpenImageIO's PNG writer (libpng) can
// only use zlib. The deflate is ISA-L's igzip (a Debian library; kPngIsalLevel below): 2x faster
// than libdeflate's level 1 on our 1080p frames, which was 2.2x faster than zlib's
// (docs/performance.md "Writing files"); --compression none writes
// libdeflate's stored blocks. The container is the PNG specification's (ISO/IEC 15948, W3C PNG 2nd
// edition): signature, IHDR, sRGB with the gAMA and cHRM values the specification recommends beside
// it (11.3.3.5), the description as a tEXt chunk (iTXt when it is not ASCII), one IDAT holding the
// zlib stream of the rows (filter type 0 on every row: the paper grain makes the predictors
// useless, the same choice as before), IEND. Files are read back by OpenImageIO like any PNG
// (tests/core/png_test.cpp).
//
// The decoder (decode_png) reads 8-bit grey, grey+alpha, RGB and RGBA PNG files and palette files
// (expanded to RGB, a tRNS chunk to alpha, as OpenImageIO's reader does) without
// OpenImageIO, for the same reason as core/jpeg.h: loading OpenImageIO's module costs a process
// ~0.2 s of CPU in the dynamic loader (its ~250 libraries), and the 8-bit base-colour maps of
// textured glTF models (Suzanne, the README's scene; the palette leaves of the ez-tree plants)
// were the only reason a PNG render loaded it. It is libpng with its defaults, as OpenImageIO's
// PNG reader, and gives its values, v x float(1/255), alpha straight as the file stores it (the
// module reads with oiio:UnassociatedAlpha; tests/core/png_decode_test.cpp compares both on every
// such PNG of the shared assets, interlaced and synthetic files). Grey and RGB files with a tRNS
// key, 16-bit and low-bit grey, and any file libpng reports an error on are left to OpenImageIO.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "core/image.h"
#include "core/image_header.h"

namespace aq {

//! The ISA-L (igzip) compression level of PNG files (Compression::Fast). Measured on a steady
//! Suzanne WC18 1080p frame (6.2 MB of rows; docs/performance.md "Writing files"): ISA-L
//! level 2 2.86 MB in 20-22 ms, level 1 2.97 MB in 20-26 ms, level 3 2.84 MB in 39 ms; libdeflate
//! level 1 (used before) 2.72 MB in 36-46 ms in the same runs. Level 2: half the CPU of the frame's
//! deflate for 5 % larger files. ISA-L picks its code path by CPU (SSE4.2, AVX, AVX2); every one of
//! those writes the same bytes (tests/core/png_cpu_variants_test.cpp); an x86-64 CPU without SSE4.2
//! or another architecture gets other compressed bytes for the same pixels (docs/provenance.md).
inline constexpr int kPngIsalLevel = 2;

//! Whether encode_png writes images of `channels` channels: 1 (grey) and 3 (RGB).
inline bool png_encodes(int channels) { return channels == 1 || channels == 3; }

//! Encodes img (1 or 3 channels: grey, RGB) as an 8-bit sRGB PNG into `out`, its
//! values quantised with to_unorm8 (core/io.h). A non-empty `description` becomes the
//! "Description" text chunk (what OpenImageIO reads as ImageDescription). `rows` is scratch for the
//! filtered rows; both vectors keep their capacity for the next call. `stored`: Compression::None,
//! libdeflate's stored blocks (a valid stream, no compression); otherwise ISA-L at kPngIsalLevel.
//! `drop_alpha`: img has 4 channels and the PNG gets the first three (RGB), the bytes of encoding
//! the RGB copy. Throws aq::Error.
void encode_png(const ImageF& img, const std::string& description, std::vector<unsigned char>& out,
                std::vector<unsigned char>& rows, bool stored = false, bool drop_alpha = false);

//! Decodes an 8-bit grey or RGB PNG held in memory: `accept` (core/image_header.h) checks the
//! header (1 or 3 channels) and says where the values go (v x float(1/255)); whatever `accept`
//! throws passes through. Returns false for a PNG left to OpenImageIO (see above) — also after
//! `accept` was called, when libpng reports an error while decoding: the caller then decodes the
//! bytes again with OpenImageIO, which reports the damage as it always did.
bool decode_png(const unsigned char* bytes, std::size_t size, AcceptHeader accept, void* ctx);

}  // namespace aq
