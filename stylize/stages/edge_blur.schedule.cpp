// stylize/stages/edge_blur.schedule.cpp — the fast schedule of edge_blur/wc18 (edge_blur.h
// edge_blur_wc18_fast): per row, runs of equal K as fixed-kernel loops with x innermost
// (accumulate_taps), eight pixels of mixed K at once where runs are short, and only the columns
// whose taps read a non-zero value. Per pixel the taps and their order are the reference loop's,
// so the bytes are the reference's (tests/stylize/edge_blur_test.cpp and the registry-wide
// traversal test compare them).
#include "stylize/stages/edge_blur.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "stylize/kernels.h"
#include "stylize/stages/blur.h"
#include "stylize/stages/toolkit.h"

namespace aq::stylize {

namespace {

//! The weights of eight pixels of mixed K (noisy control, where runs of equal K are too short for
//! accumulate_taps' eight-pixel steps): flat[K * kStride + |a|] = w_K[|a|]; for kmax <= 16 (W <= 4,
//! the published W = 3 included) the weights of one |a| for every K fit two registers, perm[2 |a|]
//! holding w_K[|a|] for K = 1..8 and perm[2 |a| + 1] for K = 9..16, so a lane's weight is a
//! two-register permutation by K - 1 instead of a gather.
struct MixedWeights {
    static constexpr int kStride = 4 * 16;
    std::vector<float> flat;
    std::vector<toolkit::v8f> perm;
    bool permuted = false;
    MixedWeights(const EdgeBlurWeights& tab, int kmax)
        : flat(std::size_t(kmax + 1) * kStride, 0.0f), perm(kmax <= 16 ? std::size_t(2 * kmax) : 0), permuted(kmax <= 16) {
        for (int k = 1; k <= kmax; ++k)
            for (int o = 0; o < k; ++o) flat[std::size_t(k) * kStride + std::size_t(o)] = tab[std::size_t(k)][std::size_t(o)];
        for (int aa = 0; permuted && aa < kmax; ++aa)
            for (int k = 1; k <= 16; ++k)
                perm[std::size_t(2 * aa + (k - 1) / 8)][(k - 1) % 8] = k <= kmax ? flat[std::size_t(k) * kStride + std::size_t(aa)] : 0.0f;
    }
};

//! Eight pixels x0..x0+7 of any K at once: the taps of the largest K in turn, each lane adding only
//! the taps |a| < its own K (a select, not a zero weight: the lane's sum is the reference's, bit for
//! bit). tap_row(a): tap a's values at the row's pixels; sr: the row's own values; kr: K per pixel.
template <class TapRow>
void mixed_kernel8(float* orow, const float* sr, const int* kr, int x0, const MixedWeights& mw, TapRow&& tap_row) {
    using toolkit::v8f;
    using toolkit::v8i;
    v8i kv;
    int kmx = 1;
    for (int i = 0; i < 8; ++i) kv[i] = kr[x0 + i], kmx = std::max(kmx, kr[x0 + i]);
    const v8i kbase = kv * MixedWeights::kStride;
    v8f wv[4 * 16];  // lane i: w_{K_i}[|a|] (0 where |a| >= K_i, not taken)
    if (mw.permuted) {
        const v8i sel = kv - 1;
        for (int aa = 0; aa < kmx; ++aa) wv[aa] = simd::permute16(mw.perm[std::size_t(2 * aa)], mw.perm[std::size_t(2 * aa + 1)], sel);
    } else {
        for (int aa = 0; aa < kmx; ++aa) wv[aa] = simd::gather8(mw.flat.data(), kbase + aa);
    }
    const v8f e0 = toolkit::load8(sr + x0);
    v8f acc = e0;
    for (int a = -(kmx - 1); a <= kmx - 1; ++a) {  // ascending, as the reference
        const int aa = std::abs(a);
        const v8i take = (v8i{} + aa) < kv;
        const v8f next = acc + wv[aa] * (toolkit::load8(tap_row(a) + x0) - e0);
        acc = take ? next : acc;
    }
    toolkit::store8(orow + x0, acc);
}

//! The end of the run of equal K starting at x0 within [x0, end): eight K compared at a time, then one.
inline int run_end(const int* kr, int x0, int end) {
    const int k = kr[x0];
    int x1 = x0 + 1;
    for (; x1 + 8 <= end; x1 += 8) {
        toolkit::v8i kn;
        std::memcpy(&kn, kr + x1, sizeof kn);
        const unsigned same = simd::bits8(kn == k);
        if (same != 0xFFu) return x1 + std::countr_one(same);
    }
    while (x1 < end && kr[x1] == k) ++x1;
    return x1;
}

//! Columns of a row (pass 0: its border-padded copy, pad[x .. x + 2R] the taps of pixel x) outside
//! which every tap reads +0: the first and last non-zero bit patterns, eight at a time from each
//! end. Empty (lo > hi) for a row of zeros.
struct Span {
    int lo, hi;
};
Span nonzero_span(const std::vector<float>& pad, int w, int R) {
    auto nonzero = [](float v) { return std::bit_cast<std::uint32_t>(v) != 0u; };
    const int np = w + 2 * R;
    const std::uint32_t* pu = reinterpret_cast<const std::uint32_t*>(pad.data());
    auto zero8 = [&](int i) {
        toolkit::v8i v;
        std::memcpy(&v, pu + i, sizeof v);
        return toolkit::all_zero(v);
    };
    int pa = 0, pb = np - 1;
    while (pa + 8 <= np && zero8(pa)) pa += 8;
    while (pa <= pb && !nonzero(pad[std::size_t(pa)])) ++pa;
    while (pb - 7 >= pa && zero8(pb - 7)) pb -= 8;
    while (pb >= pa && !nonzero(pad[std::size_t(pb)])) --pb;
    return pa <= pb ? Span{std::max(0, pa - 2 * R), std::min(w - 1, pb)} : Span{w, -1};
}

}  // namespace

void edge_blur_wc18_fast(ImageF& dst, ImageF& tmp, const ImageF& edges, const ImageF& ctrl, const EdgeBlurWeights& tab,
                         const EdgeBlurWc18Params& p, const Exec& ex) {
    const int w = edges.width(), h = edges.height();
    const int kmax = 4 * p.width;
    // Fast: each row is split into runs of equal K (painted control is smooth, so runs are long);
    // a run is a fixed-kernel 1-D convolution whose x loop vectorises. Per pixel the taps and
    // their order are those of the reference loop.
    const int R = kmax - 1;
    const std::vector<int> xt = toolkit::border_table(w, R, p.border);
    const std::vector<int> yt = toolkit::border_table(h, R, p.border);
    // K per pixel (<= 64) computed from ctrl.edge in pass 0 and kept as bytes (2 MB at 1080p) for
    // pass 1: the 4-channel control (32 MB at 1080p) is streamed once instead of twice.
    static_assert(4 * 16 <= 255);
    std::unique_ptr<std::uint8_t[]> ktab(new std::uint8_t[std::size_t(w) * std::size_t(h)]);
    // Zero spans (schedule only): where every value a pixel's taps read is +0 (bit pattern 0),
    // the delta form gives +0 exactly (0 + w * (0 - 0) for finite w), so only the columns
    // [lo, hi] of a row are computed and the rest is written +0. Pass 0 finds its span in the
    // border-resolved row (nonzero_span); pass 1's span of row y is the union of the pass-0 spans
    // of the rows its taps read (pass 0 wrote +0 outside them). Edges are zero wherever colour and
    // depth are flat: most of a frame's background.
    std::vector<Span> span0(static_cast<std::size_t>(h));
    const MixedWeights mixed(tab, kmax);
    constexpr int kMinRun = 16;  // runs of equal K at least this long go to accumulate_taps
    for (int pass = 0; pass < 2; ++pass) {
        const float* s = pass == 0 ? edges.data() : tmp.data();
        float* o = pass == 0 ? tmp.data() : dst.data();
        toolkit::for_each_row_block(ex, h, [&](int y0, int y1) {
            std::vector<float> pad(std::size_t(w + 2 * R));
            std::vector<int> krow(static_cast<std::size_t>(w));
            const float* dp[2 * 4 * 16];  // tap rows (pass 1) or shifted pad (pass 0), 2K - 1 <= 127
            float wt[2 * 4 * 16];
            for (int y = y0; y < y1; ++y) {
                const std::size_t row = std::size_t(y) * w;
                const float* __restrict sr = s + row;
                std::uint8_t* __restrict kb = ktab.get() + row;
                float* __restrict orow = o + row;
                Span sp{w, -1};
                if (pass == 0) {
                    toolkit::pad_row(pad.data(), sr, w, 1, xt, R);
                    sp = nonzero_span(pad, w, R);
                    span0[std::size_t(y)] = sp;
                    if (sp.lo <= sp.hi) {
                        edge_blur_kernel_sizes(ctrl, p.width, row + std::size_t(sp.lo), std::size_t(sp.hi - sp.lo + 1), krow.data() + sp.lo);
                        for (int x = sp.lo; x <= sp.hi; ++x) kb[x] = std::uint8_t(krow[std::size_t(x)]);
                    }
                } else {
                    for (int i = y; i <= y + 2 * R; ++i) {
                        const Span& t = span0[std::size_t(yt[std::size_t(i)])];
                        sp.lo = std::min(sp.lo, t.lo);
                        sp.hi = std::max(sp.hi, t.hi);
                    }
                    // K where pass 0 kept it (its span, inside this one: row y is one of the tap
                    // rows), computed from the control elsewhere.
                    const Span& own = span0[std::size_t(y)];
                    if (sp.lo <= sp.hi) {
                        const int a0 = own.lo <= own.hi ? own.lo : sp.hi + 1, a1 = own.lo <= own.hi ? own.hi : sp.hi;
                        if (a0 > sp.lo) edge_blur_kernel_sizes(ctrl, p.width, row + std::size_t(sp.lo), std::size_t(a0 - sp.lo), krow.data() + sp.lo);
                        for (int x = a0; x <= a1; ++x) krow[std::size_t(x)] = kb[x];
                        if (a1 < sp.hi) edge_blur_kernel_sizes(ctrl, p.width, row + std::size_t(a1 + 1), std::size_t(sp.hi - a1), krow.data() + a1 + 1);
                    }
                }
                if (sp.lo > sp.hi) {
                    std::fill_n(orow, w, 0.0f);
                    continue;
                }
                std::fill_n(orow, sp.lo, 0.0f);
                std::fill_n(orow + sp.hi + 1, w - 1 - sp.hi, 0.0f);
                const int* kr = krow.data();
                // Tap a's values at pixels x0..: the shifted padded row (pass 0) or row y + a (pass 1).
                auto tap_row = [&](int a) {
                    return pass == 0 ? pad.data() + (a + R) : s + std::size_t(yt[std::size_t(y + a + R)]) * w;
                };
                for (int x0 = sp.lo; x0 <= sp.hi;) {
                    const int k = kr[x0];
                    int x1 = run_end(kr, x0, sp.hi + 1);
                    if (x1 - x0 < kMinRun && x0 + 8 <= sp.hi + 1) {
                        mixed_kernel8(orow, sr, kr, x0, mixed, tap_row);
                        x0 += 8;
                        continue;
                    }
                    // A long run: its whole eight-pixel groups (the rest joins the next pixels).
                    if (x1 - x0 >= kMinRun && x1 <= sp.hi) x1 = x0 + (x1 - x0) / 8 * 8;
                    const float* wk = tab[std::size_t(k)].data();
                    const int taps = 2 * k - 1;
                    for (int ai = 0; ai < taps; ++ai) {  // tap a = ai - (k - 1), aligned with x0
                        const int a = ai - (k - 1);
                        dp[ai] = tap_row(a) + x0;
                        wt[ai] = wk[std::abs(a)];
                    }
                    // Per pixel the taps and their order are the reference loop's.
                    accumulate_taps(orow + x0, sr + x0, dp, wt, taps, std::size_t(x1 - x0));
                    x0 = x1;
                }
            }
        });
    }
}

}  // namespace aq::stylize
