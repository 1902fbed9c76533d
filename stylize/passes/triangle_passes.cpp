// stylize/passes/triangle_passes.cpp — registry entries of the triangle raster passes: each adapts
// its parameter table to raster::TrianglePass and calls raster::render_triangle_pass (the maths
// and both traversals live there). LD06 = Luft & Deussen 2006; values marked "ours" are the
// project's (docs/ld06.md "Parameters").
#include "stylize/passes/triangle_passes.h"

#include "stylize/passes/pass_common.h"

namespace aq::stylize {

namespace {

using raster::Blend;
using raster::DepthTest;
using raster::DrawSet;
using raster::PassValue;
using raster::PassView;
using raster::TrianglePass;
using namespace passes;

// Ours: LD06 gives no values for δ and β. δ = 0.05 of the fitted depth range keeps the band of
// semi-visible fragments narrow; β = δ keeps an object just in front fully visible (LD06 §2).
constexpr float kDefaultDelta = 0.05f;
// Ours: LD06 §3.3 gives no values. A lit surface tested against its own (blurred) light depth
// has D - f_d near 0, so it is fully lit only when β >= δ; β a little above δ absorbs the blur of
// foliage depth (on the dense oak, β = 0.01 left most lit leaves in shadow; 0.05 does not).
constexpr float kDefaultShadowDelta = 0.04f;
constexpr float kDefaultShadowBeta = 0.05f;

void run(StageIO& io, const TrianglePass& p, const Exec& ex) {
    raster::render_triangle_pass(*io.out[0], scene_of(io), p, ex, warnings_of(io));
}

struct DepthTable {
    int view = 0, draw = 0;
    float scale = 1.0f;
};
struct LightingTable {
    int draw = 0;
    float scale = 1.0f;
};
//! The parameters of the camera passes that only choose what to draw and at which size.
const ParamTable<LightingTable>& draw_scale_table() {
    static const ParamTable<LightingTable> t = ParamTable<LightingTable>()
        .e("draw", &LightingTable::draw, {"all", "foliage", "not_foliage"}, kDrawDoc)
        .f("scale", &LightingTable::scale, kMinScale, kMaxScale, kScaleDoc);
    return t;
}

struct LayerIdTable {
    int draw = 0;
    float scale = 1.0f;
    int foliage = 1;
};

struct ShadowTable {
    int draw = 0;
    float scale = 1.0f;
    float delta = kDefaultShadowDelta, beta = kDefaultShadowBeta;
};
struct IntensityTable {
    int view = 0, draw = 0;
    float scale = 1.0f;
    float delta = kDefaultDelta, beta = kDefaultDelta;
    int blend = 0;
    float alpha = 1.0f;
};


}  // namespace

void register_triangle_passes(Registry& r) {
    {
        static const ParamTable<DepthTable> t = ParamTable<DepthTable>()
            .e("view", &DepthTable::view, {"camera", "light"}, kViewDoc)
            .e("draw", &DepthTable::draw, {"all", "foliage", "not_foliage"}, kDrawDoc)
            .f("scale", &DepthTable::scale, kMinScale, kMaxScale, kScaleDoc);
        StageVariant v;
        v.stage = "depth";
        v.variant = "linear";
        v.doc = "LD06 §2: linear depth, 0 at the near and 1 at the far end of the scene's depth range in this view "
                "(background 1); binary depth test";
        v.outputs = {{"depth", "ld06.depth", 1, false}};
        v.params = t.descs();
        v.run = [](StageIO& io, const ParamValues& pv, const Exec& ex) {
            const auto tp = t.from(pv);
            TrianglePass p;
            p.view = PassView(tp.view);
            p.draw = DrawSet(tp.draw);
            p.scale = tp.scale;
            p.value = PassValue::Depth;
            run(io, p, ex);
        };
        v.reference = StageVariant::Reference::SharedMaths;
        r.add(std::move(v));
    }
    {
        struct Table {
            int draw = 0;
            float scale = 1.0f, background = 0.0f;
        };
        static const ParamTable<Table> t = ParamTable<Table>()
            .e("draw", &Table::draw, {"all", "foliage", "not_foliage"}, kDrawDoc)
            .f("scale", &Table::scale, kMinScale, kMaxScale, kScaleDoc)
            .f("background", &Table::background, 0, 1,
               "value where nothing is drawn (0; the ld06 preset uses 0.5, so particles beyond the surface's silhouette take a middle tone)");
        StageVariant v;
        v.stage = "lighting";
        v.variant = "gooch";
        v.doc = "LD06 §3.2: lighting map (1 + n.l) / 2 (Gooch's t; two-sided) of the front-most surface, background 0";
        v.outputs = {{"lighting", "ld06.lighting", 1, false}};
        v.params = t.descs();
        v.run = [](StageIO& io, const ParamValues& pv, const Exec& ex) {
            const auto tp = t.from(pv);
            TrianglePass p;
            p.draw = DrawSet(tp.draw);
            p.scale = tp.scale;
            p.value = PassValue::Lighting;
            p.lighting_background = tp.background;
            run(io, p, ex);
        };
        v.reference = StageVariant::Reference::SharedMaths;
        r.add(std::move(v));
    }
    // The shadow pass: blurred is its default (LD06 §3.3), so it is registered first.
    for (const DepthTestVariant& tv : kDepthTests) {
        static const ParamTable<ShadowTable> t = ParamTable<ShadowTable>()
            .e("draw", &ShadowTable::draw, {"all", "foliage", "not_foliage"}, kDrawDoc)
            .f("scale", &ShadowTable::scale, kMinScale, kMaxScale, kScaleDoc)
            .f("delta", &ShadowTable::delta, 0, 1, "δ of LD06 eq. 5: shadow softness (ours; unused by binary)")
            .f("beta", &ShadowTable::beta, -1, 1, "β of LD06 eq. 5: shift against self-shadowing (ours)");
        StageVariant v;
        v.stage = "shadow";
        v.variant = tv.name;
        v.doc = std::string("LD06 §3.3 eq. 5: shadow intensity 1 - f_s of the front-most surface against the "
                            "light-view depth map; ") + tv.doc;
        v.inputs = {{"shadow_map", "ld06.light_depth.blurred", 1, false}};
        v.outputs = {{"shadow", "ld06.shadow", 1, false}};
        v.params = t.descs();
        v.run = [test = tv.test](StageIO& io, const ParamValues& pv, const Exec& ex) {
            const auto tp = t.from(pv);
            TrianglePass p;
            p.draw = DrawSet(tp.draw);
            p.scale = tp.scale;
            p.value = PassValue::Shadow;
            p.shadow_map = io.in[0];
            p.shadow_test = test;
            p.shadow_delta = tp.delta;
            p.shadow_beta = tp.beta;
            run(io, p, ex);
        };
        v.reference = StageVariant::Reference::SharedMaths;
        r.add(std::move(v));
    }
    // The intensity masks of §3.1 use the binary test by default: registered first.
    for (int k : {2, 0, 1}) {
        const DepthTestVariant& tv = kDepthTests[k];
        static const ParamTable<IntensityTable> t = ParamTable<IntensityTable>()
            .e("view", &IntensityTable::view, {"camera", "light"}, kViewDoc)
            .e("draw", &IntensityTable::draw, {"all", "foliage", "not_foliage"}, kDrawDoc)
            .f("scale", &IntensityTable::scale, kMinScale, kMaxScale, kScaleDoc)
            .f("delta", &IntensityTable::delta, 0, 1, "δ of LD06 eq. 2 (blurred tests; ours)")
            .f("beta", &IntensityTable::beta, -1, 1, "β of LD06 eq. 2 (blurred tests; β = δ keeps near objects visible)")
            .e("blend", &IntensityTable::blend, {"replace", "add", "over"}, "replace, add with clamp (LD06 eq. 12), or alpha over")
            .f("alpha", &IntensityTable::alpha, 0, 1, "fragment alpha for blend 2 (times f_v)");
        StageVariant v;
        v.stage = "intensity";
        v.variant = tv.name;
        v.doc = std::string("LD06 §3.1: intensity mask (coverage 1 weighted by f_v) of the drawn geometry; ") + tv.doc;
        if (tv.test != DepthTest::Binary) v.inputs = {{"depth_map", "ld06.depth.blurred", 1, false}};
        v.outputs = {{"intensity", "ld06.intensity", 1, false}};
        v.params = t.descs();
        v.run = [test = tv.test](StageIO& io, const ParamValues& pv, const Exec& ex) {
            const auto tp = t.from(pv);
            TrianglePass p;
            p.view = PassView(tp.view);
            p.draw = DrawSet(tp.draw);
            p.scale = tp.scale;
            p.value = PassValue::Coverage;
            p.test = test;
            p.delta = tp.delta;
            p.beta = tp.beta;
            p.blend = Blend(tp.blend);
            p.alpha = tp.alpha;
            if (test != DepthTest::Binary) p.depth_map = io.in[0];
            run(io, p, ex);
        };
        v.reference = StageVariant::Reference::SharedMaths;
        r.add(std::move(v));
    }
    {
        static const ParamTable<LightingTable>& t = draw_scale_table();
        StageVariant v;
        v.stage = "intensity_texture";
        v.variant = "rgb";
        v.doc = "LD06 §4.3: the R, G, B detail maps of the materials' intensity textures (TEXCOORD_0) on the "
                "front-most surface (binary depth test; materials without one write 0 and occlude)";
        v.outputs = {{"r", "ld06.detail.r", 1, false}, {"g", "ld06.detail.g", 1, false}, {"b", "ld06.detail.b", 1, false}};
        v.params = t.descs();
        v.run = [](StageIO& io, const ParamValues& pv, const Exec& ex) {
            const auto tp = t.from(pv);
            TrianglePass p;
            p.draw = DrawSet(tp.draw);
            p.scale = tp.scale;
            p.value = PassValue::IntensityTexture;
            for (int c = 0; c < 3; ++c) {
                p.channel = c;
                raster::render_triangle_pass(*io.out[std::size_t(c)], scene_of(io), p, ex, warnings_of(io));
            }
        };
        v.reference = StageVariant::Reference::SharedMaths;
        r.add(std::move(v));
    }
    // LD06 §3.1 ID image: the layer (default) or the object of the front-most surface.
    for (bool layer : {true, false}) {
        static const ParamTable<LayerIdTable> t = ParamTable<LayerIdTable>()
            .e("draw", &LayerIdTable::draw, {"all", "foliage", "not_foliage"}, kDrawDoc)
            .f("scale", &LayerIdTable::scale, kMinScale, kMaxScale, kScaleDoc)
            .i("foliage", &LayerIdTable::foliage, 0, 1,
               "1 = foliage writes its layer; 0 = foliage (the implicit surface, or the modelled leaves under the texture "
               "technique) occludes but writes the background: the particle pass's crown map paints it (docs/ld06.md \"Leafy outlines\")");
        StageVariant v;
        v.stage = "layer_id";
        v.variant = layer ? "layer" : "object";
        v.doc = layer ? "LD06 §3.1: 1 + the layer (scene file \"layers\", else one per material; docs/ld06.md \"Layers\") of the "
                        "front-most surface, background 0; binary depth test"
                      : "LD06 §3.1: the object ID (instance) of the front-most surface, background 0; binary depth test";
        v.outputs = {{"ids", "ld06.layer_id", 1, false}};
        v.params = t.descs();
        v.run = [layer](StageIO& io, const ParamValues& pv, const Exec& ex) {
            const auto tp = t.from(pv);
            TrianglePass p;
            p.draw = DrawSet(tp.draw);
            p.scale = tp.scale;
            p.value = layer ? PassValue::LayerId : PassValue::ObjectId;
            p.foliage_layer = tp.foliage != 0;
            run(io, p, ex);
        };
        v.reference = StageVariant::Reference::SharedMaths;
        r.add(std::move(v));
    }
}

}  // namespace aq::stylize
