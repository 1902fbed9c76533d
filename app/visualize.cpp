// app/visualize.cpp
#include "app/visualize.h"

#include <cmath>
#include <cstdint>
#include <limits>

namespace aq::app {

namespace {
bool starts_with(const std::string& s, const char* p) { return s.rfind(p, 0) == 0; }

float clamp01(float v) { return std::isfinite(v) ? std::min(1.0f, std::max(0.0f, v)) : 0.0f; }

//! Deterministic colour for an object ID (integer hash, not random).
void id_color(std::uint32_t id, float rgb[3]) {
    std::uint32_t h = id * 2654435761u;
    h ^= h >> 15;
    h *= 2246822519u;
    h ^= h >> 13;
    for (int c = 0; c < 3; ++c) rgb[c] = 0.25f + 0.75f * float((h >> (8 * c)) & 0xffu) / 255.0f;
}
}  // namespace

ImageF visualize_target(const std::string& name, const ImageF& img) {
    ImageF out(img.width(), img.height(), 3);
    const int w = img.width(), h = img.height(), nc = img.channels();
    // ID maps (the G-buffer's object IDs, LD06's layer-ID map): one hashed colour per ID.
    if (name == "object_id" || name == "ld06.layer_id") {
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const float v = img.at(x, y, 0);
                float rgb[3] = {0, 0, 0};
                if (std::isfinite(v) && v >= 1.0f) id_color(std::uint32_t(v), rgb);
                for (int c = 0; c < 3; ++c) out.at(x, y, c) = rgb[c];
            }
        return out;
    }
    if (name == "depth.linear") {
        // Background pixels hold the far plane; normalise over the finite range actually present
        // below the maximum so the object is not flattened against it.
        float lo = std::numeric_limits<float>::infinity(), hi = -lo, far = -lo;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                if (std::isfinite(img.at(x, y, 0))) far = std::max(far, img.at(x, y, 0));
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const float v = img.at(x, y, 0);
                if (std::isfinite(v) && v < far) lo = std::min(lo, v), hi = std::max(hi, v);
            }
        const float span = hi > lo ? hi - lo : 1.0f;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const float v = img.at(x, y, 0);
                const float g = (std::isfinite(v) && v < far) ? 1.0f - 0.85f * (v - lo) / span : 0.0f;
                for (int c = 0; c < 3; ++c) out.at(x, y, c) = g;
            }
        return out;
    }
    const bool signed_ctrl = starts_with(name, "ctrl.") || name == "normal";
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) {
                float v = img.at(x, y, nc >= 3 ? c : 0);
                if (signed_ctrl) v = 0.5f + 0.5f * v;
                out.at(x, y, c) = clamp01(v);
            }
    return out;
}

}  // namespace aq::app
