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
#include <vector>

#include <glm/glm.hpp>

#include "core/exec.h"
#include "core/image.h"
#include "stylize/fastmath.h"
#include "stylize/kernels.h"
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

//! Bilinear sample of a plane: the shared kernels.h sample_bilinear (same arithmetic as every
//! other bilinear tap, pixel centres at +0.5, GL_LINEAR).
using aq::stylize::sample_bilinear;

//! Resampling between resolutions, the convention of docs/stylize.md: output pixel x of an
//! n_out-pixel axis samples the source (n_src texels) at ((x + 0.5) / n_out) * n_src — GL's
//! texture() of a full-screen quad — with pixel centres at +0.5 and clamp to edge.
inline float resample_coord(int x, int n_out, int n_src) {
    return ((float(x) + 0.5f) / float(n_out)) * float(n_src);
}

//! Precomputed bilinear resampling from a src_w x src_h image to out_w x out_h output pixels
//! (resample_coord convention, clamp to edge): per column and per row the two taps and the
//! weight, so the inner loop does no floor/divide/border work. Same float operations as
//! sample_bilinear on resample_coord(), hence the same values bit for bit.
struct Upsampler {
    struct Tap {
        int i0, i1;
        float t;
    };
    std::vector<Tap> cols, rows;

    Upsampler() = default;
    Upsampler(int out_w, int out_h, int src_w, int src_h) : cols(std::size_t(out_w)), rows(std::size_t(out_h)) {
        auto fill = [](std::vector<Tap>& v, int n_out, int n_src) {
            for (int i = 0; i < n_out; ++i) {
                const float f = resample_coord(i, n_out, n_src) - 0.5f;
                const float f0 = std::floor(f);
                const int i0 = int(f0);
                v[std::size_t(i)] = {resolve_border(i0, n_src, Border::Clamp), resolve_border(i0 + 1, n_src, Border::Clamp),
                                     f - f0};
            }
        };
        fill(cols, out_w, src_w);
        fill(rows, out_h, src_h);
    }
    float sample(const Plane& p, int x, int y) const {
        const Tap cx = cols[std::size_t(x)], ry = rows[std::size_t(y)];
        const float a = p(cx.i0, ry.i0), c = p(cx.i1, ry.i0), d = p(cx.i0, ry.i1), e = p(cx.i1, ry.i1);
        const float top = a + (c - a) * cx.t;
        const float bot = d + (e - d) * cx.t;
        return top + (bot - top) * ry.t;
    }
};

//! GLSL mix(a, b, t) = a*(1-t) + b*t: exact at t = 0 and t = 1 (for finite a, b), which is what
//! "zero control leaves the colour unchanged" needs.
inline float mixf(float a, float b, float t) { return a * (1.0f - t) + b * t; }
inline glm::vec3 mixv(glm::vec3 a, glm::vec3 b, float t) { return a * (1.0f - t) + b * t; }
inline float satf(float x) { return x < 0.0f ? 0.0f : (x > 1.0f ? 1.0f : x); }  // NaN -> NaN
inline float luma709(glm::vec3 c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }
inline float length3(glm::vec3 v) { return std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z); }

//! The deterministic vectorisable pow of the colour-transmittance model (stylize/fastmath.h).
using aq::stylize::pow_c;

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

//! (Re)allocates dst to w x h x c unless it already has that shape. The stage then writes the
//! region `written`: a new image is left unfilled when that covers it (no wasted pass over tens of
//! MB), and zero-filled otherwise, so pixels outside a partial roi stay defined.
inline void ensure_output(ImageF& dst, int w, int h, int c, Roi written) {
    if (dst.width() == w && dst.height() == h && dst.channels() == c) return;
    const Roi r = written.clipped(w, h);
    const bool whole = r.x0 == 0 && r.y0 == 0 && r.x1 == w && r.y1 == h;
    dst = whole ? ImageF(w, h, c, kUninitialized) : ImageF(w, h, c);
}

//! Border parameter value: 0 = clamp, 1 = mirror.
inline Border border_from(int v) { return v != 0 ? Border::Mirror : Border::Clamp; }

//! Calls row(y, x0, x1) for every row of roi with the traversal of ex: one row-major loop for
//! Reference, oneTBB blocks of whole rows for Fast. Each pixel's value depends only on the inputs,
//! so the bytes are the same for every traversal and thread count.
//! Whole rows rather than 2-D tiles: these stages are pointwise or read a few pixels around, so
//! tiles buy no cache reuse, while 64-pixel row pieces (1 KiB of RGBA) restart the hardware
//! prefetcher on every row and make a task per 64x64 tile; measured at 1080p, one thread, the
//! tiled fast traversal was 20-50 % slower than the plain reference loop (docs/performance.md).
template <class F>
void for_each_row_segment(const Exec& ex, Roi roi, F&& row) {
    if (roi.empty()) return;
    if (ex.traversal == Traversal::Reference) {
        for (int y = roi.y0; y < roi.y1; ++y) row(y, roi.x0, roi.x1);
        return;
    }
    // Rows per task as group A's row blocks (stage_util.h): tile / 8, within [1, 16] (8 at the
    // default tile): at 1080p ~135 tasks, enough to balance 2-8 threads, small enough to fit L2.
    const int grain = std::max(1, std::min(ex.tile > 0 ? ex.tile / 8 : 8, 16));
    with_arena(ex, [&] {
        tbb::parallel_for(
            tbb::blocked_range<int>(roi.y0, roi.y1, grain),
            [&](const tbb::blocked_range<int>& r) {
                for (int y = r.begin(); y < r.end(); ++y) row(y, roi.x0, roi.x1);
            },
            tbb::simple_partitioner());
    });
}

//! The pipeline-wide values (defaults when the caller passed none).
inline const Globals& globals_of(const StageIO& io) {
    static const Globals kDefault{};
    return io.globals ? *io.globals : kDefault;
}

}  // namespace aq::stylize::stage_b
