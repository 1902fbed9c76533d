// tests/core/decoder_support.h — what the tests of the decoders that stand in for OpenImageIO's
// readers (core/jpeg.h, core/png.h decode_png) share: a header callback and the comparison with
// OpenImageIO's values.
#pragma once

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/image.h"
#include "core/image_header.h"
#include "core/oiio.h"

namespace aq::test {

//! A header callback allocating the ImageF at ctx (zeroed, as core/io.cpp does for OpenImageIO).
inline PixelDest allocate_into(void* ctx, const ImageHeader& h) {
    auto* out = static_cast<ImageF*>(ctx);
    *out = ImageF(h.width, h.height, std::min(h.nchannels, 4));
    return {out->data(), nullptr};
}

//! OpenImageIO's reader `format` ("jpeg", "png") on the bytes, through the module.
inline ImageF decode_with_oiio(const std::vector<unsigned char>& bytes, const std::string& format) {
    ImageF img;
    const std::string e =
        oiio().decode(bytes.data(), bytes.size(), format.c_str(), ("memory." + format).c_str(), allocate_into, &img);
    EXPECT_EQ(e, "");
    return img;
}

//! Same size, channels and bits of every value.
inline void expect_same_values(const ImageF& a, const ImageF& b, const std::string& what) {
    ASSERT_EQ(a.width(), b.width()) << what;
    ASSERT_EQ(a.height(), b.height()) << what;
    ASSERT_EQ(a.channels(), b.channels()) << what;
    ASSERT_GT(a.num_values(), 0u) << what;
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.num_values() * sizeof(float)), 0) << what;
}

}  // namespace aq::test
