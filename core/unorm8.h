// core/unorm8.h — the float of each 8-bit code as OpenImageIO converts UINT8 to FLOAT, for the
// decoders that stand in for its readers (core/jpeg.h, core/png.h decode_png).
#pragma once

namespace aq {

//! v times the float nearest 1/255, for v = 0..255 (v / 255 differs in the last bit for some
//! codes; tests/core/jpeg_test.cpp, tests/core/png_test.cpp compare with OpenImageIO).
inline const float* unorm8_floats() {
    struct Table {
        float v[256];
        Table() {
            for (int i = 0; i < 256; ++i) v[i] = float(i) * (1.0f / 255.0f);
        }
    };
    static const Table t;
    return t.v;
}

}  // namespace aq
