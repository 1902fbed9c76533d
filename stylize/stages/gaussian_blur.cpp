// stylize/stages/gaussian_blur.cpp — see gaussian_blur.h; the traversals are blur.h's.
#include "stylize/stages/gaussian_blur.h"

#include <algorithm>

#include "stylize/kernels.h"
#include "stylize/stages/blur.h"
#include "stylize/stages/toolkit.h"

namespace aq::stylize {

void gaussian_blur(ImageF& dst, const ImageF& src, const GaussianBlurParams& p, const Exec& ex) {
    toolkit::check_input(&src, 1, toolkit::Channels::Exactly, "gaussian_blur", "image");
    const int k = p.downsample;
    if (k < 1 || k > 8) throw Error("gaussian_blur: downsample must be in [1, 8]");
    if (k == 1) {
        separable_blur(dst, src, gaussian_weights(p.radius, p.sigma), p.border, ex);
        return;
    }
    // Block means, rows of the block then pixels of the row in order, divided by the pixel count
    // (the twin's order): the same arithmetic in every traversal.
    const int w = src.width(), h = src.height(), wd = (w + k - 1) / k, hd = (h + k - 1) / k;
    ImageF small(wd, hd, 1);
    toolkit::for_each_row_block(ex, hd, [&](int y0, int y1) {
        for (int y = y0; y < y1; ++y)
            for (int x = 0; x < wd; ++x) {
                const int ye = std::min(h, (y + 1) * k), xe = std::min(w, (x + 1) * k);
                float sum = 0.0f;
                for (int yy = y * k; yy < ye; ++yy)
                    for (int xx = x * k; xx < xe; ++xx) sum += src.at(xx, yy, 0);
                small.at(x, y, 0) = sum / float((ye - y * k) * (xe - x * k));
            }
    });
    separable_blur(dst, small, gaussian_weights(p.radius, p.sigma), p.border, ex);
}

void register_gaussian_blur(Registry& r) {
    using P = GaussianBlurParams;
    r.add(declare({.stage = "gaussian_blur",
                   .variant = "separable",
                   .doc = "LD06 §2, §3.3: separable Gaussian low-pass of a one-channel map (depth, shadow or intensity map)",
                   .inputs = {{"image", "ld06.depth", 1, false}},
                   .outputs = {{"blurred", "ld06.depth.blurred", 1, false}},
                   .reference = StageVariant::Reference::PlainLoop},
                  ParamTable<P>()
                      .i("radius", &P::radius, 1, 64, "kernel radius in pixels of the map (ours: 8)")
                      .f("sigma", &P::sigma, 0.1, 64, "Gaussian sigma in pixels (ours: 4)")
                      .border(&P::border)
                      .i("downsample", &P::downsample, 1, 8,
                         "k: mean of k x k blocks first, output ceil(size / k); radius and sigma in those pixels"),
                  [](StageIO& io, const P& p, const Exec& ex) { gaussian_blur(*io.out[0], *io.in[0], p, ex); }));
}

}  // namespace aq::stylize
