// stylize/stages/layer_wash.cpp — see layer_wash.h. Blur: blur.h's separable traversals. Shaping:
// wash_amount per pixel, over a plain loop (reference) or oneTBB rows with precomputed resampling
// taps (fast); the taps give sample_resampled_plane's values bit for bit.
#include "stylize/stages/layer_wash.h"

#include "stylize/paper.h"
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

void layer_wash(ImageF& dst, const ImageF* const layers[4], const ImageF* paper, int out_w, int out_h,
                const LayerWashParams& p, const Exec& ex) {
    static const char* kPorts[4] = {"layer0", "layer1", "layer2", "layer3"};
    const ImageF* first = nullptr;
    for (int k = 0; k < 4; ++k) {
        if (!layers[k]) continue;
        check_input(layers[k], 1, Channels::Exactly, "layer_wash", kPorts[k]);
        check_not_alias(dst, layers[k], "layer_wash", kPorts[k]);
        if (!first) first = layers[k];
        else check_same_size(*layers[k], *first, "layer_wash", kPorts[k], "layer0");
    }
    if (!first) throw Error("layer_wash: no input layer");
    if (out_w <= 0 || out_h <= 0) throw Error("layer_wash: empty output size");
    if (paper) {
        check_input(paper, 3, Channels::AtLeast, "layer_wash", "paper");
        if (paper->width() != out_w || paper->height() != out_h) throw Error("layer_wash: the paper is not the output size");
    }
    ImageF blurred[4];
    for (int k = 0; k < 4; ++k)
        if (layers[k]) wash_blur(blurred[k], *layers[k], p.radius, p.sigma, ex);
    ensure_output(dst, out_w, out_h, 4);
    const float flat = kFlatPaperHeight;
    const Plane hp = paper ? plane(*paper, 2) : constant_plane(&flat, out_w, out_h);
    const float zero = 0.0f;
    Plane I[4], R[4];
    for (int k = 0; k < 4; ++k) {
        I[k] = layers[k] ? plane(*layers[k], 0) : constant_plane(&zero, first->width(), first->height());
        R[k] = layers[k] ? plane(blurred[k], 0) : constant_plane(&zero, first->width(), first->height());
    }
    float* o = dst.data();
    if (ex.traversal == Traversal::Reference) {
        plain_loop(out_w, out_h, [&](int x, int y) {
            const float h = hp(x, y);
            for (int k = 0; k < 4; ++k)
                o[(std::size_t(y) * out_w + x) * 4 + k] =
                    layers[k] ? wash_amount(sample_resampled_plane(I[k], x, y, out_w, out_h),
                                            sample_resampled_plane(R[k], x, y, out_w, out_h), h, p.shape)
                              : 0.0f;
        });
        return;
    }
    const Resampler rs(out_w, out_h, first->width(), first->height());
    for_each_row(ex, out_w, out_h, [&](int y, int x0, int x1) {
        float* row = o + std::size_t(y) * out_w * 4;
        for (int x = x0; x < x1; ++x) {
            const float h = hp(x, y);
            for (int k = 0; k < 4; ++k)
                row[std::size_t(x) * 4 + k] = layers[k] ? wash_amount(rs.sample(I[k], x, y), rs.sample(R[k], x, y), h, p.shape) : 0.0f;
        }
    });
}

namespace {
struct Table {
    int radius = kGaussianBlurRadius;
    float sigma = kGaussianBlurSigma;
    float kappa = kWashKappa, width = kWashWidth, edge = kWashEdge, border = kWashBorder, granulation = kWashGranulation;
    bool paper_before = true;
};
}  // namespace

void register_layer_wash(Registry& r) {
    static const ParamTable<Table> t = ParamTable<Table>()
        .i("radius", &Table::radius, 0, 64, "Gaussian blur radius in pixels of the intensity maps (ours: 8 at 520 px; 0 = none)")
        .f("sigma", &Table::sigma, 0.1, 64, "Gaussian sigma in pixels of the intensity maps (ours: 4)")
        .f("kappa", &Table::kappa, 0, 1, "κ: the blurred intensity where the wash's border lies (ours: 0.5)")
        .f("width", &Table::width, 0.001, 1, "w: half width of the smoothstep, narrow = wet-on-dry, wide = wet-on-wet (ours: 0.2)")
        .f("edge", &Table::edge, 0, 8, "edge-darkening gain on max(I - ρ, 0) (ours: 1)")
        .f("border", &Table::border, 0, 2, "paper height's perturbation of the border (ours: 0.3)")
        .f("granulation", &Table::granulation, 0, 1, "paper height's modulation of the pigment, more in valleys (ours: 0.35)")
        .b("paper_before", &Table::paper_before, "perturb ρ by the paper before the smoothstep (ragged borders); off: perturb the shaped border band after it");
    for (bool additive : {false, true}) {
        StageVariant v;
        v.stage = "layer_wash";
        v.variant = additive ? "additive" : "multiplicative";
        v.doc = std::string("LD06 §3.1 (reconstructed): blur, smoothstep shape, edge darkening (") +
                (additive ? "p = a + e" : "p = a·(1 + e)") + "), paper border and granulation, per layer; output at the paper's size";
        v.inputs = {{"layer0", "ld06.layer.0", 1, false},
                    {"layer1", "ld06.layer.1", 1, true},
                    {"layer2", "ld06.layer.2", 1, true},
                    {"layer3", "ld06.layer.3", 1, true}};
        v.outputs = {{"wash", "ld06.wash", 4, false}};
        v.params = t.descs();
        v.run = with_port_check(v, [additive](StageIO& io, const ParamValues& pv, const Exec& ex) {
            const auto tp = t.from(pv);
            LayerWashParams p;
            p.radius = tp.radius;
            p.sigma = tp.sigma;
            p.shape = {tp.kappa, tp.width, tp.edge, tp.border, tp.granulation, tp.paper_before, additive};
            const ImageF* paper = globals_of(io).paper;
            const ImageF* layers[4] = {io.in[0], io.in[1], io.in[2], io.in[3]};
            const int w = paper ? paper->width() : io.in[0]->width(), h = paper ? paper->height() : io.in[0]->height();
            layer_wash(*io.out[0], layers, paper, w, h, p, ex);
        });
        v.reference = StageVariant::Reference::PlainLoop;
        r.add(std::move(v));
    }
}

}  // namespace aq::stylize
