// stylize/stages/edge_blur.cpp — WC17 half-resolution 5x5 Gaussian and WC18 variable-width edge blur.
// The WC18 blur uses the delta form of blur.h with a per-pixel normalised table:
//   acc = e0;  for a = -(K-1)..(K-1) ascending: acc = acc + w_K[|a|] * (E(x + a) - e0)
// Reference: per pixel through the border rule. Fast: K computed per row (the same K for a pixel
// in both passes), each row split into runs of equal K, each run a fixed-kernel loop with x innermost —
// the same taps in the same order per pixel, so bit-identical.
#include "stylize/stages/edge_blur.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <cstdint>
#include <memory>
#include <vector>

#include "stylize/kernels.h"
#include "stylize/stages/blur.h"
#include "stylize/stages/toolkit.h"

namespace aq::stylize {

int edge_blur_kernel_size(int width, float ctrl) {
    const float wf = float(width);
    const float v = wf + lerp(0.0f, 3.0f * wf, ctrl);
    const float kmax = float(4 * width);
    // Clamped before the conversion (NaN -> 1), selects only: the row loop vectorises.
    const float vc = v >= 1.0f ? (v < kmax ? v : kmax) : 1.0f;
    return int(vc);
}

simd::v8i edge_blur_kernel_size8(int width, simd::v8f ctrl) {
    using simd::v8f;
    const float wf = float(width);
    const v8f v = wf + (0.0f + (3.0f * wf - 0.0f) * ctrl);  // lerp(0, 3W, ctrl) = 0 + (3W - 0) ctrl
    const v8f one = v8f{} + 1.0f, kmax = v8f{} + float(4 * width);
    const v8f vc = v >= one ? (v < kmax ? v : kmax) : one;
    return __builtin_convertvector(vc, simd::v8i);  // truncation, as int(vc)
}

void edge_blur_wc17(ImageF& dst, const ImageF& color, const EdgeBlurWc17Params& p, const Exec& ex) {
    toolkit::check_input(&color, 4, toolkit::Channels::Exactly, "edge_blur", "color");
    const int w = color.width(), h = color.height();
    ImageF src;
    if (p.half_res) src = toolkit::resample(color, half_size(w), half_size(h), ex);
    separable_blur(dst, p.half_res ? src : color, gaussian_weights(p.radius, p.sigma), p.border, ex);
}

namespace {

//! w[K][o], o = 0..K-1: MNPR gaussianWeight(o, K/2) normalised over taps -(K-1)..K-1.
std::vector<std::vector<float>> wc18_tables(int kmax) {
    std::vector<std::vector<float>> t(std::size_t(kmax + 1));
    for (int k = 1; k <= kmax; ++k) {
        const double sigma = double(k) / 2.0;
        std::vector<double> g(static_cast<std::size_t>(k));
        double norm = 0.0;
        for (int o = 0; o < k; ++o) {
            g[std::size_t(o)] = std::exp(-0.5 * double(o) * double(o) / (sigma * sigma)) / sigma;
            norm += (o == 0 ? 1.0 : 2.0) * g[std::size_t(o)];
        }
        t[std::size_t(k)].resize(std::size_t(k));
        for (int o = 0; o < k; ++o) t[std::size_t(k)][std::size_t(o)] = float(g[std::size_t(o)] / norm);
    }
    return t;
}

using WeightTable = std::vector<std::vector<float>>;

//! K of the pixels [i0, i0 + n) from ctrl.edge.g (channel of the 4-channel control), eight at a time.
void kernel_sizes(const ImageF& ctrl, int width, std::size_t i0, std::size_t n, int* k) {
    const float* c = ctrl.data() + 4 * i0;
    constexpr int kG = control::kEdgeWidth.channel;
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        const simd::v8i kv = edge_blur_kernel_size8(width, simd::strided8<4>(c + 4 * i + kG));
        std::memcpy(k + i, &kv, sizeof kv);
    }
    for (; i < n; ++i) k[i] = edge_blur_kernel_size(width, c[4 * i + kG]);
}

//! The plain reference: both passes pixel by pixel through the border rule.
void edge_blur_wc18_reference(ImageF& dst, ImageF& tmp, const ImageF& edges, const ImageF& ctrl, const WeightTable& tab,
                              const EdgeBlurWc18Params& p) {
    const int w = edges.width(), h = edges.height();
    const Border b = p.border;
    std::vector<int> K(std::size_t(w) * h);
    kernel_sizes(ctrl, p.width, 0, K.size(), K.data());
    for (int pass = 0; pass < 2; ++pass) {
        const float* s = pass == 0 ? edges.data() : tmp.data();
        float* o = pass == 0 ? tmp.data() : dst.data();
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const std::size_t i = std::size_t(y) * w + x;
                const int k = K[i];
                const float e0 = s[i];
                float acc = e0;
                for (int a = -(k - 1); a <= k - 1; ++a) {
                    const std::size_t di = pass == 0 ? std::size_t(y) * w + resolve_border(x + a, w, b)
                                                     : std::size_t(resolve_border(y + a, h, b)) * w + x;
                    acc = acc + tab[std::size_t(k)][std::size_t(std::abs(a))] * (s[di] - e0);
                }
                o[i] = acc;
            }
    }
}

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
    MixedWeights(const WeightTable& tab, int kmax)
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

