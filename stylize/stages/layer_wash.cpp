// stylize/stages/layer_wash.cpp — see layer_wash.h. Reference: each layer blurred alone, then a
// plain loop sampling every value per pixel; fast (layer_wash.schedule.cpp): the layers blurred as
// one packed image and resampled row by row (the same values bit for bit,
// tests/stylize/registry_traversal_test.cpp). This file: the checks, the reference and the
// declarations.
#include "stylize/stages/layer_wash.h"

#include "stylize/stages/blur.h"
#include "stylize/stages/toolkit.h"

namespace aq::stylize {

using namespace toolkit;

void wash_blur(ImageF& dst, const ImageF& src, int radius, float sigma, const Exec& ex) {
    if (radius <= 0) {
        dst = src;
        return;
    }
    separable_blur(dst, src, gaussian_weights(radius, sigma), Border::Clamp, ex);
}

namespace {

const char* const kPorts[4] = {"layer0", "layer1", "layer2", "layer3"};

//! The checks; returns the index of the first present layer.
int check_layers(const ImageF& dst, const ImageF* const layers[4], const ImageF* paper, int out_w, int out_h) {
    int first = -1;
    for (int k = 0; k < 4; ++k) {
        if (!layers[k]) continue;
        check_input(layers[k], 1, Channels::Exactly, "layer_wash", kPorts[k]);
        check_not_alias(dst, layers[k], "layer_wash", kPorts[k]);
        if (first < 0) first = k;
        else check_same_size(*layers[k], *layers[first], "layer_wash", kPorts[k], "layer0");
    }
    if (first < 0) throw Error("layer_wash: no input layer");
    if (out_w <= 0 || out_h <= 0) throw Error("layer_wash: empty output size");
    if (paper) {
        check_input(paper, 3, Channels::AtLeast, "layer_wash", "paper");
        if (paper->width() != out_w || paper->height() != out_h) throw Error("layer_wash: the paper is not the output size");
    }
    return first;
}

//! The plain schedule: each layer blurred on its own, every value sampled per pixel.
void wash_reference(ImageF& dst, const ImageF* const layers[4], const Plane& hp, int out_w, int out_h, const LayerWashParams& p,
                    const Exec& ex) {
    ImageF blurred[4];
    for (int k = 0; k < 4; ++k)
        if (layers[k]) wash_blur(blurred[k], *layers[k], p.radius, p.sigma, ex);
    ensure_output(dst, out_w, out_h, 4);
    float* o = dst.data();
    plain_loop(out_w, out_h, [&](int x, int y) {
        const float h = hp(x, y);
        for (int k = 0; k < 4; ++k)
            o[(std::size_t(y) * out_w + x) * 4 + k] =
                layers[k] ? wash_amount(sample_resampled_plane(plane(*layers[k], 0), x, y, out_w, out_h),
                                        sample_resampled_plane(plane(blurred[k], 0), x, y, out_w, out_h), h, p.shape)
                          : 0.0f;
    });
}

}  // namespace

void layer_wash(ImageF& dst, const ImageF* const layers[4], const ImageF* paper, int out_w, int out_h,
                const LayerWashParams& p, const Exec& ex, float paper_spread) {
    const int first = check_layers(dst, layers, paper, out_w, out_h);
    const float flat = kFlatPaperHeight;
    const Plane hp = paper ? plane(*paper, 2) : constant_plane(&flat, out_w, out_h);
    if (ex.traversal == Traversal::Reference) wash_reference(dst, layers, hp, out_w, out_h, p, ex);
    else layer_wash_fast(dst, layers, first, paper, hp, out_w, out_h, p, ex, paper_spread);
}

void register_layer_wash(Registry& r) {
    using P = LayerWashParams;
    const auto shape = [](auto m) { return field_path(&P::shape, m); };
    const ParamTable<P> t = ParamTable<P>()
        .i("radius", &P::radius, 0, 64, "Gaussian blur radius in pixels of the intensity maps (ours: 8 at 520 px; 0 = none)")
        .f("sigma", &P::sigma, 0.1, 64, "Gaussian sigma in pixels of the intensity maps (ours: 4)")
        .f("kappa", shape(&WashShape::kappa), 0, 1, "κ: the blurred intensity where the wash's border lies (ours: 0.5)")
        .f("width", shape(&WashShape::width), 0.001, 1,
           "w: half width of the smoothstep, narrow = wet-on-dry, wide = wet-on-wet (ours: 0.2)")
        .f("edge", shape(&WashShape::edge), 0, 8, "edge-darkening gain on max(I - ρ, 0) (ours: 1)")
        .f("border", shape(&WashShape::border), 0, 2, "paper height's perturbation of the border (ours: 0.3)")
        .f("granulation", shape(&WashShape::granulation), 0, 1,
           "paper height's modulation of the pigment, more in valleys (ours: 0.35)")
        .b("paper_before", shape(&WashShape::paper_before),
           "perturb ρ by the paper before the smoothstep (ragged borders); off: perturb the shaped border band after it");
    for (bool additive : {false, true}) {
        r.add(declare({.stage = "layer_wash",
                       .variant = additive ? "additive" : "multiplicative",
                       .doc = std::string("LD06 §3.1 (reconstructed): blur, smoothstep shape, edge darkening (") +
                              (additive ? "p = a + e" : "p = a·(1 + e)") +
                              "), paper border and granulation, per layer; output at the paper's size",
                       .inputs = {{"layer0", "ld06.layer.0", 1, false},
                                  {"layer1", "ld06.layer.1", 1, true, SizeRule::Same, "layer0"},
                                  {"layer2", "ld06.layer.2", 1, true, SizeRule::Same, "layer0"},
                                  {"layer3", "ld06.layer.3", 1, true, SizeRule::Same, "layer0"}},
                       .outputs = {{"wash", "ld06.wash", 4, false}},
                       .reference = StageVariant::Reference::PlainLoop},
                      t, [additive](StageIO& io, P p, const Exec& ex) {
                          p.shape.additive_edge = additive;
                          const Globals& g = globals_of(io);
                          const ImageF* layers[4] = {io.in[0], io.in[1], io.in[2], io.in[3]};
                          const ImageF& size = g.paper ? *g.paper : *io.in[0];
                          layer_wash(*io.out[0], layers, g.paper, size.width(), size.height(), p, ex, paper_spread_of(g, ex));
                      }));
    }
}

}  // namespace aq::stylize
