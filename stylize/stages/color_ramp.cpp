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
using P = ColorRampParams;

const ParamTable<P>& table() {
    static const ParamTable<P> t = [] {
        ParamTable<P> t;
        t.e("source", &P::source, {"given", "layers", "foliage"},
            "where the layer colours come from: as given, the scene's layers first..first+3, or the foliage layer (particles)")
            .i("first", &P::first, 0, 1 << 24, "scene layer of layer0 for source layers (as id_layers.first)");
        const char* const rgb[3] = {"r", "g", "b"};
        for (int c = 0; c < 3; ++c)
            t.f(std::string("cool_") + rgb[c], field_path(&P::hue, &RampColors::cool, c), 0, 1,
                c == 0 ? "hue ramp, cool end k_blue (r) (Gooch: (0, 0, b), b = 0.4; ours b = 0.1)"
                       : std::string("hue ramp, cool end (") + rgb[c] + ")");
        for (int c = 0; c < 3; ++c)
            t.f(std::string("warm_") + rgb[c], field_path(&P::hue, &RampColors::warm, c), 0, 1,
                c == 0 ? "hue ramp, warm end k_yellow (r) (Gooch: (y, y, 0), y = 0.4; ours y = 0.1)"
                       : std::string("hue ramp, warm end (") + rgb[c] + ")");
        t.f("cool_mix", field_path(&P::hue, &RampColors::cool_mix), 0, 2, "Gooch α: object colour in the cool end (Gooch 0.2; ours 0.8)")
            .f("warm_mix", field_path(&P::hue, &RampColors::warm_mix), 0, 2, "Gooch β: object colour in the warm end (Gooch 0.6; ours 1.0)")
            .f("keep_hue", field_path(&P::hue, &RampColors::keep_hue), 0, 1,
               "how much a saturated colour keeps its hue: the cool/warm shift is weighted by 1 - keep_hue x saturation "
               "(0 = Gooch's shift on every colour; ours 1)");
        for (int k = 0; k < 4; ++k) {
            const std::string n = std::to_string(k), layer = "layer" + n;
            for (int c = 0; c < 3; ++c)
                t.f("color" + n + "_" + rgb[c], field_path(&P::layer, k, &ColorRampLayer::color, c), 0, 1,
                    layer + " object ramp, lit end (" + rgb[c] + "; display value)");
            for (int c = 0; c < 3; ++c)
                t.f("dark" + n + "_" + rgb[c], field_path(&P::layer, k, &ColorRampLayer::dark, c), 0, 1,
                    layer + " object ramp, unlit end (" + rgb[c] + "; ours: 0.55 x colour)");
            t.f("alpha" + n, field_path(&P::layer, k, &ColorRampLayer::alpha), 0, 1,
                layer + " ramp alpha: the wash's opacity (ours: 0.85)");
            t.f("tone" + n, field_path(&P::layer, k, &ColorRampLayer::tone), 0, 4,
                layer + " factor on its object ramp (particle layers: darker / brighter tones)");
        }
        return t;
    }();
    return t;
}
}  // namespace

ColorRampParams color_ramp_params(const ParamValues& pv) { return table().from(pv); }

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
    r.add(declare({.stage = "color_ramp",
                   .variant = "gooch",
                   .doc = "LD06 §3.2: hue-shifting ramp (Gooch cool-to-warm) with per-layer object ramps and alpha, indexed by "
                          "the lighting map; RGBA per layer",
                   .inputs = {{"lighting", "ld06.lighting", 1, false}},
                   .outputs = {{"ramp0", "ld06.ramp.0", 4, false},
                               {"ramp1", "ld06.ramp.1", 4, false},
                               {"ramp2", "ld06.ramp.2", 4, false},
                               {"ramp3", "ld06.ramp.3", 4, false}},
                   .reference = StageVariant::Reference::SharedMaths,
                   .scene_params = layer_colors},
                  table(), [](StageIO& io, const P& p, const Exec& ex) {
                      ImageF* const out[4] = {io.out[0], io.out[1], io.out[2], io.out[3]};
                      color_ramp(out, *io.in[0], p, ex);
                  }));
}

}  // namespace aq::stylize
