// stylize/stages/shadow_layer.cpp — see shadow_layer.h: layer_wash for one layer, then glaze_px.
#include "stylize/stages/shadow_layer.h"

#include "stylize/stages/toolkit.h"
#include "stylize/stages/wash.h"

namespace aq::stylize {

using namespace toolkit;

void shadow_layer(ImageF& dst, const ImageF& color, const ImageF& shadow, const ImageF* paper, const ShadowLayerParams& p,
                  bool multiplicative, const Exec& ex, float paper_spread) {
    check_input(&color, 4, Channels::Exactly, "shadow_layer", "color");
    check_input(&shadow, 1, Channels::Exactly, "shadow_layer", "shadow");
    check_not_alias(dst, &color, "shadow_layer", "color");
    check_not_alias(dst, &shadow, "shadow_layer", "shadow");
    check_paper(paper, color, "shadow_layer", "color");
    const int w = color.width(), h = color.height();
    ImageF amount;
    const ImageF* layers[4] = {&shadow, nullptr, nullptr, nullptr};
    layer_wash(amount, layers, paper, w, h, p.wash, ex, paper_spread);  // both traversals follow ex
    ensure_output(dst, w, h, 4);
    const float* a = amount.data();
    const float* c = color.data();
    float* o = dst.data();
    for_each_row(ex, w, h, [&](int y, int x0, int x1) {
        const std::size_t i = (std::size_t(y) * w + x0) * 4;
        if (multiplicative) glaze_row_of<true>(o + i, c + i, a + i, 4, x1 - x0, p.color, p.alpha);
        else glaze_row_of<false>(o + i, c + i, a + i, 4, x1 - x0, p.color, p.alpha);
    });
}

void register_shadow_layer(Registry& r) {
    using P = ShadowLayerParams;
    const auto shape = [](auto m) { return field_path(&P::wash, &LayerWashParams::shape, m); };
    const ParamTable<P> t = ParamTable<P>()
        .i("radius", field_path(&P::wash, &LayerWashParams::radius), 0, 64,
           "Gaussian blur radius in pixels of the shadow map (ours: 8; 0 = none)")
        .f("sigma", field_path(&P::wash, &LayerWashParams::sigma), 0.1, 64, "Gaussian sigma (ours: 4)")
        .f("kappa", shape(&WashShape::kappa), 0, 1, "κ of the wash's smoothstep (ours: 0.5)")
        .f("width", shape(&WashShape::width), 0.001, 1, "w of the wash's smoothstep (ours: 0.3, a soft wet-on-wet shadow)")
        .f("edge", shape(&WashShape::edge), 0, 8, "edge-darkening gain (ours: 0.5)")
        .f("border", shape(&WashShape::border), 0, 2, "paper perturbation of the border (ours: 0.3)")
        .f("granulation", shape(&WashShape::granulation), 0, 1, "paper modulation of the pigment (ours: 0.35)")
        .f("color_r", field_path(&P::color, &glm::vec3::r), 0, 1, "shadow colour (r; display value; ours: a cool blue-grey)")
        .f("color_g", field_path(&P::color, &glm::vec3::g), 0, 1, "shadow colour (g)")
        .f("color_b", field_path(&P::color, &glm::vec3::b), 0, 1, "shadow colour (b)")
        .f("alpha", &P::alpha, 0, 1, "shadow wash opacity (ours: 0.5, 'semi-transparently painted')");
    for (bool mul : {true, false}) {
        r.add(declare({.stage = "shadow_layer",
                       .variant = mul ? "multiplicative" : "over",
                       .doc = std::string("LD06 §3.3: the shadow intensity map as one more wash (blur, shape, edge, paper), "
                                          "glazed ") + (mul ? "multiplicatively" : "with alpha over") + " onto the picture",
                       .inputs = {{"color", "color.glazed", 4, false}, {"shadow", "ld06.shadow", 1, false}},
                       .outputs = {{"color", "color.shadowed", 4, false}},
                       .reference = StageVariant::Reference::SharedMaths},
                      t, [mul](StageIO& io, const P& p, const Exec& ex) {
                          const Globals& g = globals_of(io);
                          shadow_layer(*io.out[0], *io.in[0], *io.in[1], g.paper, p, mul, ex, paper_spread_of(g, ex));
                      }));
    }
}

}  // namespace aq::stylize
