// stylize/stages/gaussian_blur.cpp — see gaussian_blur.h; the traversals are blur.h's.
#include "stylize/stages/gaussian_blur.h"

#include "stylize/kernels.h"
#include "stylize/stages/blur.h"

namespace aq::stylize {

void gaussian_blur(ImageF& dst, const ImageF& src, const GaussianBlurParams& p, const Exec& ex) {
    toolkit::check_input(&src, 1, toolkit::Channels::Exactly, "gaussian_blur", "image");
    separable_blur(dst, src, gaussian_weights(p.radius, p.sigma), p.border, ex);
}

namespace {
struct Table {
    int radius = kGaussianBlurRadius;
    float sigma = kGaussianBlurSigma;
    int border = 0;
};
}  // namespace

void register_gaussian_blur(Registry& r) {
    static const ParamTable<Table> t = ParamTable<Table>()
        .i("radius", &Table::radius, 1, 64, "kernel radius in pixels of the map (ours: 8)")
        .f("sigma", &Table::sigma, 0.1, 64, "Gaussian sigma in pixels (ours: 4)")
        .i("border", &Table::border, 0, 1, "0 = clamp, 1 = mirror");
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
        gaussian_blur(*io.out[0], *io.in[0], p, ex);
    };
    v.reference = StageVariant::Reference::PlainLoop;
    r.add(std::move(v));
}

}  // namespace aq::stylize
