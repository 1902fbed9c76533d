// stylize/stages/toolkit.h — the one set of helpers every stage implementation uses
// (docs/stylize.md "Writing a stage"): entry checks that name the stage and the port, output
// allocation, border index tables, the resampling convention between resolutions, single-channel
// read views, and the one row traversal (Reference: one plain loop; Fast: oneTBB blocks of rows).
// Scalar maths (sat, mix, smoothstep, luminance, bilinear taps) lives in stylize/kernels.h.
#pragma once

#include <algorithm>
#include <functional>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <immintrin.h>

#include "core/exec.h"
#include "core/image.h"
#include "core/simd.h"
#include "stylize/kernels.h"
#include "stylize/paper.h"
#include "stylize/declare.h"
#include "stylize/schedule/rows.h"
#include "stylize/stage.h"

namespace aq::stylize::toolkit {

// ---- entry checks: every error names the stage and the port ----------------------------------

//! The channel rule of an input check. Through the registry every port has an exact count
//! (check_io, stylize/stage.h); a typed stage function states which rule it accepts: Exactly where it
//! addresses pixels with the declared stride, AtLeast where it reads channels through a Plane
//! (any stride), so a 4-channel control target can feed a 1-channel port's function directly.
enum class Channels { Exactly, AtLeast };

//! Throws aq::Error unless img is present, non-empty and has `channels` channels under `rule`.
inline void check_input(const ImageF* img, int channels, Channels rule, const std::string& stage,
                        const std::string& port) {
    if (!img || img->empty()) throw Error(stage + ": input '" + port + "' is missing or empty");
    const bool ok = rule == Channels::Exactly ? img->channels() == channels : img->channels() >= channels;
    if (!ok)
        throw Error(stage + ": input '" + port + "' has " + std::to_string(img->channels()) + " channels, " +
                    (rule == Channels::Exactly ? "expected " : "needs at least ") + std::to_string(channels));
}

//! Throws aq::Error unless img has the size of `like`.
inline void check_same_size(const ImageF& img, const ImageF& like, const std::string& stage, const std::string& port,
                            const std::string& like_port) {
    if (!img.same_size(like))
        throw Error(stage + ": input '" + port + "' is " + std::to_string(img.width()) + "x" +
                    std::to_string(img.height()) + ", expected " + std::to_string(like.width()) + "x" +
                    std::to_string(like.height()) + " like '" + like_port + "'");
}

//! Accepts a lower-resolution intermediate of the same image: full size, or half size
//! (half_size(w) x half_size(h), the WC17 intermediates); anything else is an error naming the port.
inline void check_full_or_half(const ImageF& img, const ImageF& like, const std::string& stage, const std::string& port,
                               const std::string& like_port) {
    const int w = like.width(), h = like.height();
    const bool full = img.width() == w && img.height() == h;
    const bool half = img.width() == half_size(w) && img.height() == half_size(h);
    if (!full && !half)
        throw Error(stage + ": input '" + port + "' is " + std::to_string(img.width()) + "x" +
                    std::to_string(img.height()) + ", expected the size of '" + like_port + "' (" + std::to_string(w) +
                    "x" + std::to_string(h) + ") or half of it (" + std::to_string(half_size(w)) + "x" +
                    std::to_string(half_size(h)) + ")");
}

//! The optional bleed mask of the edge stages (edge_darken/rgbd, gaps_overlaps/wc18): one channel or
//! four (the mask in alpha, the bleed stage's RGBA output), full or half the size of `like`.
//! nullptr (no bleed step) passes.
inline void check_bleed_mask(const ImageF* bleed, const ImageF& like, const std::string& stage) {
    if (!bleed) return;
    check_input(bleed, 1, Channels::AtLeast, stage, "bleed");
    if (bleed->channels() != 1 && bleed->channels() != 4)
        throw Error(stage + ": input 'bleed' must have 1 channel or 4 (mask in alpha)");
    check_full_or_half(*bleed, like, stage, "bleed", "color");
}

//! The paper texture of Globals::paper, when bound: >= 3 channels (MNPR layout), the size of `like`.
//! nullptr (the flat paper) passes.
inline void check_paper(const ImageF* paper, const ImageF& like, const std::string& stage, const std::string& like_port) {
    if (!paper) return;
    check_input(paper, 3, Channels::AtLeast, stage, "paper");
    check_same_size(*paper, like, stage, "paper", like_port);
}

//! The output must not be one of the inputs (no stage writes its own input).
inline void check_not_alias(const ImageF& dst, const ImageF* in, const std::string& stage, const std::string& port) {
    if (in && &dst == in) throw Error(stage + ": output aliases input '" + port + "'");
}

//! The pipeline-wide values of a stage call (defaults when a caller passed none).
inline const Globals& globals_of(const StageIO& io) {
    static const Globals kDefault{};
    return io.globals ? *io.globals : kDefault;
}

//! The run's paper_height_spread (Globals::paper_spread, computed once per run), or a negative
//! value without a paper.
inline float paper_spread_of(const Globals& g, const Exec& ex) {
    if (!g.paper) return -1.0f;
    if (!(g.paper_spread >= 0.0f) && g.paper_spread == g.paper_spread) g.paper_spread = paper_height_spread(*g.paper, ex);
    return g.paper_spread;
}

// ---- outputs ---------------------------------------------------------------------------------

//! core/image.h: reuses an output's storage when it already has the shape (every stage writes
//! every value of its output).
using aq::ensure_output;

// ---- borders ---------------------------------------------------------------------------------

//! The source index of every padded position -pad..n-1+pad under border rule b.
inline std::vector<int> border_table(int n, int pad, Border b) {
    std::vector<int> t(std::size_t(n + 2 * pad));
    for (int i = -pad; i < n + pad; ++i) t[std::size_t(i + pad)] = resolve_border(i, n, b);
    return t;
}

//! A padded row copy: dst[(i + pad) C + c] = src[table[i + pad] C + c] for i in -pad..n-1+pad, with
//! table = border_table(n, pad, b): the row itself copied in one block (the table is the identity
//! there), only the 2 pad border texels looked up. C channels interleaved.
inline void pad_row(float* dst, const float* src, int n, int C, const std::vector<int>& table, int pad) {
    std::copy_n(src, std::size_t(n) * std::size_t(C), dst + std::size_t(pad) * std::size_t(C));
    auto border = [&](int i) {
        for (int c = 0; c < C; ++c) dst[std::size_t(i) * C + c] = src[std::size_t(table[std::size_t(i)]) * C + c];
    };
    for (int i = 0; i < pad; ++i) border(i);
    for (int i = pad + n; i < n + 2 * pad; ++i) border(i);
}

// ---- the traversal (stylize/schedule/rows.h) ---------------------------------------------------

using schedule::any_index;
using schedule::for_each_row;
using schedule::for_each_row_block;
using schedule::plain_loop;
using schedule::row_grain;

// ---- registers -------------------------------------------------------------------------------

// Eight-lane registers: core/simd.h.
using simd::v8f;
using simd::v8i;
using simd::v4f;
using simd::load8;
using simd::store8;
using simd::all_zero;
//! kernels.h sat lane by lane (x < 0 ? 0 : x > 1 ? 1 : x; NaN and -0 kept), as kernels.h sat8.
inline v8f sat(v8f x) {
    const v8f zero{}, one = v8f{} + 1.0f;
    return x < zero ? zero : (x > one ? one : x);
}
//! Eight RGBA pixels from planes: o[4i .. 4i+3] = (r[i], g[i], b[i], a[i]), i < 8 (unpacks and
//! 128-bit permutes: values moved, never computed). For row kernels that compute channels as
//! separate vectorised planes and store interleaved pixels.
inline void store_rgba8(float* o, const float* r, const float* g, const float* b, const float* a) {
#ifndef __AVX__
    for (int i = 0; i < 8; ++i) std::memcpy(o + 4 * i, r + i, 4), std::memcpy(o + 4 * i + 1, g + i, 4),
                                std::memcpy(o + 4 * i + 2, b + i, 4), std::memcpy(o + 4 * i + 3, a + i, 4);
#else
    const __m256 vr = _mm256_loadu_ps(r), vg = _mm256_loadu_ps(g), vb = _mm256_loadu_ps(b), va = _mm256_loadu_ps(a);
    const __m256 rg_lo = _mm256_unpacklo_ps(vr, vg), rg_hi = _mm256_unpackhi_ps(vr, vg);  // r0 g0 r1 g1 | r4 g4 r5 g5
    const __m256 ba_lo = _mm256_unpacklo_ps(vb, va), ba_hi = _mm256_unpackhi_ps(vb, va);
    const __m256 p0 = _mm256_shuffle_ps(rg_lo, ba_lo, 0x44), p1 = _mm256_shuffle_ps(rg_lo, ba_lo, 0xee);  // px 0|4, 1|5
    const __m256 p2 = _mm256_shuffle_ps(rg_hi, ba_hi, 0x44), p3 = _mm256_shuffle_ps(rg_hi, ba_hi, 0xee);  // px 2|6, 3|7
    _mm256_storeu_ps(o, _mm256_permute2f128_ps(p0, p1, 0x20));
    _mm256_storeu_ps(o + 8, _mm256_permute2f128_ps(p2, p3, 0x20));
    _mm256_storeu_ps(o + 16, _mm256_permute2f128_ps(p0, p1, 0x31));
    _mm256_storeu_ps(o + 24, _mm256_permute2f128_ps(p2, p3, 0x31));
#endif
}

//! Bit k set when channel k (C <= 8) of the n values at d (C channels interleaved, d at a channel-0
//! value) holds a value other than 0 (NaN counts; -0 is 0), on the calling thread: 8 values per
//! compare where C divides 8 (lane l is channel l % C).
inline std::uint32_t nonzero_channels_of(const float* d, std::size_t n, int C) {
    std::uint32_t m = 0;
    std::size_t j = 0;
    if (8 % C == 0) {
        v8i acc{};
        for (; j + 8 <= n; j += 8) acc |= load8(d + j) != v8f{};
        for (int l = 0; l < 8; ++l) m |= std::uint32_t(acc[l] != 0) << (l % C);
    }
    for (; j < n; ++j) m |= std::uint32_t(d[j] != 0.0f) << (j % std::size_t(C));
    return m;
}

//! Bit k set when channel k (C <= 8) of img holds a value other than 0 (NaN counts), on the
//! traversal of ex (the answer does not depend on it): one pass over the image for all channels,
//! 8 values per compare where C divides 8 (lane l is channel l % C), stopping once every channel
//! has been seen.
inline std::uint32_t nonzero_channels(const Exec& ex, const ImageF& img) {
    const int C = img.channels();
    const float* d = img.data();
    const std::size_t nv = img.num_values();
    const std::uint32_t all = (1u << C) - 1u;
    std::atomic<std::uint32_t> mask{0};
    auto scan = [&](std::size_t v0, std::size_t v1) {      // v0: a multiple of C
        const std::size_t chunk = 256 * std::size_t(C);  // values between checks of the shared mask
        for (std::size_t i = v0; i < v1; i += chunk) {
            if (mask.load(std::memory_order_relaxed) == all) return;
            const std::uint32_t m = nonzero_channels_of(d + i, std::min(i + chunk, v1) - i, C);
            if (m) mask.fetch_or(m, std::memory_order_relaxed);
        }
    };
    const std::size_t block = std::size_t(1) << 15;  // times C: a multiple of C
    if (ex.traversal == Traversal::Reference || nv <= block) scan(0, nv);
    else
        with_arena(ex, [&] {
            const std::size_t step = block * std::size_t(C), nb = (nv + step - 1) / step;
            tbb::parallel_for(std::size_t(0), nb, [&](std::size_t k) { scan(k * step, std::min(nv, (k + 1) * step)); });
        });
    return mask.load();
}

//! Whether any of the n values at d is > bound (NaN is not), 8 values per compare, on the calling
//! thread: the skip tests of row kernels (a chunk with no positive control, no edge above a threshold).
inline bool any_above(const float* d, std::size_t n, float bound) {
    const v8f b = v8f{} + bound;
    v8i above{};
    std::size_t j = 0;
    for (; j + 8 <= n; j += 8) above |= load8(d + j) > b;
    bool any = !all_zero(above);
    for (; j < n; ++j) any |= d[j] > bound;
    return any;
}

//! Whether every one of the n values at d equals v (== : false for NaN, -0 equals +0), 8 values
//! per compare, on the calling thread; returns at the first block of 64 values with one that
//! differs: the flat-region tests of neighbourhood kernels (edge_detect).
inline bool all_equal(const float* d, std::size_t n, float v) {
    const v8f b = v8f{} + v;
    std::size_t j = 0;
    for (; j + 64 <= n; j += 64) {
        v8i ne{};
        for (std::size_t k = j; k < j + 64; k += 8) ne |= load8(d + k) != b;
        if (!all_zero(ne)) return false;
    }
    bool ok = true;
    for (; j < n; ++j) ok &= d[j] == v;
    return ok;
}

//! Whether channel k of the n pixels at d (4 channels interleaved) is 0 in every pixel (-0 is 0,
//! NaN is not), on the calling thread; returns at the first block of 16 pixels with one that is
//! not (nonzero_channels_of scans everything: it answers for every channel).
inline bool channel_all_zero4(const float* d, std::size_t n, int k) {
    v8i lane{};
    for (int l = 0; l < 8; ++l) lane[l] = l % 4 == k ? -1 : 0;
    std::size_t j = 0;
    const std::size_t nv = 4 * n;
    for (; j + 64 <= nv; j += 64) {
        v8i hit{};
        for (std::size_t q = j; q < j + 64; q += 8) hit |= (load8(d + q) != v8f{}) & lane;
        if (!all_zero(hit)) return false;
    }
    bool zero = true;
    for (; j < nv; ++j)
        if (j % 4 == std::size_t(k)) zero &= d[j] == 0.0f;
    return zero;
}

//! Whether any of the n values at d is -0 (the bit pattern 0x80000000), 8 values per compare, on
//! the calling thread: tests of exact shortcuts where +0 + c == c holds for every c but -0.
inline bool any_negative_zero(const float* d, std::size_t n) {
    const v8i m = v8i{} + std::int32_t(0x80000000u);
    v8i hit{};
    std::size_t j = 0;
    for (; j + 8 <= n; j += 8) {
        v8i bits;
        std::memcpy(&bits, d + j, sizeof bits);
        hit |= bits == m;
    }
    bool any = !all_zero(hit);
    for (; j < n; ++j) any |= std::bit_cast<std::uint32_t>(d[j]) == 0x80000000u;
    return any;
}

//! Whether every one of the n values at d lies in [-bound, bound] (false for NaN), 8 values per
//! compare, on the calling thread; returns at the first block of 64 values with one outside.
inline bool all_within(const float* d, std::size_t n, float bound) {
    const v8f hi = v8f{} + bound, lo = v8f{} - bound;
    std::size_t j = 0;
    for (; j + 64 <= n; j += 64) {
        v8i out{};
        for (std::size_t k = j; k < j + 64; k += 8) {
            const v8f x = load8(d + k);
            out |= ~((x <= hi) & (x >= lo));
        }
        bool any = false;
        for (int l = 0; l < 8; ++l) any |= out[l] != 0;
        if (any) return false;
    }
    bool ok = true;
    for (; j < n; ++j) ok &= d[j] <= bound && d[j] >= -bound;
    return ok;
}

//! Whether some of the n values at d is NaN or beyond [-bound, bound] (bound = FLT_MAX: not finite),
//! on the traversal of ex; the answer does not depend on it.
inline bool any_beyond(const Exec& ex, const float* d, std::size_t n, float bound) {
    constexpr std::size_t kChunk = 1024;
    return any_index(ex, (n + kChunk - 1) / kChunk, [&](std::size_t c) {
        const std::size_t i0 = c * kChunk;
        return !all_within(d + i0, std::min(n, i0 + kChunk) - i0, bound);
    });
}

// ---- single-channel views ----------------------------------------------------------------------

//! Read-only view of one channel of an image with any channel count; px/row are element strides.
//! A constant plane (px = row = 0) stands in for an absent texture (e.g. the flat paper).
struct Plane {
    const float* p = nullptr;
    std::ptrdiff_t px = 0, row = 0;
    int width = 0, height = 0;