void edge_blur_wc18(ImageF& dst, const ImageF& edges, const ImageF& ctrl, const EdgeBlurWc18Params& p,
                    const Exec& ex) {
    toolkit::check_input(&edges, 1, toolkit::Channels::Exactly, "edge_blur", "edges");
    toolkit::check_input(&ctrl, 4, toolkit::Channels::Exactly, "edge_blur", "ctrl_edge");
    toolkit::check_same_size(ctrl, edges, "edge_blur", "ctrl_edge", "edges");
    if (p.width < 1 || p.width > 16) throw Error("edge_blur: width must be in [1, 16]");
    const int w = edges.width(), h = edges.height();
    const int kmax = 4 * p.width;
    const WeightTable tab = wc18_tables(kmax);
    // K is recomputed per row where needed: cheaper than a full-size table (8 MB at 1080p, faulted
    // in and filled every frame).
    auto sizes = [&](std::size_t i0, std::size_t n, int* k) { kernel_sizes(ctrl, p.width, i0, n, k); };
    ImageF tmp(w, h, 1, kUninitialized);  // pass 0 writes every value
    toolkit::ensure_output(dst, w, h, 1);
    if (ex.traversal == Traversal::Reference) {
        edge_blur_wc18_reference(dst, tmp, edges, ctrl, tab, p);
        return;
    }
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
                        sizes(row + std::size_t(sp.lo), std::size_t(sp.hi - sp.lo + 1), krow.data() + sp.lo);
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
                        if (a0 > sp.lo) sizes(row + std::size_t(sp.lo), std::size_t(a0 - sp.lo), krow.data() + sp.lo);
                        for (int x = a0; x <= a1; ++x) krow[std::size_t(x)] = kb[x];
                        if (a1 < sp.hi) sizes(row + std::size_t(a1 + 1), std::size_t(sp.hi - a1), krow.data() + a1 + 1);
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

void register_edge_blur(Registry& r) {
    using P17 = EdgeBlurWc17Params;
    using P18 = EdgeBlurWc18Params;
    r.add(declare({.stage = "edge_blur",
                   .variant = "wc17",
                   .doc = "WC17 3.3: 5x5 Gaussian (sigma 1) of the colour image at half resolution, for DoG edge darkening",
                   .inputs = {{"color", "color.bled", 4, false}},
                   .outputs = {{"blurred", "color.blurred", 4, false}},
                   .reference = StageVariant::Reference::PlainLoop},
                  ParamTable<P17>()
                      .i("radius", &P17::radius, 1, 16, "kernel radius (WC17: 2, a 5x5 kernel)")
                      .f("sigma", &P17::sigma, 0.1, 16, "Gaussian sigma (WC17: 1)")
                      .b("half_res", &P17::half_res, "blur at half resolution (WC17 as published)")
                      .border(&P17::border),
                  [](StageIO& io, const P17& p, const Exec& ex) { edge_blur_wc17(*io.out[0], *io.in[0], p, ex); }));
    r.add(declare({.stage = "edge_blur",
                   .variant = "wc18",
                   .doc = "WC18 3.1: Gaussian blur of the Sobel edges, per-pixel width from ctrl.edge.g, sigma = K/2, |o| < K",
                   .inputs = {{"edges", "edges", 1, false}, {"ctrl_edge", target::kCtrlEdge, 4, false}},
                   .outputs = {{"blurred", "edges.blurred", 1, false}},
                   .reference = StageVariant::Reference::PlainLoop},
                  ParamTable<P18>()
                      .i("width", &P18::width, 1, 16, "W, global edge width (MNPR 3); K = max(1, int(W + 3W ctrl.edge.g))")
                      .border(&P18::border),
                  [](StageIO& io, const P18& p, const Exec& ex) {
                      edge_blur_wc18(*io.out[0], *io.in[0], *io.in[1], p, ex);
                  }));
}

}  // namespace aq::stylize
