// stylize/stages/glaze.cpp — see glaze.h: the checks, the reference (a plain loop sampling the
// ramp per pixel, sample_resampled_plane) and the declarations; the fast schedule (oneTBB row
// blocks resampling each ramp row once, the same values) is glaze.schedule.cpp.
#include "stylize/stages/glaze.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "stylize/stages/toolkit.h"
#include "stylize/stages/wash.h"

namespace aq::stylize {

using namespace toolkit;

namespace {

//! The checks, then the plain loop (images only: computed ramps' reference runs color_ramp
//! first) or the fast schedule.
void glaze_impl(ImageF& dst, const ImageF* base, const ImageF& wash, const GlazeRamps& src, glm::vec3 paper_color,
                bool multiplicative, const Exec& ex) {
    check_input(&wash, 4, Channels::Exactly, "glaze", "wash");
    check_not_alias(dst, &wash, "glaze", "wash");
    const ImageF* const* ramp = src.images;
    if (base) {
        check_input(base, 4, Channels::Exactly, "glaze", "color");
        check_same_size(*base, wash, "glaze", "color", "wash");
        check_not_alias(dst, base, "glaze", "color");
    }
    const int w = wash.width(), h = wash.height();
    ensure_output(dst, w, h, 4);
    if (ex.traversal == Traversal::Fast) {
        glaze_fast(dst, base, wash, src, paper_color, multiplicative, ex);
        return;
    }
    // The plain loop: images only (ComputedRamps' reference runs color_ramp first).
    Plane rp[16];
    if (ramp)
        for (int c = 0; c < 16; ++c) rp[c] = plane(*ramp[c / 4], c % 4);
    const float* wd = wash.data();
    const float* bd = base ? base->data() : nullptr;
    float* od = dst.data();
    plain_loop(w, h, [&](int x, int y) {
        auto sample = [&](const Plane& p) { return sample_resampled_plane(p, x, y, w, h); };
        const std::size_t i = std::size_t(y) * w + x;
        glm::vec3 c = bd ? glm::vec3(bd[i * 4], bd[i * 4 + 1], bd[i * 4 + 2]) : paper_color;
        for (int k = 0; k < 4; ++k) {
            const glm::vec3 col(sample(rp[4 * k]), sample(rp[4 * k + 1]), sample(rp[4 * k + 2]));
            const float a = sample(rp[4 * k + 3]);
            c = glaze_px(c, col, sat(a * wd[i * 4 + k]), multiplicative);
        }
        od[i * 4] = c.r, od[i * 4 + 1] = c.g, od[i * 4 + 2] = c.b, od[i * 4 + 3] = 1.0f;
    });
}

}  // namespace

void glaze(ImageF& dst, const ImageF* base, const ImageF& wash, const ComputedRamps& ramps, glm::vec3 paper_color,
           bool multiplicative, const Exec& ex) {
    check_input(ramps.lighting, 1, Channels::Exactly, "glaze", "lighting");
    check_not_alias(dst, ramps.lighting, "glaze", "lighting");
    // The row skips below rely on finite ramp parameters (the stage's ranges guarantee them); with
    // others the ramps are computed as images first.
    bool finite = std::isfinite(ramps.ramps.hue.cool_mix) && std::isfinite(ramps.ramps.hue.warm_mix) &&
                  std::isfinite(ramps.ramps.hue.keep_hue);
    for (int c = 0; c < 3; ++c) finite = finite && std::isfinite(ramps.ramps.hue.cool[c]) && std::isfinite(ramps.ramps.hue.warm[c]);
    for (const ColorRampLayer& l : ramps.ramps.layer) {
        finite = finite && std::isfinite(l.alpha) && std::isfinite(l.tone);
        for (int c = 0; c < 3; ++c) finite = finite && std::isfinite(l.color[c]) && std::isfinite(l.dark[c]);
    }
    if (ex.traversal == Traversal::Reference || !finite) {  // color_ramp, then glaze
        ImageF img[4];
        ImageF* const out[4] = {&img[0], &img[1], &img[2], &img[3]};
        color_ramp(out, *ramps.lighting, ramps.ramps, ex);
        const ImageF* const in[4] = {&img[0], &img[1], &img[2], &img[3]};
        glaze(dst, base, wash, in, paper_color, multiplicative, ex);
        return;
    }
    GlazeRamps s;
    s.computed = &ramps;
    glaze_impl(dst, base, wash, s, paper_color, multiplicative, ex);
}

void glaze(ImageF& dst, const ImageF* base, const ImageF& wash, const ImageF* const ramp[4], glm::vec3 paper_color,
           bool multiplicative, const Exec& ex) {
    static const char* kPorts[4] = {"ramp0", "ramp1", "ramp2", "ramp3"};
    for (int k = 0; k < 4; ++k) {
        check_input(ramp[k], 4, Channels::Exactly, "glaze", kPorts[k]);
        check_not_alias(dst, ramp[k], "glaze", kPorts[k]);
        if (k) check_same_size(*ramp[k], *ramp[0], "glaze", kPorts[k], "ramp0");
    }
    GlazeRamps s;
    s.images = ramp;
    glaze_impl(dst, base, wash, s, paper_color, multiplicative, ex);
}

void register_glaze(Registry& r) {
    for (bool mul : {true, false}) {
        r.add(declare(
            {.stage = "glaze",
             .variant = mul ? "multiplicative" : "over",
             .doc = mul ? "LD06 §4.2 glazing, subtractive-like: dst·(1 - k·(1 - c)) per layer, back to front, over the "
                          "picture or the paper colour"
                        : "LD06 §4.2 glazing as plain alpha blending: mix(dst, c, k) per layer, back to front",
             .inputs = {{"color", "color.ld06", 4, true, SizeRule::Same, "wash"},
                        {"wash", "ld06.wash", 4, false},
                        {"ramp0", "ld06.ramp.0", 4, false},
                        {"ramp1", "ld06.ramp.1", 4, false, SizeRule::Same, "ramp0"},
                        {"ramp2", "ld06.ramp.2", 4, false, SizeRule::Same, "ramp0"},
                        {"ramp3", "ld06.ramp.3", 4, false, SizeRule::Same, "ramp0"}},
             .outputs = {{"color", "color.glazed", 4, false}},
             .reference = StageVariant::Reference::PlainLoop},
            ParamTable<NoParams>(), [mul](StageIO& io, const NoParams&, const Exec& ex) {
                const ImageF* const ramp[4] = {io.in[2], io.in[3], io.in[4], io.in[5]};
                glaze(*io.out[0], io.in[0], *io.in[1], ramp, globals_of(io).substrate_color, mul, ex);
            }));
        // color_ramp -> glaze: the ramp rows computed where glaze reads them (ComputedRamps).
        Fusion f;
        f.producer = "color_ramp/gooch";
        f.consumer = "glaze/" + std::string(mul ? "multiplicative" : "over");
        f.links = {{"ramp0", "ramp0"}, {"ramp1", "ramp1"}, {"ramp2", "ramp2"}, {"ramp3", "ramp3"}};
        f.doc = "glaze computes the colour-ramp rows it reads from the lighting map (no ramp image; rows of skipped layers never computed)";
        f.run = [mul](const StageIO& producer, const ParamValues& pp, StageIO& io, const ParamValues&, const Exec& ex) {
            if (producer.in.size() != 1 || io.in.size() != 6 || io.out.size() != 1 || !io.out[0])
                throw Error("glaze (fused with color_ramp): unexpected ports");
            if (!io.in[1] || io.in[1]->empty()) throw Error("glaze: required input 'wash' is missing or empty");
            ComputedRamps ramps;
            ramps.lighting = producer.in[0];
            ramps.ramps = color_ramp_params(pp);
            glaze(*io.out[0], io.in[0], *io.in[1], ramps, globals_of(io).substrate_color, mul, ex);
        };
        r.add_fusion(std::move(f));
    }
}

}  // namespace aq::stylize