    float operator()(int x, int y) const { return p[y * row + x * px]; }
    float at(int x, int y, Border b) const { return (*this)(resolve_border(x, width, b), resolve_border(y, height, b)); }
};

inline Plane plane(const ImageF& img, int channel) {
    return {img.data() + channel, img.channels(), std::ptrdiff_t(img.channels()) * img.width(), img.width(),
            img.height()};
}

inline Plane constant_plane(const float* value, int w, int h) { return {value, 0, 0, w, h}; }

//! p(x, y) .. p(x + 7, y) (x + 8 <= p.width): one load for a contiguous plane, shuffles for 3 or 4
//! interleaved channels, a broadcast for a constant plane, else value by value. Values are moved,
//! never computed.
inline v8f plane8(const Plane& p, int x, int y) {
    const float* q = p.p + y * p.row + x * p.px;
    switch (p.px) {
    case 0: return v8f{} + *q;
    case 1: return simd::strided8<1>(q);
    case 3: return simd::strided8<3>(q);
    case 4: return simd::strided8<4>(q);
    default: {
        v8f v;
        for (int i = 0; i < 8; ++i) v[i] = q[i * p.px];
        return v;
    }
    }
}

//! Value at output pixel (x, y) of a w x h image of plane p resampled by the convention of
//! kernels.h sample_resampled (texel_coord + sample_bilinear, clamp to edge; exactly the identity at
//! equal sizes), computed directly: the plain counterpart of Resampler::sample.
inline float sample_resampled_plane(const Plane& p, int x, int y, int w, int h) {
    if (p.width == w && p.height == h) return p(x, y);
    return sample_bilinear(p, texel_coord(x, w, p.width), texel_coord(y, h, p.height), Border::Clamp);
}

// ---- resampling between resolutions (docs/stylize.md "Resolution conventions") --------------

//! Per-axis taps of the resampling convention (kernels.h texel_coord + sample_bilinear, clamp to
//! edge): for output index x, source taps i0[x], i1[x] (already clamped) and weight t[x], computed
//! with exactly sample_bilinear's float operations, so resampled values equal sample_resampled's
//! bit for bit.
//! `same` (n_out == n_src) marks the identity: users of two axes read the texel itself when both
//! are the same (sample_resampled's rule at equal sizes).
//! `pairs` (schedule only) marks a halving whose taps are exactly i0[x] = 2x, i1[x] = 2x + 1 for
//! every x (even n_src = 2 n_out; t[x] is still per x: in float it is not always 0.5), so a row
//! loop can address the taps without the tables.
struct ResampleAxis {
    std::vector<int> i0, i1;
    std::vector<float> t;
    bool same = true;
    bool pairs = false;
    ResampleAxis() = default;
    ResampleAxis(int n_out, int n_src)
        : i0(std::size_t(n_out)), i1(std::size_t(n_out)), t(std::size_t(n_out)), same(n_out == n_src) {
        pairs = n_out > 0;
        for (int x = 0; x < n_out; ++x) {
            const float f = texel_coord(x, n_out, n_src) - 0.5f;
            const float f0 = std::floor(f);
            t[std::size_t(x)] = f - f0;
            const int i = int(f0);
            i0[std::size_t(x)] = resolve_border(i, n_src, Border::Clamp);
            i1[std::size_t(x)] = resolve_border(i + 1, n_src, Border::Clamp);
            pairs = pairs && i0[std::size_t(x)] == 2 * x && i1[std::size_t(x)] == 2 * x + 1;
        }
    }
};

//! Both axes of a resampling from src_w x src_h to out_w x out_h, for stages that sample a
//! lower-resolution plane pixel by pixel.
struct Resampler {
    ResampleAxis x, y;
    Resampler() = default;
    Resampler(int out_w, int out_h, int src_w, int src_h) : x(out_w, src_w), y(out_h, src_h) {}
    //! True when both sizes are equal: every sample is the texel itself.
    bool identity() const { return x.same && y.same; }
    //! The value at output pixel (ox, oy): sample_resampled's, bit for bit.
    float sample(const Plane& p, int ox, int oy) const {
        if (identity()) return p(ox, oy);
        const std::size_t i = std::size_t(ox), j = std::size_t(oy);
        const float a = p(x.i0[i], y.i0[j]), c = p(x.i1[i], y.i0[j]), d = p(x.i0[i], y.i1[j]), e = p(x.i1[i], y.i1[j]);
        return maths::bilerp(a, c, d, e, x.t[i], y.t[j]);
    }
    //! sample(p, ox + i, oy) for i < 8 (ox + 8 <= the output width): the same operations lane by
    //! lane, the taps gathered.
    v8f sample8(const Plane& p, int ox, int oy) const {
        if (identity()) return plane8(p, ox, oy);
        const std::size_t i = std::size_t(ox), j = std::size_t(oy);
        v8i i0, i1;
        std::memcpy(&i0, x.i0.data() + i, sizeof i0);
        std::memcpy(&i1, x.i1.data() + i, sizeof i1);
        i0 *= int(p.px), i1 *= int(p.px);
        const float* r0 = p.p + std::ptrdiff_t(y.i0[j]) * p.row;
        const float* r1 = p.p + std::ptrdiff_t(y.i1[j]) * p.row;
        const v8f a = simd::gather8(r0, i0), c = simd::gather8(r0, i1), d = simd::gather8(r1, i0), e = simd::gather8(r1, i1);
        return maths::bilerp(a, c, d, e, load8(x.t.data() + i), y.t[j]);
    }
};

//! The lerp a + (b - a) * t of one pixel of C channels (C <= 4) at p0 and p1, written to o: for
//! C = 4 the channels side by side in one 4-lane register (the same IEEE operations per lane as
//! the scalar form: bit for bit equal, and no FMA under the project's flags), else scalar (2 or 3
//! channels packed into a register measured slower than the scalar form: the partial loads cost
//! shuffles).
template <int C>
inline void lerp_pixel(const float* p0, const float* p1, float t, float* o) {
    static_assert(C >= 1 && C <= 4);
    if constexpr (C == 4) {
        v4f a, b;
        std::memcpy(&a, p0, sizeof a);
        std::memcpy(&b, p1, sizeof b);
        const v4f r = a + (b - a) * t;
        std::memcpy(o, &r, sizeof r);
    } else {
        for (int c = 0; c < C; ++c) o[c] = p0[c] + (p1[c] - p0[c]) * t;
    }
}

//! The horizontal lerps of a halving axis (ResampleAxis::pairs): output pixel x of C channels is
//! lerp_pixel(source pixel 2x, source pixel 2x + 1, t[x]) — the same operations as the tabled
//! loop, with the taps addressed directly (no index loads); four channels two output pixels per
//! register, one channel (S = 1) eight outputs per register from two loads.
template <int C, int S = C>
inline void halve_row(const float* __restrict r, const float* __restrict t, float* __restrict h, int w) {
    int x = 0;
    if constexpr (C == 4 && S == 4) {
        for (; x + 2 <= w; x += 2) {
            v8f p, q;  // source pixels 2x, 2x + 1 and 2x + 2, 2x + 3
            std::memcpy(&p, r + 8 * std::size_t(x), sizeof p);
            std::memcpy(&q, r + 8 * std::size_t(x) + 8, sizeof q);
            const v8f a = __builtin_shufflevector(p, q, 0, 1, 2, 3, 8, 9, 10, 11);
            const v8f b = __builtin_shufflevector(p, q, 4, 5, 6, 7, 12, 13, 14, 15);
            const v8f tv = {t[x], t[x], t[x], t[x], t[x + 1], t[x + 1], t[x + 1], t[x + 1]};
            const v8f o = a + (b - a) * tv;
            std::memcpy(h + 4 * std::size_t(x), &o, sizeof o);
        }
    } else if constexpr (C == 1 && S == 1) {
        for (; x + 8 <= w; x += 8) {
            v8f p, q, tv;  // source values 2x .. 2x + 15
            std::memcpy(&p, r + 2 * std::size_t(x), sizeof p);
            std::memcpy(&q, r + 2 * std::size_t(x) + 8, sizeof q);
            std::memcpy(&tv, t + x, sizeof tv);
            const v8f a = __builtin_shufflevector(p, q, 0, 2, 4, 6, 8, 10, 12, 14);
            const v8f b = __builtin_shufflevector(p, q, 1, 3, 5, 7, 9, 11, 13, 15);
            const v8f o = a + (b - a) * tv;
            std::memcpy(h + x, &o, sizeof o);
        }
    }
    for (; x < w; ++x) lerp_pixel<C>(r + std::size_t(2 * x) * S, r + std::size_t(2 * x + 1) * S, t[x], h + std::size_t(x) * C);
}

//! Output row y (w pixels of C channels, written to o) of the resampling of s (sw texels wide).
//! S: the source's channel count when it differs from C (then s points at the first channel
//! wanted, e.g. data() + 2 resamples channel 2 of an S-channel image without extracting it).
template <int C, int S = C>
void resample_row(const float* s, int sw, float* o, int w, const ResampleAxis& ax, const ResampleAxis& ay, int y) {
    if (ax.same && ay.same) {  // the identity: the source row itself
        const float* r = s + std::size_t(y) * sw * S;
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < C; ++c) o[std::size_t(x) * C + c] = r[std::size_t(x) * S + c];
        return;
    }
    const float ty = ay.t[std::size_t(y)];
    const float* r0 = s + std::size_t(ay.i0[std::size_t(y)]) * sw * S;
    const float* r1 = s + std::size_t(ay.i1[std::size_t(y)]) * sw * S;
    for (int x = 0; x < w; ++x) {
        const float tx = ax.t[std::size_t(x)];
        const std::size_t a0 = std::size_t(ax.i0[std::size_t(x)]) * S, a1 = std::size_t(ax.i1[std::size_t(x)]) * S;
        float top[C], bot[C];  // C is a constant: channels side by side
        lerp_pixel<C>(r0 + a0, r0 + a1, tx, top);
        lerp_pixel<C>(r1 + a0, r1 + a1, tx, bot);
        lerp_pixel<C>(top, bot, ty, o + std::size_t(x) * C);
    }
}

