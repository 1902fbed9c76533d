// stylize/stages/edge_detect.cpp — RGBD Sobel edge detection (WC18 §3 "Edge detection"; MNPR
// quadEdgeDetection.ogsfx sobelRGBDFrag, same kernel orientation and accumulation order).
// Reference (here): every tap through the border rule, per pixel. Fast (edge_detect.schedule.cpp):
// planar border-resolved row copies and the same expressions (edge_detect.h sobel_squares,
// sobel_magnitude), x innermost (vectorised); same operations per pixel -> bit-exact.
#include "stylize/stages/edge_detect.h"

#include "stylize/kernels.h"
#include "stylize/stages/toolkit.h"

namespace aq::stylize {

namespace {

//! n[0..8] = TL, TM, TR, ML, M, MR, BL, BM, BR; each {r, g, b, depth}.
inline float sobel_pixel(const float (*n)[4], float wd) {
    float hs, vs;
    sobel_squares([n](int r, int col, int c) { return n[3 * r + col][c]; }, wd, hs, vs);
    return sobel_magnitude(hs, vs);
}

//! The plain reference: every tap through the border rule, pixel by pixel.
void sobel_reference(ImageF& edges, const ImageF& color, const ImageF& depth, const EdgeDetectParams& p) {
    const int w = color.width(), h = color.height();
    const float* cd = color.data();
    const float* zd = depth.data();
    float n[9][4];
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            int k = 0;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx, ++k) {
                    const std::size_t i = std::size_t(resolve_border(y + dy, h, p.border)) * w + resolve_border(x + dx, w, p.border);
                    n[k][0] = cd[4 * i];
                    n[k][1] = cd[4 * i + 1];
                    n[k][2] = cd[4 * i + 2];
                    n[k][3] = zd[i];
                }
            edges.data()[std::size_t(y) * w + x] = sobel_pixel(n, p.depth_weight);
        }
}

}  // namespace

void edge_detect_rgbd_sobel(ImageF& edges, const ImageF& color, const ImageF& depth, const EdgeDetectParams& p,
                            const Exec& ex) {
    toolkit::check_input(&color, 4, toolkit::Channels::Exactly, "edge_detect", "color");
    toolkit::check_input(&depth, 1, toolkit::Channels::Exactly, "edge_detect", "depth");
    toolkit::check_same_size(depth, color, "edge_detect", "depth", "color");
    const int w = color.width(), h = color.height();
    toolkit::ensure_output(edges, w, h, 1);
    if (ex.traversal == Traversal::Reference) sobel_reference(edges, color, depth, p);
    else edge_detect_rgbd_sobel_fast(edges, color, depth, p, ex);
}

void register_edge_detect(Registry& r) {
    using P = EdgeDetectParams;
    StageVariant v = declare({.stage = "edge_detect",
                              .variant = "rgbd_sobel",
                              .doc = "WC18 3: 3x3 Sobel on (r, g, b, depth*wD), magnitude clamped to 1",
                              .inputs = {{"color", "color.adjusted", 4, false}, {"depth", "depth", 1, false, SizeRule::Same, "color"}},
                              .outputs = {{"edges", "edges", 1, false}},
                              .reference = StageVariant::Reference::PlainLoop},
                             ParamTable<P>()
                                 .f("depth_weight", &P::depth_weight, 0, 1000, "wD, depth gradient weight (MNPR 5)")
                                 .border(&P::border),
                             [](StageIO& io, const P& p, const Exec& ex) {
                                 edge_detect_rgbd_sobel(*io.out[0], *io.in[0], *io.in[1], p, ex);
                             });
    v.row_halo = [](const ParamValues&) { return 1; };  // the 3 x 3 Sobel taps
    r.add(std::move(v));
}

}  // namespace aq::stylize
