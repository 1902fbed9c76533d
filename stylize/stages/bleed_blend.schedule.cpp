// stylize/stages/bleed_blend.schedule.cpp — the fast schedule of bleed_blend/eq7 (bleed_blend.h
// bleed_blend_fast): the bleed upsampled row by row, quiet column chunks kept as they are, the
// blend two pixels per register with bleed_blend_px's operations lane by lane (the reference's
// bytes: tests/stylize/bleed_test.cpp and the registry-wide traversal test compare them).
#include "stylize/stages/bleed_blend.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "stylize/kernels.h"
#include "stylize/stages/toolkit.h"

namespace aq::stylize {

namespace {
//! |value| bound of the quiet-row test: differences of bounded values stay finite.
constexpr float kQuietBound = 1e37f;
//! Column chunk of the quiet test in place, output pixels (a 1080p row: 15 chunks).
constexpr int kChunk = 128;
}  // namespace

void bleed_blend_fast(ImageF& dst, const ImageF& color, const ImageF& bleed, float gain, const Exec& ex) {
    const int w = color.width(), h = color.height();
    const float* I = color.data();
    float* o = dst.data();
    // Eq. 7 for the n pixels starting at pixel index i0, with their bleed values in B[0 .. 4n):
    // two pixels per register (lane-wise, the scalar expressions' operations: k = sat(gain * B.a)
    // of each pixel broadcast over its four lanes, alpha lanes from I), then one pixel at a time.
    auto blend = [&](const float* B, std::size_t i0, std::size_t n) {
        const float* Ii = I + 4 * i0;
        float* oi = o + 4 * i0;
        using toolkit::v8f;
        using toolkit::v8i;
        const v8i alpha = {0, 0, 0, -1, 0, 0, 0, -1};
        const v8f vgain = v8f{} + gain;
        std::size_t i = 0;
        for (; i + 2 <= n; i += 2) {
            const v8f b = toolkit::load8(B + 4 * i), c = toolkit::load8(Ii + 4 * i);
            const v8f s = toolkit::sat(vgain * b);
            const v8f k = __builtin_shufflevector(s, s, 3, 3, 3, 3, 7, 7, 7, 7);
            const v8f r = k * (b - c) + c;
            toolkit::store8(oi + 4 * i, alpha ? c : r);
        }
        for (; i < n; ++i) {
            const float k = sat(gain * B[4 * i + 3]);
            oi[4 * i + 0] = k * (B[4 * i + 0] - Ii[4 * i + 0]) + Ii[4 * i + 0];
            oi[4 * i + 1] = k * (B[4 * i + 1] - Ii[4 * i + 1]) + Ii[4 * i + 1];
            oi[4 * i + 2] = k * (B[4 * i + 2] - Ii[4 * i + 2]) + Ii[4 * i + 2];
            oi[4 * i + 3] = Ii[4 * i + 3];
        }
    };
    // The bleed (full or half size) is upsampled row by row into a buffer (toolkit::RowResampler:
    // the sample_resampled convention, value for value, each source row resampled horizontally once
    // per row block; a full-size bleed is read in place) and blended at once: no full-size
    // temporary (33 MB at 1080p, written and read back every frame).
    const toolkit::ResampleAxis ax(w, bleed.width()), ay(h, bleed.height());
    // Column chunks of rows where nothing bleeds keep the colour, exactly, without the upsampling
    // and the blend: in place nothing is written (schedule only; most of a frame's background, and
    // the parts of a bleeding row away from the bleeding: in a Suzanne frame a quarter of the
    // chunks lie within reach of bleeding control). Output pixels [x0, x1) of chunk k read the
    // bleed's columns [s_lo[k], s_hi[k]] only (the upsampling's taps) of the row's two source rows.
    // Where those are quiet — mask (alpha) +-0, values bounded — the bilinear upsampling has a mask
    // of +-0 and a bounded colour b, so k = sat(gain x +-0) = +-0 (gain finite, >= 0), k (b - c) is
    // +-0 for a bounded c, and +-0 + c == c unless c is -0.
    const int bw = bleed.width();
    const bool gain_ok = std::isfinite(gain) && gain >= 0.0f;
    // Out of place a kept chunk is still copied, after two test passes over its colour: cheaper than
    // the blend only in place, so out of place the unit is the row (stage/bleed_blend/eq7, an
    // edge-dense frame: 5.4 ms with 128-pixel chunks against 4.4 by rows).
    const int cw = o == I ? kChunk : w;
    const int nck = (w + cw - 1) / cw;
    std::vector<int> s_lo(std::size_t(nck), bw), s_hi(std::size_t(nck), 0);
    for (int x = 0; x < w; ++x) {
        const std::size_t k = std::size_t(x / cw);
        s_lo[k] = std::min(s_lo[k], ax.i0[std::size_t(x)]);
        s_hi[k] = std::max(s_hi[k], ax.i1[std::size_t(x)]);
    }
    auto quiet_source = [&](int j, int k) {
        const float* r = bleed.data() + (std::size_t(j) * std::size_t(bw) + std::size_t(s_lo[std::size_t(k)])) * 4;
        const std::size_t n = std::size_t(s_hi[std::size_t(k)] - s_lo[std::size_t(k)] + 1);
        return toolkit::channel_all_zero4(r, n, 3) && toolkit::all_within(r, n * 4, kQuietBound);
    };
    toolkit::for_each_row_block(ex, h, [&](int y0, int y1) {
        const auto span = std::make_unique_for_overwrite<float[]>(std::size_t(cw) * 4);
        toolkit::RowResampler<4> up(bleed.data(), bleed.width(), w, ax, ay);
        // The quiet test of the block's source rows (increasing with y), each row and chunk once.
        const int j_lo = ay.i0[std::size_t(y0)], j_hi = ay.i1[std::size_t(y1 - 1)];
        std::vector<std::uint8_t> quiet(gain_ok ? std::size_t(j_hi - j_lo + 1) * std::size_t(nck) : 0);
        for (int j = j_lo; gain_ok && j <= j_hi; ++j)
            for (int k = 0; k < nck; ++k) quiet[std::size_t(j - j_lo) * std::size_t(nck) + std::size_t(k)] = quiet_source(j, k);
        for (int y = y0; y < y1; ++y) {
            const std::size_t q0 = std::size_t(ay.i0[std::size_t(y)] - j_lo) * std::size_t(nck);
            const std::size_t q1 = std::size_t(ay.i1[std::size_t(y)] - j_lo) * std::size_t(nck);
            for (int k = 0; k < nck; ++k) {
                const int x0 = k * cw, x1 = std::min(w, x0 + cw);
                const std::size_t i0 = std::size_t(y) * w + std::size_t(x0), n = std::size_t(x1 - x0);
                const float* c = I + 4 * i0;
                if (gain_ok && quiet[q0 + std::size_t(k)] && quiet[q1 + std::size_t(k)] &&
                    toolkit::all_within(c, 4 * n, kQuietBound) && !toolkit::any_negative_zero(c, 4 * n)) {
                    if (o != I) std::memcpy(o + 4 * i0, c, 4 * n * sizeof(float));
                    continue;
                }
                if (up.identity()) {
                    blend(bleed.data() + 4 * i0, i0, n);
                } else {
                    up.row_span(y, span.get(), x0, x1);
                    blend(span.get(), i0, n);
                }
            }
        }
    });
}

}  // namespace aq::stylize