//! resample_row for a traversal that visits output rows in increasing order (a row block): each
//! source row is resampled horizontally once and kept while the next output rows still need it
//! (an upsampling by 2 reads every source row for up to four output rows), and the vertical step
//! runs over contiguous rows, so it vectorises. Values: exactly resample_row's (the same
//! horizontal lerps, then the same vertical one).
//! The source may also be computed row by row (a fused schedule: `generate(j)` returns source row j
//! — sw pixels of S channels — valid until its next call; each row is asked for once per cache
//! miss), so a producer's image need not exist.
template <int C, int S = C>
class RowResampler {
public:
    using Generator = std::function<const float*(int j)>;
    RowResampler(const float* s, int sw, int w, const ResampleAxis& ax, const ResampleAxis& ay)
        : s_(s), sw_(sw), w_(w), ax_(ax), ay_(ay) {
        if (!identity())  // every value of a row buffer is written before it is read: not zero-filled
            for (auto& b : buf_) b = std::make_unique_for_overwrite<float[]>(std::size_t(w) * C);
    }
    RowResampler(Generator generate, int sw, int w, const ResampleAxis& ax, const ResampleAxis& ay)
        : RowResampler(nullptr, sw, w, ax, ay) {
        gen_ = std::move(generate);
    }
    //! Writes output row y (w * C values) to o.
    void row(int y, float* o) {
        if (identity()) {
            if (gen_) resample_row<C, S>(gen_(y), sw_, o, w_, ax_, ay_, 0);  // row 0 of the generated row
            else resample_row<C, S>(s_, sw_, o, w_, ax_, ay_, y);
            return;
        }
        row_span(y, o, 0, w_);
    }

