// tests/stylize/synthetic_gbuffer.h — deterministic synthetic G-buffers for the stylization tests:
// shapes at different depths, painted control with zero and non-zero regions, and inputs for any
// registered port (so registry-wide tests also cover stages added later).
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "core/image.h"
#include "core/hash.h"
#include "core/targets.h"
#include "stylize/stage.h"

namespace aq::test {

//! Hash-based value noise in [0, 1), keyed by pixel, channel and seed (never by thread).
inline float hash01(int x, int y, int c, std::uint32_t seed) {
    std::uint32_t h = std::uint32_t(x) * 0x8da6b343u ^ std::uint32_t(y) * 0xd8163841u ^ std::uint32_t(c) * 0xcb1ab31fu ^
                      seed * 0x9e3779b9u;
    return float(hash32(h) >> 8) / float(1u << 24);
}

//! Which object covers (x, y): 0 background, 1 disc (front), 2 bar (middle).
inline int object_at(int x, int y, int w, int h) {
    const float dx = x - 0.35f * w, dy = y - 0.5f * h;
    if (dx * dx + dy * dy < 0.09f * w * w) return 1;
    if (x > 0.55f * w && x < 0.8f * w && y > 0.15f * h) return 2;
    return 0;
}

//! A synthetic image for a target name and channel count, render-like: objects with smooth shading
//! and slight texture over a flat background (alpha = coverage); linear depth in scene units
//! (depth.linear, +inf where there is no geometry) or normalised ("depth"); painted control
//! (ctrl.*) smooth on the objects, signed on the bar, zero on the background; edge targets 1 on
//! object boundaries and 0 elsewhere.
inline ImageF synthetic_target(const std::string& name, int channels, int w, int h, std::uint32_t seed = 1) {
    ImageF img(w, h, channels);
    const bool is_ctrl = name.rfind("ctrl.", 0) == 0;
    const bool is_lin_depth = name == target::kDepthLinear;
    const bool is_depth = name == "depth" || name.find("depth") != std::string::npos;
    const bool is_edges = name.find("edges") != std::string::npos;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const int obj = object_at(x, y, w, h);
            const float fx = float(x) / float(w), fy = float(y) / float(h);
            for (int c = 0; c < channels; ++c) {
                const float n = hash01(x, y, c, seed);
                float v;
                if (is_lin_depth) {
                    v = obj == 1 ? 12.0f + 2.0f * fx : obj == 2 ? 25.0f + 1.0f * fy : std::numeric_limits<float>::infinity();
                } else if (is_depth) {
                    v = obj == 1 ? 0.1f + 0.05f * fx : obj == 2 ? 0.4f + 0.02f * fy : 1.0f;
                } else if (is_ctrl) {
                    const float ph = float(c + 1 + int(seed % 5));
                    v = obj == 0 ? 0.0f
                        : obj == 1 ? 0.4f + 0.4f * std::sin(6.0f * fx * ph)
                                   : std::cos(5.0f * fy * ph + 3.0f * fx);
                } else if (is_edges) {
                    v = (obj != object_at(x + 1, y, w, h) || obj != object_at(x, y + 1, w, h)) ? 1.0f : 0.0f;
                } else if (channels == 4 && c == 3) {
                    v = obj == 0 ? 0.0f : 1.0f;  // alpha = coverage
                } else if (obj == 0) {
                    v = 0.95f;
                } else {
                    const float base = obj == 1 ? 0.8f - 0.15f * float(c) : 0.2f + 0.3f * float(c);
                    v = base * (0.7f + 0.3f * fx) + 0.02f * (n - 0.5f);
                }
                img.at(x, y, c) = v;
            }
        }
    return img;
}

//! A G-buffer holding every spec §1 target plus, for the given variant, every input port's
//! default target (intermediates), all at w x h.
inline Targets synthetic_gbuffer(int w, int h, std::uint32_t seed = 1) {
    Targets t;
    auto ch = [](const char* name) { return target::gbuffer_channels(name); };  // core/targets.h layout
    t.set(target::kColor, synthetic_target(target::kColor, ch(target::kColor), w, h, seed));
    t.set(target::kDepthLinear, synthetic_target(target::kDepthLinear, ch(target::kDepthLinear), w, h, seed));
    for (const char* c : control::kTargets) t.set(c, synthetic_target(c, ch(c), w, h, seed + 7));
    t.set(target::kNormal, synthetic_target(target::kNormal, ch(target::kNormal), w, h, seed));
    return t;
}

}  // namespace aq::test
