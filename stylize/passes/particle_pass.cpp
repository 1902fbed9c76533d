// stylize/passes/particle_pass.cpp — pass "particles": LD06 §4.2 eq. 8-12, one pass writing the
// dark, medium and bright intensity maps. Variants are the depth tests (blurred first: the
// default; binary for the paper's Fig. 9 comparison).
#include "stylize/passes/particle_pass.h"

#include <algorithm>

#include "raster/pass.h"
#include "raster/particles.h"
#include "stylize/passes/pass_common.h"

namespace aq::stylize {

namespace {

struct Table {
    float quantity = raster::kLd06Quantity, spread = raster::kLd06Spread, height = raster::kLd06TreeHeight;
    int seed = 1;
    float t0 = raster::kLd06T0, t1 = raster::kLd06T1;
    float size_scale = raster::kParticleSizeScale, size_bias = raster::kParticleSizeBias;
    int shape = 0;
    float scale = 1.0f;
    float delta = 0.05f, beta = 0.05f;
    int crown = 0;
};

}  // namespace

void register_particle_pass(Registry& r) {
    static const ParamTable<Table> t = ParamTable<Table>()
        .f("quantity", &Table::quantity, 0, 10000, "ω_quantity of eq. 8: N = quantity x height² (LD06: 30)")
        .f("spread", &Table::spread, 0, 10, "ω_spread of eq. 9: offset spread x sqrt(height), in height units (LD06: 0.07)")
        .f("height", &Table::height, 0.01, 10000,
           "h of eq. 8-9: the plant's height in the equations' units (23.8 = the paper's Fig. 8 tree, whatever the model's units)")
        .i("seed", &Table::seed, 0, 1000000, "seed of the particle placement (eq. 9's random directions)")
        .f("t0", &Table::t0, -1, 1, "eq. 11 dark/medium threshold on n.l (LD06: -0.5)")
        .f("t1", &Table::t1, -1, 1, "eq. 11 medium/bright threshold on n.l (LD06: 0.1)")
        .f("size_scale", &Table::size_scale, 0, 1000, "ω_scale of eq. 10, pixels at 720 px (LD06: 200; ours 20, docs/ld06.md)")
        .f("size_bias", &Table::size_bias, 0, 200, "ω_bias of eq. 10, pixels at 720 px (LD06: 5; ours 4)")
        .e("shape", &Table::shape, {"round", "square"}, "round blotch or square sprite")
        .f("scale", &Table::scale, passes::kMinScale, passes::kMaxScale, passes::kScaleDoc)
        .f("delta", &Table::delta, 0, 1, "δ of eq. 2 (ours: 0.05; unused by binary)")
        .f("beta", &Table::beta, -1, 1, "β of eq. 2 (LD06: β = δ)")
        .i("crown", &Table::crown, 0, 1,
           "1 = the crown map: every particle into `bright` (dark and medium stay empty); under the texture technique the "
           "leaves' coverage (docs/ld06.md \"Leafy outlines\")");
    for (const passes::DepthTestVariant& tv : passes::kDepthTests) {
        StageVariant v;
        v.stage = "particles";
        v.variant = tv.name;
        v.doc = std::string("LD06 §4.2 eq. 8-12: particles around the implicit foliage surface, classed by n.l, additive "
                            "sprites into dark / medium / bright maps; ") + tv.doc;
        // The blurred tests read the blurred depth map (LD06 §2); the binary one, the standard
        // depth test, reads the depth map itself (the paper's Fig. 9 comparison).
        v.inputs = {{"depth_map", tv.test == raster::DepthTest::Binary ? "ld06.depth" : "ld06.depth.blurred", 1, false}};
        v.outputs = {{"dark", "ld06.particles.dark", 1, false},
                     {"medium", "ld06.particles.medium", 1, false},
                     {"bright", "ld06.particles.bright", 1, false}};
        v.params = t.descs();
        v.run = [test = tv.test](StageIO& io, const ParamValues& pv, const Exec& ex) {
            const raster::PassScene& ps = passes::scene_of(io);
            const auto tp = t.from(pv);
            raster::ParticleParams p;
            p.quantity = tp.quantity;
            p.spread = tp.spread;
            p.height = tp.height;
            p.seed = std::uint32_t(tp.seed);
            p.t0 = tp.t0;
            p.t1 = tp.t1;
            p.size_scale = tp.size_scale;
            p.size_bias = tp.size_bias;
            p.shape = tp.shape;
            p.scale = tp.scale;
            p.test = test;
            p.delta = tp.delta;
            p.beta = tp.beta;
            p.depth_map = io.in[0];
            if (!ps.foliage_surface && ps.foliage_detail) {
                // LD06 §4.3 instead of §4.2 (raster/foliage.h technique texture): the three maps are
                // the foliage's intensity-texture detail, dark (R), medium (G), bright (B); the crown
                // map is the leaves' coverage.
                raster::TrianglePass tp3;
                tp3.draw = raster::DrawSet::Foliage;
                tp3.scale = tp.scale;
                tp3.value = tp.crown ? raster::PassValue::Coverage : raster::PassValue::IntensityTexture;
                for (int c = 0; c < 3; ++c) {
                    tp3.channel = c;
                    if (tp.crown && c < 2) {  // empty dark and medium maps of the pass's size
                        const raster::PassViewSetup vs = raster::pass_view(ps, raster::PassView::Camera, tp.scale);
                        ImageF& out = *io.out[std::size_t(c)];  // reused frame to frame
                        ensure_output(out, vs.width, vs.height, 1);
                        std::fill(out.data(), out.data() + out.num_values(), 0.0f);
                        continue;
                    }
                    raster::render_triangle_pass(*io.out[std::size_t(c)], ps, tp3, ex, passes::warnings_of(io));
                }
                return;
            }
            std::vector<raster::Particle> particles;
            if (ps.foliage_surface) {
                particles = raster::place_particles(*ps.foliage_surface, ps.plant_height, ps.light_dir, p);
                if (tp.crown)
                    for (raster::Particle& q : particles) q.cls = 2;  // one class: the crown map
            } else if (std::vector<std::string>* w = passes::warnings_of(io)) {
                w->push_back("particles: no implicit foliage surface (no foliage, or the style has no "
                                                "\"foliage\" block): the particle maps are empty (docs/ld06.md \"Particles\")");
            }
            raster::render_particles(*io.out[0], *io.out[1], *io.out[2], ps, particles, p, ex);
        };
        v.reference = StageVariant::Reference::SharedMaths;
        r.add(std::move(v));
    }
}

}  // namespace aq::stylize
