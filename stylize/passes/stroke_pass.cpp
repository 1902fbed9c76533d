// stylize/passes/stroke_pass.cpp — pass "strokes": LD06 §4.4, the scene's hand-made strokes then the
// automatic contours of trunks and branches, drawn in order with f_v as transparency and the
// distance, n·v and (hatching) n·l fades. Variants are the depth tests.
#include "stylize/passes/stroke_pass.h"

#include "raster/strokes.h"
#include "stylize/passes/pass_common.h"

namespace aq::stylize {

namespace {
//! The pass's parameters: the strokes', and whether the automatic contours are drawn.
struct StrokePass : raster::StrokeParams {
    bool contours = true;
};
}  // namespace

void register_stroke_pass(Registry& r) {
    using P = StrokePass;
    const ParamTable<P> t = ParamTable<P>()
        .f("width", &P::width_px, 0.1, 64, "line width in pixels at 720 px (ours: 2)")
        .f("scale", &P::scale, passes::kMinScale, passes::kMaxScale, passes::kScaleDoc)
        .f("delta", &P::delta, 0, 1, "δ of eq. 2 (ours: 0.02)")
        .f("beta", &P::beta, -1, 1, "β of eq. 2 (ours: 0.02 = δ, strokes stay on their surface)")
        .f("fade_near", &P::fade_near, 0, 1, "distance fade starts at this normalised depth (ours)")
        .f("fade_far", &P::fade_far, 0, 1, "... and is complete here (ours)")
        .f("nv_lo", &P::nv_lo, 0, 1, "n.v fade: invisible at |n.v| <= nv_lo (ours)")
        .f("nv_hi", &P::nv_hi, 0, 1, "n.v fade: fully visible at |n.v| >= nv_hi (ours)")
        .f("nl_lo", &P::nl_lo, -1, 1, "hatching strokes: fully visible at n.l <= nl_lo (ours)")
        .f("nl_hi", &P::nl_hi, -1, 1, "hatching strokes: invisible at n.l >= nl_hi (ours)")
        .f("alpha", &P::alpha, 0, 1, "stroke opacity")
        .b("contours", &P::contours, "draw the automatic contours of non-foliage meshes (trunk, branches)");
    for (const passes::DepthTestVariant& tv : passes::kDepthTests) {
        r.add(declare(
            {.stage = "strokes",
             .variant = tv.name,
             .doc = std::string("LD06 §4.4: line strokes (scene strokes, then trunk contours) over each other in order, "
                                "f_v as transparency, distance / n.v / n.l fades; ") + tv.doc,
             // Blurred tests: the blurred depth map (LD06 §2); binary: the depth map itself.
             .inputs = {{"depth_map", tv.test == raster::DepthTest::Binary ? "ld06.depth" : "ld06.depth.blurred", 1, false}},
             .outputs = {{"strokes", "ld06.strokes", 1, false}},
             .reference = StageVariant::Reference::SharedMaths},
            t, [test = tv.test](StageIO& io, const P& pp, const Exec& ex) {
                const raster::PassScene& ps = passes::scene_of(io);
                raster::StrokeParams p = pp;
                p.test = test;
                p.depth_map = io.in[0];
                std::vector<raster::Stroke> contours;
                if (pp.contours) contours = raster::contour_strokes(ps, ex);
                const std::vector<raster::Stroke> none;
                const std::vector<raster::Stroke>* lists[2] = {ps.strokes ? ps.strokes : &none, &contours};
                std::size_t dropped = 0;
                raster::render_strokes(*io.out[0], ps, lists, p, ex, &dropped);
                if (std::vector<std::string>* w = passes::warnings_of(io); dropped && w)
                    w->push_back("strokes: " + std::to_string(dropped) + " segment(s) with non-finite points dropped");
            }));
    }
}

}  // namespace aq::stylize
