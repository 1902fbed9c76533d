// stylize/passes/stroke_pass.cpp — pass "strokes": LD06 §4.4, the scene's hand-made strokes then the
// automatic contours of trunks and branches, drawn in order with f_v as transparency and the
// distance, n·v and (hatching) n·l fades. Variants are the depth tests.
#include "stylize/passes/stroke_pass.h"

#include "raster/strokes.h"
#include "stylize/passes/pass_common.h"

namespace aq::stylize {

namespace {

struct Table {
    float width = 2.0f, scale = 1.0f, delta = 0.02f, beta = 0.02f;
    float fade_near = 0.6f, fade_far = 1.0f, nv_lo = 0.05f, nv_hi = 0.3f, nl_lo = -0.2f, nl_hi = 0.4f, alpha = 1.0f;
    bool contours = true;
};

}  // namespace

void register_stroke_pass(Registry& r) {
    static const ParamTable<Table> t = ParamTable<Table>()
        .f("width", &Table::width, 0.1, 64, "line width in pixels at 720 px (ours: 2)")
        .f("scale", &Table::scale, passes::kMinScale, passes::kMaxScale, passes::kScaleDoc)
        .f("delta", &Table::delta, 0, 1, "δ of eq. 2 (ours: 0.02)")
        .f("beta", &Table::beta, -1, 1, "β of eq. 2 (ours: 0.02 = δ, strokes stay on their surface)")
        .f("fade_near", &Table::fade_near, 0, 1, "distance fade starts at this normalised depth (ours)")
        .f("fade_far", &Table::fade_far, 0, 1, "... and is complete here (ours)")
        .f("nv_lo", &Table::nv_lo, 0, 1, "n.v fade: invisible at |n.v| <= nv_lo (ours)")
        .f("nv_hi", &Table::nv_hi, 0, 1, "n.v fade: fully visible at |n.v| >= nv_hi (ours)")
        .f("nl_lo", &Table::nl_lo, -1, 1, "hatching strokes: fully visible at n.l <= nl_lo (ours)")
        .f("nl_hi", &Table::nl_hi, -1, 1, "hatching strokes: invisible at n.l >= nl_hi (ours)")
        .f("alpha", &Table::alpha, 0, 1, "stroke opacity")
        .b("contours", &Table::contours, "draw the automatic contours of non-foliage meshes (trunk, branches)");
    for (const passes::DepthTestVariant& tv : passes::kDepthTests) {
        StageVariant v;
        v.stage = "strokes";
        v.variant = tv.name;
        v.doc = std::string("LD06 §4.4: line strokes (scene strokes, then trunk contours) over each other in order, "
                            "f_v as transparency, distance / n.v / n.l fades; ") + tv.doc;
        // Blurred tests: the blurred depth map (LD06 §2); binary: the depth map itself.
        v.inputs = {{"depth_map", tv.test == raster::DepthTest::Binary ? "ld06.depth" : "ld06.depth.blurred", 1, false}};
        v.outputs = {{"strokes", "ld06.strokes", 1, false}};
        v.params = t.descs();
        v.run = [test = tv.test](StageIO& io, const ParamValues& pv, const Exec& ex) {
            const raster::PassScene& ps = passes::scene_of(io);
            const auto tp = t.from(pv);
            raster::StrokeParams p;
            p.width_px = tp.width;
            p.scale = tp.scale;
            p.test = test;
            p.delta = tp.delta;
            p.beta = tp.beta;
            p.fade_near = tp.fade_near;
            p.fade_far = tp.fade_far;
            p.nv_lo = tp.nv_lo;
            p.nv_hi = tp.nv_hi;
            p.nl_lo = tp.nl_lo;
            p.nl_hi = tp.nl_hi;
            p.alpha = tp.alpha;
            p.depth_map = io.in[0];
            std::vector<raster::Stroke> contours;
            if (tp.contours) contours = raster::contour_strokes(ps, ex);
            const std::vector<raster::Stroke> none;
            const std::vector<raster::Stroke>* lists[2] = {ps.strokes ? ps.strokes : &none, &contours};
            std::size_t dropped = 0;
            raster::render_strokes(*io.out[0], ps, lists, p, ex, &dropped);
            if (std::vector<std::string>* w = passes::warnings_of(io); dropped && w)
                w->push_back("strokes: " + std::to_string(dropped) +
                                                " segment(s) with non-finite points dropped");
        };
        v.reference = StageVariant::Reference::SharedMaths;
        r.add(std::move(v));
    }
}

}  // namespace aq::stylize