    //! Output pixels [x0, x1) of row y (C values each) written to o[0 .. (x1 - x0) C): row(y)'s
    //! values there (the same horizontal rows, the same vertical lerp per value), for a traversal
    //! that needs parts of a row. Not for the identity (use row_or_source and offset the pointer).
    void row_span(int y, float* o, int x0, int x1) {
        const float ty = ay_.t[std::size_t(y)];
        const int j0 = ay_.i0[std::size_t(y)], j1 = ay_.i1[std::size_t(y)];
        const float* __restrict top = horizontal(j0, -1) + std::size_t(x0) * C;
        const float* __restrict bot = horizontal(j1, j0) + std::size_t(x0) * C;
        const std::size_t n = std::size_t(x1 - x0) * C;
        for (std::size_t i = 0; i < n; ++i) o[i] = top[i] + (bot[i] - top[i]) * ty;
    }

    //! Output row y without a copy where it exists as is (the identity of a C-channel source): a
    //! pointer into the source; otherwise row(y, buf) and buf. buf holds w * C values.
    const float* row_or_source(int y, float* buf) {
        if (identity() && C == S) return gen_ ? gen_(y) : s_ + std::size_t(y) * sw_ * S;
        row(y, buf);
        return buf;
    }
    bool identity() const { return ax_.same && ay_.same; }

private:
    //! The horizontal resampling of source row j, cached; never evicts the row `keep`.
    const float* horizontal(int j, int keep) {
        for (int k = 0; k < 2; ++k)
            if (key_[k] == j) return buf_[k].get();
        const int k = key_[0] == keep ? 1 : (key_[1] == keep ? 0 : next_);
        next_ = 1 - k;
        key_[k] = j;
        float* h = buf_[k].get();
        const float* r = gen_ ? gen_(j) : s_ + std::size_t(j) * sw_ * S;
        if (ax_.pairs) {
            halve_row<C, S>(r, ax_.t.data(), h, w_);
            return h;
        }
        for (int x = 0; x < w_; ++x) {
            const std::size_t a0 = std::size_t(ax_.i0[std::size_t(x)]) * S, a1 = std::size_t(ax_.i1[std::size_t(x)]) * S;
            lerp_pixel<C>(r + a0, r + a1, ax_.t[std::size_t(x)], h + std::size_t(x) * C);
        }
        return h;
    }
    const float* s_;
    Generator gen_;
    int sw_, w_;
    const ResampleAxis& ax_;
    const ResampleAxis& ay_;
    std::unique_ptr<float[]> buf_[2];
    int key_[2] = {-1, -1};
    int next_ = 0;
};

