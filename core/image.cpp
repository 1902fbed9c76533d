// core/image.cpp — ImageF allocation with size limits, border names.
#include "core/image.h"

namespace aq {

void check_image_size(int w, int h, const std::string& what) {
    if (w < 1 || h < 1)
        throw Error(what + ": size " + std::to_string(w) + "x" + std::to_string(h) +
                    " is empty; width and height must be at least 1");
    if (w > kMaxImageSide || h > kMaxImageSide ||
        std::int64_t(w) * std::int64_t(h) > kMaxImagePixels)
        throw Error(what + ": size " + std::to_string(w) + "x" + std::to_string(h) +
                    " exceeds the limit (" + std::to_string(kMaxImageSide) + " px per side, " +
                    std::to_string(kMaxImagePixels) + " px in all; see docs/limits.md)");
}

ImageF::ImageF(int w, int h, int channels, float fill) {
    check_image_size(w, h);
    if (channels < 1 || channels > 4)
        throw Error("image: channel count " + std::to_string(channels) + " is not in [1, 4]");
    w_ = w;
    h_ = h;
    c_ = channels;
    pixels_.assign(std::size_t(w) * h * channels, fill);
}

void ImageF::check_view(std::size_t c) const {
    if (c != std::size_t(c_))
        throw Error("image view of " + std::to_string(c) + " channels over an image of " +
                    std::to_string(c_) + " channels");
}

const char* border_name(Border b) { return b == Border::Clamp ? "clamp" : "mirror"; }

Border parse_border(const std::string& s) {
    if (s == "clamp") return Border::Clamp;
    if (s == "mirror") return Border::Mirror;
    throw Error("unknown border mode '" + s + "' (expected clamp or mirror)");
}

}  // namespace aq
