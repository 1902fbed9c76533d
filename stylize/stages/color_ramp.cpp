// stylize/stages/color_ramp.cpp — see color_ramp.h. Pointwise; one row traversal for both schedules.
#pragma GCC optimize("no-trapping-math")  // lets the row loop if-convert and vectorise; values unchanged
#include "stylize/stages/color_ramp.h"

#include "stylize/scene_inputs.h"

#include <algorithm>

#include "stylize/stages/toolkit.h"

namespace aq::stylize {

using namespace toolkit;

void color_ramp(ImageF* const dst[4], const ImageF& lighting, const ColorRampParams& p, const Exec& ex) {
    check_input(&lighting, 1, Channels::Exactly, "color_ramp", "lighting");
    const int w = lighting.width(), h = lighting.height();
    for (int k = 0; k < 4; ++k) {
        check_not_alias(*dst[k], &lighting, "color_ramp", "lighting");
        ensure_output(*dst[k], w, h, 4);
    }
    const float* in = lighting.data();
    if (ex.traversal == Traversal::Reference) {  // the plain loop: ramp_color pixel by pixel
        for (int k = 0; k < 4; ++k) {
            const ColorRampLayer l = p.layer[k];
            float* o = dst[k]->data();
            plain_loop(w, h, [&](int x, int y) {
                const std::size_t i = std::size_t(y) * w + x;
                const glm::vec3 c = ramp_color(in[i], l.color, l.dark, l.tone, p.hue);
                o[i * 4] = c.r, o[i * 4 + 1] = c.g, o[i * 4 + 2] = c.b, o[i * 4 + 3] = l.alpha;
            });
        }
        return;
    }
    // Fast: per layer, row by row (color_ramp_row).
    for_each_row(ex, w, h, [&](int y, int x0, int x1) {
        const std::size_t r = std::size_t(y) * w;
        for (int k = 0; k < 4; ++k) color_ramp_row(in + r + x0, x1 - x0, p.layer[k], p.hue, dst[k]->data() + (r + x0) * 4);
    });
}

// Per chunk of the row, ramp_color into R, G, B planes (a loop over x without branches: it
// vectorises), then stored as RGBA pixels 8 at a time (store_rgba8).
void color_ramp_row(const float* t, int n, const ColorRampLayer& l, const RampColors& hue, float* o) {
    constexpr int kChunk = 64;
    alignas(32) float R[kChunk], G[kChunk], B[kChunk], A[kChunk];
    std::fill_n(A, kChunk, l.alpha);
    for (int xs = 0; xs < n; xs += kChunk) {
        const int m = std::min(kChunk, n - xs);
        for (int i = 0; i < m; ++i) {
            const glm::vec3 c = ramp_color(t[xs + i], l.color, l.dark, l.tone, hue);
            R[i] = c.r, G[i] = c.g, B[i] = c.b;
        }
        int i = 0;
        for (; i + 8 <= m; i += 8) store_rgba8(o + std::size_t(xs + i) * 4, R + i, G + i, B + i, A + i);
        for (; i < m; ++i) {
            float* q = o + std::size_t(xs + i) * 4;
            q[0] = R[i], q[1] = G[i], q[2] = B[i], q[3] = A[i];
        }
    }
}

namespace {
using T = ColorRampTable;
const ParamTable<T>& table() {
    static const ParamTable<T> t = ParamTable<T>()
        .e("source", &T::source, {"given", "layers", "foliage"}, "where the layer colours come from: as given, the scene's layers first..first+3, or the foliage layer (particles)")
        .i("first", &T::first, 0, 1 << 24, "scene layer of layer0 for source layers (as id_layers.first)")
        .f("cool_r", &T::cool_r, 0, 1, "hue ramp, cool end k_blue (r) (Gooch: (0, 0, b), b = 0.4; ours b = 0.1)")
        .f("cool_g", &T::cool_g, 0, 1, "hue ramp, cool end (g)")
        .f("cool_b", &T::cool_b, 0, 1, "hue ramp, cool end (b)")
        .f("warm_r", &T::warm_r, 0, 1, "hue ramp, warm end k_yellow (r) (Gooch: (y, y, 0), y = 0.4; ours y = 0.1)")
        .f("warm_g", &T::warm_g, 0, 1, "hue ramp, warm end (g)")
        .f("warm_b", &T::warm_b, 0, 1, "hue ramp, warm end (b)")
        .f("cool_mix", &T::cool_mix, 0, 2, "Gooch α: object colour in the cool end (Gooch 0.2; ours 0.8)")
        .f("warm_mix", &T::warm_mix, 0, 2, "Gooch β: object colour in the warm end (Gooch 0.6; ours 1.0)")
        .f("keep_hue", &T::keep_hue, 0, 1, "how much a saturated colour keeps its hue: the cool/warm shift is weighted by 1 - keep_hue x saturation (0 = Gooch's shift on every colour; ours 1)")
        .f("color0_r", &T::color0_r, 0, 1, "layer0 object ramp, lit end (r; display value)")
        .f("color0_g", &T::color0_g, 0, 1, "layer0 object ramp, lit end (g; display value)")
        .f("color0_b", &T::color0_b, 0, 1, "layer0 object ramp, lit end (b; display value)")
        .f("dark0_r", &T::dark0_r, 0, 1, "layer0 object ramp, unlit end (r; ours: 0.55 x colour)")
        .f("dark0_g", &T::dark0_g, 0, 1, "layer0 object ramp, unlit end (g; ours: 0.55 x colour)")
        .f("dark0_b", &T::dark0_b, 0, 1, "layer0 object ramp, unlit end (b; ours: 0.55 x colour)")
        .f("alpha0", &T::alpha0, 0, 1, "layer0 ramp alpha: the wash's opacity (ours: 0.85)")
        .f("tone0", &T::tone0, 0, 4, "layer0 factor on its object ramp (particle layers: darker / brighter tones)")
        .f("color1_r", &T::color1_r, 0, 1, "layer1 object ramp, lit end (r; display value)")
        .f("color1_g", &T::color1_g, 0, 1, "layer1 object ramp, lit end (g; display value)")
        .f("color1_b", &T::color1_b, 0, 1, "layer1 object ramp, lit end (b; display value)")
        .f("dark1_r", &T::dark1_r, 0, 1, "layer1 object ramp, unlit end (r; ours: 0.55 x colour)")
        .f("dark1_g", &T::dark1_g, 0, 1, "layer1 object ramp, unlit end (g; ours: 0.55 x colour)")
        .f("dark1_b", &T::dark1_b, 0, 1, "layer1 object ramp, unlit end (b; ours: 0.55 x colour)")
        .f("alpha1", &T::alpha1, 0, 1, "layer1 ramp alpha: the wash's opacity (ours: 0.85)")
        .f("tone1", &T::tone1, 0, 4, "layer1 factor on its object ramp (particle layers: darker / brighter tones)")
        .f("color2_r", &T::color2_r, 0, 1, "layer2 object ramp, lit end (r; display value)")
        .f("color2_g", &T::color2_g, 0, 1, "layer2 object ramp, lit end (g; display value)")
        .f("color2_b", &T::color2_b, 0, 1, "layer2 object ramp, lit end (b; display value)")
        .f("dark2_r", &T::dark2_r, 0, 1, "layer2 object ramp, unlit end (r; ours: 0.55 x colour)")
        .f("dark2_g", &T::dark2_g, 0, 1, "layer2 object ramp, unlit end (g; ours: 0.55 x colour)")
        .f("dark2_b", &T::dark2_b, 0, 1, "layer2 object ramp, unlit end (b; ours: 0.55 x colour)")
        .f("alpha2", &T::alpha2, 0, 1, "layer2 ramp alpha: the wash's opacity (ours: 0.85)")
        .f("tone2", &T::tone2, 0, 4, "layer2 factor on its object ramp (particle layers: darker / brighter tones)")
        .f("color3_r", &T::color3_r, 0, 1, "layer3 object ramp, lit end (r; display value)")
        .f("color3_g", &T::color3_g, 0, 1, "layer3 object ramp, lit end (g; display value)")
        .f("color3_b", &T::color3_b, 0, 1, "layer3 object ramp, lit end (b; display value)")
        .f("dark3_r", &T::dark3_r, 0, 1, "layer3 object ramp, unlit end (r; ours: 0.55 x colour)")
        .f("dark3_g", &T::dark3_g, 0, 1, "layer3 object ramp, unlit end (g; ours: 0.55 x colour)")
        .f("dark3_b", &T::dark3_b, 0, 1, "layer3 object ramp, unlit end (b; ours: 0.55 x colour)")
        .f("alpha3", &T::alpha3, 0, 1, "layer3 ramp alpha: the wash's opacity (ours: 0.85)")
        .f("tone3", &T::tone3, 0, 4, "layer3 factor on its object ramp (particle layers: darker / brighter tones)");
    return t;
}
}  // namespace

ColorRampParams color_ramp_params(const ParamValues& pv) {
    const T tp = table().from(pv);
    ColorRampParams p;
    p.hue.cool = {tp.cool_r, tp.cool_g, tp.cool_b};
    p.hue.warm = {tp.warm_r, tp.warm_g, tp.warm_b};
    p.hue.cool_mix = tp.cool_mix;
    p.hue.warm_mix = tp.warm_mix;
    p.hue.keep_hue = tp.keep_hue;
    p.layer[0] = {{tp.color0_r, tp.color0_g, tp.color0_b}, {tp.dark0_r, tp.dark0_g, tp.dark0_b}, tp.alpha0, tp.tone0};
    p.layer[1] = {{tp.color1_r, tp.color1_g, tp.color1_b}, {tp.dark1_r, tp.dark1_g, tp.dark1_b}, tp.alpha1, tp.tone1};
    p.layer[2] = {{tp.color2_r, tp.color2_g, tp.color2_b}, {tp.dark2_r, tp.dark2_g, tp.dark2_b}, tp.alpha2, tp.tone2};
    p.layer[3] = {{tp.color3_r, tp.color3_g, tp.color3_b}, {tp.dark3_r, tp.dark3_g, tp.dark3_b}, tp.alpha3, tp.tone3};
    return p;
}

namespace {
//! LD06 layer colours (docs/ld06.md "Layers"): with `source` 1 or 2 the step takes the colours of
//! the scene's layers (1: layers first..first+3; 2: the foliage layer in all four).
std::vector<SceneValue> layer_colors(const ParamValues& pv, const SceneInputs& scene) {
    std::vector<SceneValue> out;
    const int source = int(pv.at("source"));
    if (source == 0) return out;
    const scene::LayerTable& table = scene.layers();
    const int foliage_layer = source == 2 ? scene.foliage_layer() : -1;
    const std::string why = "the scene's layer colours";
    for (int k = 0; k < 4; ++k) {
        const int l = source == 1 ? int(pv.at("first")) + k : foliage_layer;
        if (l < 0 || l >= int(table.layers.size())) continue;
        const scene::Layer& layer = table.layers[std::size_t(l)];
        const std::string n = std::to_string(k);
        for (int c = 0; c < 3; ++c) {
            const std::string ch(1, "rgb"[c]);
            out.push_back({"color" + n + "_" + ch, double(layer.color[c]), why});
            out.push_back({"dark" + n + "_" + ch, double(layer.dark[c]), why});
        }
        if (source == 1) out.push_back({"alpha" + n, double(layer.alpha) * pv.at("alpha" + n), why});
    }
    return out;
}
}  // namespace

void register_color_ramp(Registry& r) {
    StageVariant v;
    v.stage = "color_ramp";
    v.variant = "gooch";
    v.doc = "LD06 §3.2: hue-shifting ramp (Gooch cool-to-warm) with per-layer object ramps and alpha, indexed by the lighting map; RGBA per layer";
    v.inputs = {{"lighting", "ld06.lighting", 1, false}};
    v.outputs = {{"ramp0", "ld06.ramp.0", 4, false},
                 {"ramp1", "ld06.ramp.1", 4, false},
                 {"ramp2", "ld06.ramp.2", 4, false},
                 {"ramp3", "ld06.ramp.3", 4, false}};
    v.params = table().descs();
    v.run = with_port_check(v, [](StageIO& io, const ParamValues& pv, const Exec& ex) {
        ImageF* const out[4] = {io.out[0], io.out[1], io.out[2], io.out[3]};
        color_ramp(out, *io.in[0], color_ramp_params(pv), ex);
    });
    v.reference = StageVariant::Reference::SharedMaths;
    v.scene_params = layer_colors;
    r.add(std::move(v));
}

}  // namespace aq::stylize
