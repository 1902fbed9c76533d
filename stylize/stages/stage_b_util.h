// stylize/stages/stage_b_util.h — helpers shared by stage group B (edge darkening, gaps & overlaps,
// pigment application, substrate distortion and lighting): single-channel read views, entry
// checks naming the offending port, a fast deterministic pow for the colour-transmittance model,
// and the traversal used by every group-B stage.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <string>

#include <glm/glm.hpp>

#include "core/exec.h"
#include "core/image.h"
#include "stylize/stage.h"

namespace aq::stylize::stage_b {

//! Read-only view of one channel of an image with any channel count; px/row are element strides.
//! A constant plane (px = row = 0) stands in for an absent texture (e.g. the flat paper).
struct Plane {
    const float* p = nullptr;
    std::ptrdiff_t px = 0, row = 0;
    int width = 0, height = 0;

    float operator()(int x, int y) const { return p[y * row + x * px]; }
    float at(int x, int y, Border b) const {
        return (*this)(resolve_border(x, width, b), resolve_border(y, height, b));
    }
};

inline Plane plane(const ImageF& img, int channel) {
    return {img.data() + channel, img.channels(), std::ptrdiff_t(img.channels()) * img.width(), img.width(),
            img.height()};
}

inline Plane constant_plane(const float* value, int w, int h) { return {value, 0, 0, w, h}; }

//! Bilinear sample of a plane at continuous pixel coordinates (pixel centres at +0.5, GL_LINEAR),
//! the same arithmetic as kernels.h sample_bilinear. Coordinates must be finite.
inline float sample_bilinear(const Plane& v, float px, float py, Border b) {
    const float fx = px - 0.5f, fy = py - 0.5f;
    const float x0f = std::floor(fx), y0f = std::floor(fy);
    const float tx = fx - x0f, ty = fy - y0f;
    const int x0 = int(x0f), y0 = int(y0f);
    const float a = v.at(x0, y0, b), c = v.at(x0 + 1, y0, b);
    const float d = v.at(x0, y0 + 1, b), e = v.at(x0 + 1, y0 + 1, b);
    const float top = a + (c - a) * tx;
    const float bot = d + (e - d) * tx;
    return top + (bot - top) * ty;
}

//! Resampling between resolutions, the convention of docs/stylize.md: output pixel x of an
//! n_out-pixel axis samples the source (n_src texels) at ((x + 0.5) / n_out) * n_src — GL's
//! texture() of a full-screen quad — with pixel centres at +0.5 and clamp to edge.
inline float resample_coord(int x, int n_out, int n_src) {
    return ((float(x) + 0.5f) / float(n_out)) * float(n_src);
}

//! GLSL mix(a, b, t) = a*(1-t) + b*t: exact at t = 0 and t = 1 (for finite a, b), which is what
//! "zero control leaves the colour unchanged" needs.
inline float mixf(float a, float b, float t) { return a * (1.0f - t) + b * t; }
inline glm::vec3 mixv(glm::vec3 a, glm::vec3 b, float t) { return a * (1.0f - t) + b * t; }
inline float satf(float x) { return x < 0.0f ? 0.0f : (x > 1.0f ? 1.0f : x); }  // NaN -> NaN
inline float luma709(glm::vec3 c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }
inline float length3(glm::vec3 v) { return std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z); }

// ---------------------------------------------------------------------------------------------
// pow for the colour transmittance model C^d (WC17 eq. 8/9, WC18 §3.1 and eq. 2): x in [0,1]
// (values are clamped to >= 0, as MNPR's pow(abs(c), d) for colours), d > 0 in practice.
// exp2(d * log2(x)) with fixed polynomials: branch-light, no libm call, deterministic on every
// machine (plain float multiply/add, no FMA with our flags). The relative error grows with
// |d log2 x| (float rounding of the exponent): below 1e-5 wherever the result exceeds 1e-30
// (tests/stylize/stage_b_registry_test.cpp StageBMath checks it against std::pow), i.e. far below
// one 8-bit output step.

//! log2(x) for finite x > 0 (normal range).
inline float fast_log2(float x) {
    std::uint32_t bits = std::bit_cast<std::uint32_t>(x);
    int e = int((bits >> 23) & 0xffu) - 127;
    bits = (bits & 0x007fffffu) | 0x3f800000u;  // mantissa in [1, 2)
    float m = std::bit_cast<float>(bits);
    if (m > 1.41421356f) {  // centre on 1: m in [sqrt(1/2), sqrt(2))
        m *= 0.5f;
        e += 1;
    }
    // ln(m) = 2 atanh(t), t = (m-1)/(m+1), |t| <= 0.1716
    const float t = (m - 1.0f) / (m + 1.0f);
    const float t2 = t * t;
    const float s = 1.0f + t2 * (1.0f / 3.0f + t2 * (1.0f / 5.0f + t2 * (1.0f / 7.0f + t2 * (1.0f / 9.0f))));
    return float(e) + (2.0f * 1.44269504f) * t * s;
}

//! 2^y for y in [-126, 127]; 0 below.
inline float fast_exp2(float y) {
    if (!(y > -126.0f)) return y != y ? y : 0.0f;  // NaN passes through, underflow -> 0
    if (y > 127.0f) y = 127.0f;
    const float n = std::floor(y + 0.5f);
    const float f = y - n;  // [-0.5, 0.5]
    const float z = f * 0.69314718f;
    // e^z, Taylor to z^7 (|z| <= 0.347: truncation < 3e-9)
    const float p =
        1.0f + z * (1.0f + z * (0.5f + z * (1.0f / 6.0f + z * (1.0f / 24.0f + z * (1.0f / 120.0f +
                                                                                  z * (1.0f / 720.0f + z * (1.0f / 5040.0f)))))));
    const std::uint32_t scale = std::uint32_t(int(n) + 127) << 23;
    return p * std::bit_cast<float>(scale);
}

