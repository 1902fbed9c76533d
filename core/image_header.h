// core/image_header.h — what a decoder tells its caller before it decodes any pixel: the header,
// handed to a callback that checks it and says where the pixels go. The same for both decoders,
// core/jpeg.h and OpenImageIO's readers behind core/oiio_module.h; core/io.cpp's callback applies
// the size, channel and budget checks of docs/limits.md. Plain types only: the OpenImageIO module
// includes it and uses nothing of aq_core.
#pragma once

namespace aq {

//! An image file's header as a decoder reads it.
struct ImageHeader {
    int width = 0, height = 0, depth = 1, nchannels = 0;
    bool deep = false;
};

//! Where a decoder puts the pixels: exactly one of the two is set.
struct PixelDest {
    //! The first min(nchannels, 4) channels as float, width x height interleaved (every decoder).
    float* values = nullptr;
    //! The 8-bit codes of an 8-bit file, four per pixel in RGBA order (grey copied to R, G and B; a
    //! missing alpha 255), width x height: only core/png.h and core/jpeg.h fill it, for the
    //! textures that keep their texels as codes (scenes/scene.h TextureCodes).
    unsigned char* rgba_codes = nullptr;
};

//! Called with the header before any pixel is decoded: checks it (throwing aq::Error, which passes
//! through the decoder unchanged) and returns where the pixels go.
using AcceptHeader = PixelDest (*)(void* ctx, const ImageHeader& header);

}  // namespace aq
