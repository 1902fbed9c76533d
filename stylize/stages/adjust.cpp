// stylize/stages/adjust.cpp — spec §4.1 "Adjust / load" (MNPR quadAdjustLoad.ogsfx adjustLoadFrag).
// Pointwise: one kernel over lanes (AdjustKernel) run by the shared pointwise schedule — the plain
// loop for the reference, eight pixels per step for the fast traversal (the same IEEE operations
// per lane, bit-exact; tests/stylize/registry_traversal_test.cpp).
#include "stylize/stages/adjust.h"

#include "stylize/scene_inputs.h"

#include <cmath>

#include "core/lanes.h"
#include "stylize/kernels.h"
#include "stylize/schedule/pointwise.h"
#include "stylize/stages/toolkit.h"

namespace aq::stylize {

namespace {

using namespace aq::lanes;

//! Linear depth is in scene units, whatever the model's units: a model in large units (a box
//! scaled by 1e6) has an automatic depth range in the millions. Any finite float range is valid.
constexpr double kMaxDepthRange = 1e30;

// The maths of one pixel, written once over a lane type F (one pixel, or eight in simd::v8f): the
// reference runs it pixel by pixel, the fast schedule eight pixels at a time
// (stylize/schedule/pointwise.h). Inputs: colour (RGBA), linear depth; outputs: colour, normalised
// depth.
struct AdjustKernel {
    struct Params {
        AdjustParams p;
        glm::vec3 substrate{1.0f};
        float inv_range = 0, inv_atm = 0;  //!< 1 / (far - near), 1 / (atmosphere end - start)
    };
    static constexpr std::array<int, 2> kInputs = {4, 1};
    static constexpr std::array<int, 2> kOutputs = {4, 1};

    template <class F>
    static void pixel(const schedule::Pixel<F>* in, schedule::Pixel<F>* out, const Params& q) {
        const AdjustParams& p = q.p;
        const schedule::Pixel<F>& c = in[0];
        const F z = in[1][0];
        constexpr float kFloatMax = 3.402823466e38f;
        const auto finite = select(z < splat<F>(0.0f), -z, z) <= splat<F>(kFloatMax);  // |z|: false for +-inf and NaN
        out[1][0] = select(finite, (z - p.depth_near) * q.inv_range, splat<F>(1.0f));  // no geometry -> far (MNPR)
        const F luma = (kLumaR * c[0] + kLumaG * c[1]) + kLumaB * c[2];
        const float k = p.contrast * 0.5f + 0.5f;
        const float b = p.brightness - 1.0f;
        F atm = splat<F>(0.0f);
        if (p.atmosphere) {
            const F zz = select(finite, z, splat<F>(1.0e9f));  // MNPR: no geometry = 1e9 units
            atm = lanes::sat((zz - p.atmosphere_start) * q.inv_atm);
        }
        const float tint[3] = {p.tint_r, p.tint_g, p.tint_b};
        const F a = c[3];
        for (int i = 0; i < 3; ++i) {
            const F s = luma + (c[i] - luma) * p.saturation;  // lerp(luma, c, saturation)
            const F ct = 0.5f + (s - 0.5f) * k;                // lerp(0.5, s, k)
            F v = lanes::sat(ct + b);
            if (p.atmosphere) v = v + (tint[i] - v) * atm;     // lerp(v, tint, atm)
            out[0][i] = q.substrate[i] * (1.0f - a) + v * a;  // mix(substrate, v, a)
        }
        out[0][3] = a;
    }
};

}  // namespace

void check_adjust_params(const AdjustParams& p) {
    if (p.depth_far == p.depth_near) throw Error("adjust: depth_near == depth_far");
    if (p.atmosphere && p.atmosphere_end == p.atmosphere_start) throw Error("adjust: atmosphere_start == atmosphere_end");
}

void adjust(ImageF& color_out, ImageF& depth_out, const ImageF& color, const ImageF& depth_linear,
            glm::vec3 substrate, const AdjustParams& p, const Exec& ex) {
    toolkit::check_input(&color, 4, toolkit::Channels::Exactly, "adjust", "color");
    toolkit::check_input(&depth_linear, 1, toolkit::Channels::Exactly, "adjust", "depth");
    toolkit::check_same_size(depth_linear, color, "adjust", "depth", "color");
    check_adjust_params(p);
    AdjustKernel::Params q{p, substrate, 1.0f / (p.depth_far - p.depth_near),
                           p.atmosphere ? 1.0f / (p.atmosphere_end - p.atmosphere_start) : 0.0f};
    ImageF* const outs[2] = {&color_out, &depth_out};
    schedule::run_pointwise<AdjustKernel>(outs, {&color, &depth_linear}, q, ex);
}

void register_adjust(Registry& r) {
    using P = AdjustParams;
    StageVariant v = declare(
        {.stage = "adjust",
         .variant = "mnpr",
         .doc = "MNPR adjust-load: normalised depth (near..far -> 0..1), saturation/contrast/brightness, "
                "atmosphere, background = substrate colour (spec 4.1)",
         .inputs = {{"color", target::kColor, 4, false}, {"depth", target::kDepthLinear, 1, false, SizeRule::Same, "color"}},
         .outputs = {{"color", "color.adjusted", 4, false}, {"depth", "depth", 1, false}},
         .reference = StageVariant::Reference::SharedMaths,
         .row_halo = pointwise_rows},
        ParamTable<P>()
            .f("depth_near", &P::depth_near, 0, kMaxDepthRange, "linear depth mapped to 0 (MNPR 8)")
            .f("depth_far", &P::depth_far, 0, kMaxDepthRange, "linear depth mapped to 1 (MNPR 50)")
            .f("saturation", &P::saturation, 0, 5, "saturation, 1 = unchanged")
            .f("contrast", &P::contrast, 0, 5, "contrast, 1 = unchanged")
            .f("brightness", &P::brightness, 0, 5, "brightness, 1 = unchanged")
            .b("atmosphere", &P::atmosphere, "tint towards the atmosphere colour with depth")
            .f("atmosphere_start", &P::atmosphere_start, 0, 1e6, "depth where the tint starts")
            .f("atmosphere_end", &P::atmosphere_end, 0, 1e6, "depth where the tint is full")
            .f("tint_r", &P::tint_r, 0, 1, "atmosphere tint red")
            .f("tint_g", &P::tint_g, 0, 1, "atmosphere tint green")
            .f("tint_b", &P::tint_b, 0, 1, "atmosphere tint blue"),
        [](StageIO& io, const P& p, const Exec& ex) {
            adjust(*io.out[0], *io.out[1], *io.in[0], *io.in[1], globals_of(io).substrate_color, p, ex);
        },
        check_adjust_params);
    // MNPR normalises depth over 8..50 scene units (a Maya scene in cm). An automatically framed
    // camera hugs the scene's bounding sphere, so its clip range is the scene's depth range
    // whatever the model's units: normalise over it instead.
    v.scene_params = [](const ParamValues&, const SceneInputs& scene) {
        std::vector<SceneValue> out;
        if (const auto& range = scene.framed_depth_range()) {
            const std::string why = "the automatic depth range of the framed camera";
            out = {{"depth_near", double(range->first), why}, {"depth_far", double(range->second), why}};
        }
        return out;
    };
    r.add(std::move(v));
}

}  // namespace aq::stylize