//! Bilinear resample of src (1..4 channels) to w x h with the convention above, on the traversal
//! of ex; each value is the same expression as sample_resampled.
inline ImageF resample(const ImageF& src, int w, int h, const Exec& ex) {
    const int C = src.channels(), sw = src.width();
    const ResampleAxis ax(w, sw), ay(h, src.height());
    ImageF dst(w, h, C, kUninitialized);  // every value written below
    const float* s = src.data();
    float* d = dst.data();
    auto rows = [&]<int N>(int y0, int y1) {
        RowResampler<N> up(s, sw, w, ax, ay);
        for (int y = y0; y < y1; ++y) up.row(y, d + std::size_t(y) * w * N);
    };
    for_each_row_block(ex, h, [&](int y0, int y1) {
        switch (C) {
            case 1: rows.template operator()<1>(y0, y1); break;
            case 2: rows.template operator()<2>(y0, y1); break;
            case 3: rows.template operator()<3>(y0, y1); break;
            default: rows.template operator()<4>(y0, y1); break;
        }
    });
    return dst;
}

//! Channel c of a 4-channel src resampled to a w x h 1-channel image: the values of resampling
//! that channel alone, without a full-size extracted copy.
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

}  // namespace aq::stylize::toolkit

namespace aq::stylize {
// What the registration functions of stage files (stylize/stages/*.cpp register_*) read.
using toolkit::globals_of;
using toolkit::paper_spread_of;
}  // namespace aq::stylize
