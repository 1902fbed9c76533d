// stylize/stages/extend_edges.cpp — see extend_edges.h. The separable part is blur.h (bit-exact
// reference/fast); the pointwise gamma is extend_edges_gamma, pixel by pixel in the reference here
// and packed by chunks in the fast schedule (extend_edges.schedule.cpp).
#include "stylize/stages/extend_edges.h"

#include <cmath>
#include <vector>

#include "stylize/kernels.h"

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
    extend_edges_gamma_fast(dst, g, ex);
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
