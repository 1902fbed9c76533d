// stylize/stages/stage_util.h — helpers shared by the stage group A implementations: entry checks
// that name the offending target, border-resolved index tables for padded row/column access, and
// the half-resolution size/sampling convention (see docs/stylize.md "Resolution conventions").
#pragma once

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "core/exec.h"
#include "core/image.h"
#include "stylize/kernels.h"
#include "stylize/stage.h"

namespace aq::stylize::detail {

//! Throws aq::Error unless img is non-empty with `channels` channels ("stage: input 'name' ...").
inline void check_input(const ImageF& img, int channels, const std::string& stage, const std::string& name) {
    if (img.empty())
        throw Error(stage + ": input '" + name + "' is empty");
    if (img.channels() != channels)
        throw Error(stage + ": input '" + name + "' has " + std::to_string(img.channels()) +
                    " channels, expected " + std::to_string(channels));
}

//! Throws aq::Error unless img has the same size as `like`.
inline void check_same_size(const ImageF& img, const ImageF& like, const std::string& stage,
                            const std::string& name, const std::string& like_name) {
    if (!img.same_size(like))
        throw Error(stage + ": input '" + name + "' is " + std::to_string(img.width()) + "x" +
                    std::to_string(img.height()) + " but '" + like_name + "' is " +
                    std::to_string(like.width()) + "x" + std::to_string(like.height()));
}

//! Makes img a w x h x c image, reusing its storage when it already has that shape (a caller
//! running a stage every frame then writes into the same pages). Contents are unspecified (a new
//! image is not filled: the stage writes every value).
inline void ensure_image(ImageF& img, int w, int h, int c) {
    if (img.width() != w || img.height() != h || img.channels() != c) img = ImageF(w, h, c, kUninitialized);
}

//! The source index of every padded position -pad..n-1+pad under border rule b.
inline std::vector<int> border_table(int n, int pad, Border b) {
    std::vector<int> t(std::size_t(n + 2 * pad));
    for (int i = -pad; i < n + pad; ++i) t[std::size_t(i + pad)] = resolve_border(i, n, b);
    return t;
}

//! Border parameter (0 = clamp, 1 = mirror) of a parameter map.
inline Border border_param(const ParamValues& p, const char* name = "border") {
    auto it = p.find(name);
    return (it != p.end() && it->second != 0.0) ? Border::Mirror : Border::Clamp;
}

//! The pipeline-wide values of a stage call (defaults when a caller passed none).
inline const Globals& globals_of(const StageIO& io) {
    static const Globals kDefault{};
    return io.globals ? *io.globals : kDefault;
}

//! Eight floats / ints as a GCC vector (one AVX2 register with -mavx2, two SSE ones without):
//! for kernels that keep an accumulator in registers across taps. Element-wise IEEE operations,
//! so a lane computes exactly what the scalar expression computes.
typedef float v8f __attribute__((vector_size(32)));
typedef int v8i __attribute__((vector_size(32)));
inline v8f load8(const float* p) {
    v8f v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
inline void store8(float* p, v8f v) { std::memcpy(p, &v, sizeof v); }

//! Runs f(y0, y1) over row blocks: one call for Reference, oneTBB row blocks for Fast. Each block
//! writes only its own rows, so results cannot depend on the thread count.
template <class F>
void for_each_row_block(const Exec& ex, int h, F&& f) {
    if (h <= 0) return;
    if (ex.traversal == Traversal::Reference) {
        f(0, h);
        return;
    }
    const int grain = std::max(1, std::min(ex.tile > 0 ? ex.tile / 8 : 8, 16));
    with_arena(ex, [&] {
        tbb::parallel_for(
            tbb::blocked_range<int>(0, h, grain), [&](const tbb::blocked_range<int>& r) { f(r.begin(), r.end()); },
            tbb::simple_partitioner());
    });
}


//! Per-axis tables of the resampling convention (kernels.h texel_coord + sample_bilinear, clamp to
//! edge): for output index x, source taps i0[x], i1[x] (already clamped) and weight t[x], computed
//! with exactly sample_bilinear's float operations, so resampled values equal sample_resampled's
//! bit for bit.
struct ResampleAxis {
    std::vector<int> i0, i1;
    std::vector<float> t;
    ResampleAxis(int n_out, int n_src) : i0(std::size_t(n_out)), i1(std::size_t(n_out)), t(std::size_t(n_out)) {
        for (int x = 0; x < n_out; ++x) {
            const float f = texel_coord(x, n_out, n_src) - 0.5f;
            const float f0 = std::floor(f);
            t[std::size_t(x)] = f - f0;
            const int i = int(f0);
            i0[std::size_t(x)] = resolve_border(i, n_src, Border::Clamp);
            i1[std::size_t(x)] = resolve_border(i + 1, n_src, Border::Clamp);
        }
    }
};

//! Output row y (w pixels of C channels, written to o) of the resampling of s (sw texels wide).
//! Stages that consume a resampled image pixel by pixel call this into a row buffer instead of
//! materialising the whole resampled image (same values, no full-size temporary).
//! S: the source's channel count when it differs from C (then s points at the first channel
//! wanted, e.g. data() + 2 resamples channel 2 of an S-channel image without extracting it).
template <int C, int S = C>
void resample_row(const float* s, int sw, float* o, int w, const ResampleAxis& ax, const ResampleAxis& ay, int y) {
    const float ty = ay.t[std::size_t(y)];
    const float* r0 = s + std::size_t(ay.i0[std::size_t(y)]) * sw * S;
    const float* r1 = s + std::size_t(ay.i1[std::size_t(y)]) * sw * S;
    for (int x = 0; x < w; ++x) {
        const float tx = ax.t[std::size_t(x)];
        const std::size_t a0 = std::size_t(ax.i0[std::size_t(x)]) * S, a1 = std::size_t(ax.i1[std::size_t(x)]) * S;
        for (int c = 0; c < C; ++c) {  // C is a constant: unrolled, channels side by side
            const float a = r0[a0 + c], cc = r0[a1 + c], dd = r1[a0 + c], e = r1[a1 + c];
            const float top = a + (cc - a) * tx;
            const float bot = dd + (e - dd) * tx;
            o[std::size_t(x) * C + c] = top + (bot - top) * ty;
        }
    }
}

//! resample_row for a traversal that visits output rows in increasing order (a row block): each
//! source row is resampled horizontally once and kept while the next output rows still need it
//! (an upsampling by 2 reads every source row for up to four output rows), and the vertical step
//! runs over contiguous rows, so it vectorises. Values: exactly resample_row's (the same
//! horizontal lerps, then the same vertical one).
template <int C, int S = C>
class RowResampler {
public:
    RowResampler(const float* s, int sw, int w, const ResampleAxis& ax, const ResampleAxis& ay)
        : s_(s), sw_(sw), w_(w), ax_(ax), ay_(ay) {
        for (auto& b : buf_) b.resize(std::size_t(w) * C);
    }
    //! Writes output row y (w * C values) to o.
    void row(int y, float* o) {
        const float ty = ay_.t[std::size_t(y)];
        const int j0 = ay_.i0[std::size_t(y)], j1 = ay_.i1[std::size_t(y)];
        const float* __restrict top = horizontal(j0, -1);
        const float* __restrict bot = horizontal(j1, j0);
        const std::size_t n = std::size_t(w_) * C;
        for (std::size_t i = 0; i < n; ++i) o[i] = top[i] + (bot[i] - top[i]) * ty;
    }

private:
    //! The horizontal resampling of source row j, cached; never evicts the row `keep`.
    const float* horizontal(int j, int keep) {
        for (int k = 0; k < 2; ++k)
            if (key_[k] == j) return buf_[k].data();
        const int k = key_[0] == keep ? 1 : (key_[1] == keep ? 0 : next_);
        next_ = 1 - k;
        key_[k] = j;
        float* h = buf_[k].data();
        const float* r = s_ + std::size_t(j) * sw_ * S;
        for (int x = 0; x < w_; ++x) {
            const float tx = ax_.t[std::size_t(x)];
            const std::size_t a0 = std::size_t(ax_.i0[std::size_t(x)]) * S, a1 = std::size_t(ax_.i1[std::size_t(x)]) * S;
            for (int c = 0; c < C; ++c) {
                const float a = r[a0 + c], cc = r[a1 + c];
                h[std::size_t(x) * C + c] = a + (cc - a) * tx;
            }
        }
        return h;
    }
    const float* s_;
    int sw_, w_;
    const ResampleAxis& ax_;
    const ResampleAxis& ay_;
    std::vector<float> buf_[2];
    int key_[2] = {-1, -1};
    int next_ = 0;
};

template <int C>
void resample_rows(const float* s, int sw, float* d, int w, const ResampleAxis& ax, const ResampleAxis& ay, int y0,
                   int y1) {
    RowResampler<C> up(s, sw, w, ax, ay);
    for (int y = y0; y < y1; ++y) up.row(y, d + std::size_t(y) * w * C);
}

//! Bilinear resample of src (1..4 channels) to w x h with the convention above. Row blocks on the
//! traversal of ex; each value is the same expression as sample_resampled.
inline ImageF resample(const ImageF& src, int w, int h, const Exec& ex) {
    const int C = src.channels(), sw = src.width();
    const ResampleAxis ax(w, sw), ay(h, src.height());
    ImageF dst(w, h, C, kUninitialized);  // every value written below
    const float* s = src.data();
    float* d = dst.data();
    for_each_row_block(ex, h, [&](int y0, int y1) {
        switch (C) {
            case 1: resample_rows<1>(s, sw, d, w, ax, ay, y0, y1); break;
            case 2: resample_rows<2>(s, sw, d, w, ax, ay, y0, y1); break;
            case 3: resample_rows<3>(s, sw, d, w, ax, ay, y0, y1); break;
            default: resample_rows<4>(s, sw, d, w, ax, ay, y0, y1); break;
        }
    });
    return dst;
}

//! Channel c of a 4-channel src resampled to a w x h 1-channel image: the same values as
//! resample(extract_channel(src, c), w, h), without the full-size extracted copy.
inline ImageF resample_channel(const ImageF& src, int c, int w, int h, const Exec& ex) {
    const ResampleAxis ax(w, src.width()), ay(h, src.height());
    ImageF dst(w, h, 1, kUninitialized);  // every value written below
    const float* s = src.data() + c;
    float* d = dst.data();
    const int sw = src.width();
    for_each_row_block(ex, h, [&](int y0, int y1) {
        RowResampler<1, 4> up(s, sw, w, ax, ay);
        for (int y = y0; y < y1; ++y) up.row(y, d + std::size_t(y) * w);
    });
    return dst;
}

//! Channel c of src as a 1-channel image (row blocks on ex).
inline ImageF extract_channel(const ImageF& src, int c, const Exec& ex) {
    const int w = src.width(), C = src.channels();
    ImageF dst(w, src.height(), 1, kUninitialized);  // every value written below
    const float* s = src.data();
    float* d = dst.data();
    for_each_row_block(ex, src.height(), [&](int y0, int y1) {
        for (std::size_t i = std::size_t(y0) * w; i < std::size_t(y1) * w; ++i) d[i] = s[i * C + std::size_t(c)];
    });
    return dst;
}

}  // namespace aq::stylize::detail
