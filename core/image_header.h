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

//! Called with the header before any pixel is decoded: checks it (throwing aq::Error, which passes
//! through the decoder unchanged) and returns where to decode the first min(nchannels, 4)
//! channels as float, width x height interleaved.
using AcceptHeader = float* (*)(void* ctx, const ImageHeader& header);

}  // namespace aq
