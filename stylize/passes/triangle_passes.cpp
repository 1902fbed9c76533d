// stylize/passes/triangle_passes.cpp — registry entries of the triangle raster passes: each adapts
// its parameter table to raster::TrianglePass and calls raster::render_triangle_pass (the maths
// and both traversals live there). LD06 = Luft & Deussen 2006; values marked "ours" are the
// project's (docs/ld06.md "Parameters").
#include "stylize/passes/triangle_passes.h"

#include "stylize/passes/pass_common.h"

namespace aq::stylize {

namespace {

using raster::DepthTest;
using raster::PassValue;
using raster::TrianglePass;
using namespace passes;

using P = TrianglePass;

//! The pass declared by `v` drawing `value` with the parameters `t` (bound to TrianglePass).
template <class Params = P>
StageVariant triangle_pass(StageVariant v, ParamTable<Params> t, PassValue value, DepthTest test = DepthTest::Binary) {
    return declare(std::move(v), std::move(t), [value, test](StageIO& io, const Params& params, const Exec& ex) {
        TrianglePass p = params;
        p.value = value;
        p.test = test;
        if (test != DepthTest::Binary) p.depth_map = io.in[0];
        raster::render_triangle_pass(*io.out[0], scene_of(io), p, ex, warnings_of(io));
    });
}

//! What to draw and at which size: every camera pass's parameters.
ParamTable<P> draw_scale() {
    return ParamTable<P>().e("draw", &P::draw, {"all", "foliage", "not_foliage"}, kDrawDoc).f("scale", &P::scale, kMinScale, kMaxScale, kScaleDoc);
}

//! The intensity passes' defaults: β = δ keeps near objects visible (LD06 §2; ours).
struct IntensityPass : TrianglePass {
    IntensityPass() { beta = raster::kPassDelta; }
};

}  // namespace

void register_triangle_passes(Registry& r) {
    r.add(triangle_pass({.stage = "depth",
                         .variant = "linear",
                         .doc = "LD06 §2: linear depth, 0 at the near and 1 at the far end of the scene's depth range in this view "
                                "(background 1); binary depth test",
                         .outputs = {{"depth", "ld06.depth", 1, false}},
                         .reference = StageVariant::Reference::SharedMaths},
                        ParamTable<P>()
                            .e("view", &P::view, {"camera", "light"}, kViewDoc)
                            .e("draw", &P::draw, {"all", "foliage", "not_foliage"}, kDrawDoc)
                            .f("scale", &P::scale, kMinScale, kMaxScale, kScaleDoc),
                        PassValue::Depth));
    r.add(triangle_pass({.stage = "lighting",
                         .variant = "gooch",
                         .doc = "LD06 §3.2: lighting map (1 + n.l) / 2 (Gooch's t; two-sided) of the front-most surface, background 0",
                         .outputs = {{"lighting", "ld06.lighting", 1, false}},
                         .reference = StageVariant::Reference::SharedMaths},
                        draw_scale().f("background", &P::lighting_background, 0, 1,
                                       "value where nothing is drawn (0; the ld06 preset uses 0.5, so particles beyond the "
                                       "surface's silhouette take a middle tone)"),
                        PassValue::Lighting));
    // The shadow pass: blurred is its default (LD06 §3.3), so it is registered first. Its depth
    // test is that of the light-view map it reads (the camera's depth is not read).
    for (const DepthTestVariant& tv : kDepthTests) {
        r.add(declare({.stage = "shadow",
                       .variant = tv.name,
                       .doc = std::string("LD06 §3.3 eq. 5: shadow intensity 1 - f_s of the front-most surface against the "
                                          "light-view depth map; ") + tv.doc,
                       .inputs = {{"shadow_map", "ld06.light_depth.blurred", 1, false}},
                       .outputs = {{"shadow", "ld06.shadow", 1, false}},
                       .reference = StageVariant::Reference::SharedMaths},
                      draw_scale()
                          .f("delta", &P::shadow_delta, 0, 1, "δ of LD06 eq. 5: shadow softness (ours; unused by binary)")
                          .f("beta", &P::shadow_beta, -1, 1, "β of LD06 eq. 5: shift against self-shadowing (ours)"),
                      [test = tv.test](StageIO& io, P p, const Exec& ex) {
                          p.value = PassValue::Shadow;
                          p.shadow_map = io.in[0];
                          p.shadow_test = test;
                          raster::render_triangle_pass(*io.out[0], scene_of(io), p, ex, warnings_of(io));
                      }));
    }
    // The intensity masks of §3.1 use the binary test by default: registered first.
    for (int k : {2, 0, 1}) {
        const DepthTestVariant& tv = kDepthTests[k];
        using I = IntensityPass;
        StageVariant v = {.stage = "intensity",
                          .variant = tv.name,
                          .doc = std::string("LD06 §3.1: intensity mask (coverage 1 weighted by f_v) of the drawn geometry; ") + tv.doc,
                          .outputs = {{"intensity", "ld06.intensity", 1, false}},
                          .reference = StageVariant::Reference::SharedMaths};
        if (tv.test != DepthTest::Binary) v.inputs = {{"depth_map", "ld06.depth.blurred", 1, false}};
        r.add(triangle_pass(std::move(v),
                            ParamTable<I>()
                                .e("view", &I::view, {"camera", "light"}, kViewDoc)
                                .e("draw", &I::draw, {"all", "foliage", "not_foliage"}, kDrawDoc)
                                .f("scale", &I::scale, kMinScale, kMaxScale, kScaleDoc)
                                .f("delta", &I::delta, 0, 1, "δ of LD06 eq. 2 (blurred tests; ours)")
                                .f("beta", &I::beta, -1, 1, "β of LD06 eq. 2 (blurred tests; β = δ keeps near objects visible)")
                                .e("blend", &I::blend, {"replace", "add", "over"}, "replace, add with clamp (LD06 eq. 12), or alpha over")
                                .f("alpha", &I::alpha, 0, 1, "fragment alpha for blend 2 (times f_v)"),
                            PassValue::Coverage, tv.test));
    }
    r.add(declare({.stage = "intensity_texture",
                   .variant = "rgb",
                   .doc = "LD06 §4.3: the R, G, B detail maps of the materials' intensity textures (TEXCOORD_0) on the "
                          "front-most surface (binary depth test; materials without one write 0 and occlude)",
                   .outputs = {{"r", "ld06.detail.r", 1, false}, {"g", "ld06.detail.g", 1, false}, {"b", "ld06.detail.b", 1, false}},
                   .reference = StageVariant::Reference::SharedMaths},
                  draw_scale(), [](StageIO& io, P p, const Exec& ex) {
                      p.value = PassValue::IntensityTexture;
                      for (int c = 0; c < 3; ++c) {
                          p.channel = c;
                          raster::render_triangle_pass(*io.out[std::size_t(c)], scene_of(io), p, ex, warnings_of(io));
                      }
                  }));
    // LD06 §3.1 ID image: the layer (default) or the object of the front-most surface.
    for (bool layer : {true, false}) {
        r.add(triangle_pass({.stage = "layer_id",
                             .variant = layer ? "layer" : "object",
                             .doc = layer ? "LD06 §3.1: 1 + the layer (scene file \"layers\", else one per material; docs/ld06.md "
                                            "\"Layers\") of the front-most surface, background 0; binary depth test"
                                          : "LD06 §3.1: the object ID (instance) of the front-most surface, background 0; binary depth test",
                             .outputs = {{"ids", "ld06.layer_id", 1, false}},
                             .reference = StageVariant::Reference::SharedMaths},
                            draw_scale().b("foliage", &P::foliage_layer,
                                           "on: foliage writes its layer; off: foliage (the implicit surface, or the modelled leaves "
                                           "under the texture technique) occludes but writes the background: the particle pass's "
                                           "crown map paints it (docs/ld06.md \"Leafy outlines\")"),
                            layer ? PassValue::LayerId : PassValue::ObjectId));
    }
}

}  // namespace aq::stylize
