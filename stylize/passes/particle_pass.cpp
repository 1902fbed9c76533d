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
//! The pass's parameters: the particles', and whether this is the crown map.
struct ParticlePass : raster::ParticleParams {
    int crown = 0;
};
}  // namespace

void register_particle_pass(Registry& r) {
    using P = ParticlePass;
    const ParamTable<P> t = ParamTable<P>()
        .f("quantity", &P::quantity, 0, 10000, "ω_quantity of eq. 8: N = quantity x height² (LD06: 30)")
        .f("spread", &P::spread, 0, 10, "ω_spread of eq. 9: offset spread x sqrt(height), in height units (LD06: 0.07)")
        .f("height", &P::height, 0.01, 10000,
           "h of eq. 8-9: the plant's height in the equations' units (23.8 = the paper's Fig. 8 tree, whatever the model's units)")
        .i("seed", &P::seed, 0, 1000000, "seed of the particle placement (eq. 9's random directions)")
        .f("t0", &P::t0, -1, 1, "eq. 11 dark/medium threshold on n.l (LD06: -0.5)")
        .f("t1", &P::t1, -1, 1, "eq. 11 medium/bright threshold on n.l (LD06: 0.1)")
        .f("size_scale", &P::size_scale, 0, 1000, "ω_scale of eq. 10, pixels at 720 px (LD06: 200; ours 20, docs/ld06.md)")
        .f("size_bias", &P::size_bias, 0, 200, "ω_bias of eq. 10, pixels at 720 px (LD06: 5; ours 4)")
        .e("shape", &P::shape, {"round", "square"}, "round blotch or square sprite")
        .f("scale", &P::scale, passes::kMinScale, passes::kMaxScale, passes::kScaleDoc)
        .f("delta", &P::delta, 0, 1, "δ of eq. 2 (ours: 0.05; unused by binary)")
        .f("beta", &P::beta, -1, 1, "β of eq. 2 (LD06: β = δ)")
        .i("crown", &P::crown, 0, 1,
           "1 = the crown map: every particle into `bright` (dark and medium stay empty); under the texture technique the "
           "leaves' coverage (docs/ld06.md \"Leafy outlines\")");
    for (const passes::DepthTestVariant& tv : passes::kDepthTests) {
        r.add(declare(
            {.stage = "particles",
             .variant = tv.name,
             .doc = std::string("LD06 §4.2 eq. 8-12: particles around the implicit foliage surface, classed by n.l, additive "
                                "sprites into dark / medium / bright maps; ") + tv.doc,
             // The blurred tests read the blurred depth map (LD06 §2); the binary one, the standard
             // depth test, reads the depth map itself (the paper's Fig. 9 comparison).
             .inputs = {{"depth_map", tv.test == raster::DepthTest::Binary ? "ld06.depth" : "ld06.depth.blurred", 1, false}},
             .outputs = {{"dark", "ld06.particles.dark", 1, false},
                         {"medium", "ld06.particles.medium", 1, false},
                         {"bright", "ld06.particles.bright", 1, false}},
             .reference = StageVariant::Reference::SharedMaths},
            t, [test = tv.test](StageIO& io, const P& pp, const Exec& ex) {
                const raster::PassScene& ps = passes::scene_of(io);
                raster::ParticleParams p = pp;
                p.test = test;
                p.depth_map = io.in[0];
                if (!ps.foliage_surface && ps.foliage_detail) {
                    // LD06 §4.3 instead of §4.2 (raster/foliage.h technique texture): the three maps are
                    // the foliage's intensity-texture detail, dark (R), medium (G), bright (B); the crown
                    // map is the leaves' coverage.
                    raster::TrianglePass tp3;
                    tp3.draw = raster::DrawSet::Foliage;
                    tp3.scale = p.scale;
                    tp3.value = pp.crown ? raster::PassValue::Coverage : raster::PassValue::IntensityTexture;
                    for (int c = 0; c < 3; ++c) {
                        tp3.channel = c;
                        if (pp.crown && c < 2) {  // empty dark and medium maps of the pass's size
                            const raster::PassViewSetup vs = raster::pass_view(ps, raster::PassView::Camera, p.scale);
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
                    if (pp.crown)
                        for (raster::Particle& q : particles) q.cls = 2;  // one class: the crown map
                } else if (std::vector<std::string>* w = passes::warnings_of(io)) {
                    w->push_back("particles: no implicit foliage surface (no foliage, or the style has no "
                                 "\"foliage\" block): the particle maps are empty (docs/ld06.md \"Particles\")");
                }
                raster::render_particles(*io.out[0], *io.out[1], *io.out[2], ps, particles, p, ex);
            },
            [](const P& p) { raster::check_particle_params(p); }));
    }
}

}  // namespace aq::stylize
