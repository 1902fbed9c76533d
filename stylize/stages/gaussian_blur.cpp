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

namespace {
struct Table {
    int radius = kGaussianBlurRadius;
    float sigma = kGaussianBlurSigma;
    int border = 0;
    int downsample = 1;
};
}  // namespace

void register_gaussian_blur(Registry& r) {
    static const ParamTable<Table> t = ParamTable<Table>()
        .i("radius", &Table::radius, 1, 64, "kernel radius in pixels of the map (ours: 8)")
        .f("sigma", &Table::sigma, 0.1, 64, "Gaussian sigma in pixels (ours: 4)")
        .e("border", &Table::border, {"clamp", "mirror"}, "taps outside the image: clamp to the edge or mirror")
        .i("downsample", &Table::downsample, 1, 8, "k: mean of k x k blocks first, output ceil(size / k); radius and sigma in those pixels");
    StageVariant v;
    v.stage = "gaussian_blur";
    v.variant = "separable";
    v.doc = "LD06 §2, §3.3: separable Gaussian low-pass of a one-channel map (depth, shadow or intensity map)";
    v.inputs = {{"image", "ld06.depth", 1, false}};
    v.outputs = {{"blurred", "ld06.depth.blurred", 1, false}};
    v.params = t.descs();
    v.run = [](StageIO& io, const ParamValues& pv, const Exec& ex) {
        const auto tp = t.from(pv);
        GaussianBlurParams p;
        p.radius = tp.radius;
        p.sigma = tp.sigma;
        p.border = tp.border ? Border::Mirror : Border::Clamp;
        p.downsample = tp.downsample;
        gaussian_blur(*io.out[0], *io.in[0], p, ex);
    };
    v.reference = StageVariant::Reference::PlainLoop;
    r.add(std::move(v));
}

}  // namespace aq::stylize
