// stylize/stages/edge_blur.cpp — WC17 half-resolution 5x5 Gaussian and WC18 variable-width edge blur.
// The WC18 blur uses the delta form of blur.h with a per-pixel normalised table:
//   acc = e0;  for a = -(K-1)..(K-1) ascending: acc = acc + w_K[|a|] * (E(x + a) - e0)
// Reference: per pixel through the border rule. Fast: K computed per row (the same K for a pixel
// in both passes), each row split into runs of equal K, each run a fixed-kernel loop with x innermost —
// the same taps in the same order per pixel, so bit-identical. This file: the checks, the kernel
// sizes, the weights, the reference and the declarations; the fast schedule is
// edge_blur.schedule.cpp.
#include "stylize/stages/edge_blur.h"

#include <algorithm>
#include <cmath>
#include <cstring>
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

void edge_blur_kernel_sizes(const ImageF& ctrl, int width, std::size_t i0, std::size_t n, int* k) {
    const float* c = ctrl.data() + 4 * i0;
    constexpr int kG = control::kEdgeWidth.channel;
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        const simd::v8i kv = edge_blur_kernel_size8(width, simd::strided8<4>(c + 4 * i + kG));
        std::memcpy(k + i, &kv, sizeof kv);
    }
    for (; i < n; ++i) k[i] = edge_blur_kernel_size(width, c[4 * i + kG]);
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
EdgeBlurWeights wc18_tables(int kmax) {
    EdgeBlurWeights t(std::size_t(kmax + 1));
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

//! The plain reference: both passes pixel by pixel through the border rule.
void edge_blur_wc18_reference(ImageF& dst, ImageF& tmp, const ImageF& edges, const ImageF& ctrl, const EdgeBlurWeights& tab,
                              const EdgeBlurWc18Params& p) {
    const int w = edges.width(), h = edges.height();
    const Border b = p.border;
    std::vector<int> K(std::size_t(w) * h);
    edge_blur_kernel_sizes(ctrl, p.width, 0, K.size(), K.data());
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

}  // namespace

void edge_blur_wc18(ImageF& dst, const ImageF& edges, const ImageF& ctrl, const EdgeBlurWc18Params& p,
                    const Exec& ex) {
    toolkit::check_input(&edges, 1, toolkit::Channels::Exactly, "edge_blur", "edges");
    toolkit::check_input(&ctrl, 4, toolkit::Channels::Exactly, "edge_blur", "ctrl_edge");
    toolkit::check_same_size(ctrl, edges, "edge_blur", "ctrl_edge", "edges");
    if (p.width < 1 || p.width > 16) throw Error("edge_blur: width must be in [1, 16]");
    const int w = edges.width(), h = edges.height();
    const EdgeBlurWeights tab = wc18_tables(4 * p.width);
    ImageF tmp(w, h, 1, kUninitialized);  // pass 0 writes every value
    toolkit::ensure_output(dst, w, h, 1);
    if (ex.traversal == Traversal::Reference) edge_blur_wc18_reference(dst, tmp, edges, ctrl, tab, p);
    else edge_blur_wc18_fast(dst, tmp, edges, ctrl, tab, p, ex);
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
                   .inputs = {{"edges", "edges", 1, false}, {"ctrl_edge", target::kCtrlEdge, 4, false, SizeRule::Same, "edges"}},
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