//! max(x,0)^d for d >= 0: 0^d = 0 (d > 0), x^0 = 1, NaN in -> NaN out (never UB).
inline float pow_c(float x, float d) {
    if (x != x || d != d) return x + d;  // NaN
    if (x <= 0.0f) return d == 0.0f ? 1.0f : 0.0f;
    if (x == 1.0f || d == 1.0f) return x == 1.0f ? 1.0f : x;
    if (x > 3.0e38f) return x;  // +inf stays inf for d > 0
    const float r = fast_exp2(d * fast_log2(std::max(x, 1.17549435e-38f)));
    // Keep the exact ordering x^d <= x for x < 1 <= d (darkening never brightens by an ulp).
    return (d >= 1.0f && x < 1.0f && r > x) ? x : r;
}

// ---------------------------------------------------------------------------------------------
// Entry checks: every error names the stage and the port (the pipeline maps ports to targets).

inline void check_input(const ImageF* img, int min_channels, const std::string& stage, const std::string& port) {
    if (!img || img->empty()) throw Error(stage + ": input '" + port + "' is missing or empty");
    if (img->channels() < min_channels)
        throw Error(stage + ": input '" + port + "' has " + std::to_string(img->channels()) +
                    " channels, needs at least " + std::to_string(min_channels));
}

inline void check_same_size(const ImageF& img, const ImageF& like, const std::string& stage, const std::string& port,
                            const std::string& like_port) {
    if (!img.same_size(like))
        throw Error(stage + ": input '" + port + "' is " + std::to_string(img.width()) + "x" +
                    std::to_string(img.height()) + ", expected " + std::to_string(like.width()) + "x" +
                    std::to_string(like.height()) + " like '" + like_port + "'");
}

//! Accepts a lower-resolution intermediate of the same image: full size, or half size
//! (ceil(w/2) x ceil(h/2), the WC17 intermediates); anything else is an error naming the port.
inline void check_full_or_half(const ImageF& img, const ImageF& like, const std::string& stage, const std::string& port,
                               const std::string& like_port) {
    const int w = like.width(), h = like.height();
    const bool full = img.width() == w && img.height() == h;
    const bool half = img.width() == (w + 1) / 2 && img.height() == (h + 1) / 2;
    if (!full && !half)
        throw Error(stage + ": input '" + port + "' is " + std::to_string(img.width()) + "x" +
                    std::to_string(img.height()) + ", expected the size of '" + like_port + "' (" + std::to_string(w) +
                    "x" + std::to_string(h) + ") or half of it (" + std::to_string((w + 1) / 2) + "x" +
                    std::to_string((h + 1) / 2) + ")");
}

//! Wraps a registry run function with the exact channel check of every declared input port (the
//! typed functions accept >= the channels they read; through the registry the declared count is
//! the contract).
inline RunFn with_port_check(const StageVariant& v, RunFn fn) {
    return [ins = v.inputs, key = v.key(), fn = std::move(fn)](StageIO& io, const ParamValues& pv, const Exec& ex) {
        for (std::size_t k = 0; k < ins.size(); ++k) {
            const ImageF* img = k < io.in.size() ? io.in[k] : nullptr;
            if (!img) {
                if (!ins[k].optional) throw Error(key + ": input '" + ins[k].name + "' is missing");
                continue;
            }
            if (img->channels() != ins[k].channels)
                throw Error(key + ": input '" + ins[k].name + "' has " + std::to_string(img->channels()) +
                            " channels, expected " + std::to_string(ins[k].channels));
        }
        if (io.out.empty() || !io.out[0]) throw Error(key + ": no output bound");
        fn(io, pv, ex);
    };
}

//! The output must not be one of the inputs (no stage writes its own input).
inline void check_not_alias(const ImageF& dst, const ImageF* in, const std::string& stage, const std::string& port) {
    if (in && &dst == in) throw Error(stage + ": output aliases input '" + port + "'");
}

//! (Re)allocates dst to w x h x c unless it already has that shape.
inline void ensure_output(ImageF& dst, int w, int h, int c) {
    if (dst.width() != w || dst.height() != h || dst.channels() != c) dst = ImageF(w, h, c);
}

//! Border parameter value: 0 = clamp, 1 = mirror.
inline Border border_from(int v) { return v != 0 ? Border::Mirror : Border::Clamp; }

//! Calls row(y, x0, x1) for every row segment of roi with the traversal of ex: one row-major loop
//! for Reference, oneTBB tiles for Fast. Each pixel's value depends only on the inputs, so the
//! bytes are the same for every traversal and thread count.
template <class F>
void for_each_row_segment(const Exec& ex, Roi roi, F&& row) {
    for_each_tile(ex, roi, [&](Roi r) {
        for (int y = r.y0; y < r.y1; ++y) row(y, r.x0, r.x1);
    });
}

//! The pipeline-wide values (defaults when the caller passed none).
inline const Globals& globals_of(const StageIO& io) {
    static const Globals kDefault{};
    return io.globals ? *io.globals : kDefault;
}

}  // namespace aq::stylize::stage_b
