// stylize/stages/extend_edges.cpp — see extend_edges.h. The separable part is blur.h (bit-exact
// reference/fast); the pointwise gamma is extend_edges_gamma, pixel by pixel in the reference and
// packed by chunks in the fast schedule, with the deterministic pow_c of core/fastmath.h (vectorised; needs -fno-trapping-math: FP exception
// flags only, no value changes).
#pragma GCC optimize("no-trapping-math")
#include "stylize/stages/extend_edges.h"

#include <algorithm>
#include <cmath>

#include "stylize/kernels.h"
#include <vector>

#include "stylize/stages/blur.h"
#include "stylize/stages/toolkit.h"

namespace aq::stylize {

std::vector<float> linear_weights(int width) {
    std::vector<double> g(std::size_t(2 * width - 1));
    double norm = 0.0;
    for (int l = -(width - 1); l <= width - 1; ++l) {
        g[std::size_t(l + width - 1)] = 1.0 - double(std::abs(l)) / double(width);
        norm += g[std::size_t(l + width - 1)];
    }
    std::vector<float> w(g.size());
    for (std::size_t i = 0; i < g.size(); ++i) w[i] = float(g[i] / norm);
    return w;
}

void extend_edges(ImageF& dst, const ImageF& edges, const ExtendEdgesParams& p, const Exec& ex) {
    toolkit::check_input(&edges, 1, toolkit::Channels::Exactly, "extend_edges", "edges");
    if (p.width < 1 || p.width > 32) throw Error("extend_edges: width must be in [1, 32]");
    separable_blur(dst, edges, linear_weights(p.width), p.border, ex);
    const float g = 2.0f / float(p.width);
    float* d = dst.data();
    const int w = dst.width();
    if (ex.traversal == Traversal::Reference) {  // the plain reference: the gamma pixel by pixel
        toolkit::plain_loop(w, dst.height(), [&](int x, int y) {
            float& v = d[std::size_t(y) * w + x];
            v = extend_edges_gamma(v, g);
        });
        return;
    }
    toolkit::for_each_row_block(ex, dst.height(), [&](int y0, int y1) {
        // b > 0: (b^(1/b))^(2/W) = b^((1/b) (2/W)), taken as one power (MNPR takes two; the
        // results differ by rounding only, and where b^(1/b) alone would underflow: values below
        // 1e-30, checked against the two-power GLSL twin by tests/reference); b <= 0 (and NaN) -> 0.
        // The positive values of a chunk are packed and only they take the power (vectorised).
        constexpr std::size_t kChunk = 256;
        float bs[kChunk], t[kChunk];
        int idx[kChunk];
        const std::size_t end = std::size_t(y1) * w;
        for (std::size_t i0 = std::size_t(y0) * w; i0 < end; i0 += kChunk) {
            const std::size_t n = std::min(kChunk, end - i0);
            float* di = d + i0;
            // No positive value (the background's zeros): only the clamp below.
            if (!toolkit::any_above(di, n, 0.0f)) {
                for (std::size_t j = 0; j < n; ++j) di[j] = di[j] > 0.0f ? di[j] : 0.0f;
                continue;
            }
            int m = 0;
            for (std::size_t j = 0; j < n; ++j) m += di[j] > 0.0f;
            if (std::size_t(4 * m) >= n) {
                // Mostly positive (inside a model's edges): every value takes the power, without
                // packing, and the non-positive ones are replaced by 0 — a positive value's power
                // is the same operations either way.
                for (std::size_t j = 0; j < n; ++j) bs[j] = di[j] > 0.0f ? di[j] : 1.0f;
                for (std::size_t j = 0; j < n; ++j) t[j] = (1.0f / bs[j]) * g;
                pow_c_many(bs, t, t, n);
                for (std::size_t j = 0; j < n; ++j) di[j] = di[j] > 0.0f ? t[j] : 0.0f;
                continue;
            }
            m = 0;
            for (std::size_t j = 0; j < n; ++j) {
                idx[m] = int(j);
                m += di[j] > 0.0f;
            }
            for (int q = 0; q < m; ++q) bs[q] = di[idx[q]];
            for (int q = 0; q < m; ++q) t[q] = (1.0f / bs[q]) * g;
            pow_c_many(bs, t, t, std::size_t(m));
            for (std::size_t j = 0; j < n; ++j) di[j] = di[j] > 0.0f ? di[j] : 0.0f;  // <= 0, NaN -> 0
            for (int q = 0; q < m; ++q) di[idx[q]] = t[q];
        }
    });
}

void register_extend_edges(Registry& r) {
    using P = ExtendEdgesParams;
    r.add(declare({.stage = "extend_edges",
                   .variant = "mnpr",
                   .doc = "WC18 3.2 / MNPR: linear kernel (1 - |l|/W, normalised) over the edges, b = b^(1/b), b = b^(2/W)",
                   .inputs = {{"edges", "edges", 1, false}},
                   .outputs = {{"extended", "edges.extended", 1, false}},
                   .reference = StageVariant::Reference::PlainLoop},
                  ParamTable<P>()
                      .i("width", &P::width, 1, 32, "W, linear kernel width (MNPR 3; WC18 paper m = 5)")
                      .border(&P::border),
                  [](StageIO& io, const P& p, const Exec& ex) { extend_edges(*io.out[0], *io.in[0], p, ex); }));
}

}  // namespace aq::stylize
