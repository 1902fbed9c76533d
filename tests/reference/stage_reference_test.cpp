// tests/reference/stage_reference_test.cpp — every registered stage variant against its GLSL twin
// (reference/shaders/<stage>.<variant>.glsl) run through OpenGL, on a synthetic G-buffer and on
// G-buffers rasterized from real models. Tolerances are per stage, each with its reason
// (docs/reference.md); a variant without a twin is a failure.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>

#include <gtest/gtest.h>

#include "core/compare.h"
#include "core/io.h"
#include "reference/stage_twin.h"
#include "reference/stage_inputs.h"
#include "tests/synthetic_gbuffer.h"
#include "stylize/paper.h"
#include "stylize/pipeline.h"
#include "tests/raster/raster_test_util.h"
#include "scenes/procedural.h"
#include "raster/pass.h"
#include "tests/reference/reference_scenes.h"
#include "tests/reference/reference_support.h"
#include "tests/test_support.h"

namespace aq::ref {
namespace {

using stylize::StageVariant;

// How far the C++ stage and its GLSL twin may differ, and why.
//  max_abs    : bound on |C++ - GL| for every value, except
//  flip_frac  : the fraction of values allowed above max_abs (0 = none). Used for stages with a
//               hard threshold, where a value within an ulp of the threshold may fall on either
//               side and flip a pixel by a large amount.
struct Tolerance {
    double max_abs = 1e-5;
    double flip_frac = 0.0;
    const char* why = "pointwise arithmetic in the same order: differences are float rounding only";
};

const std::map<std::string, Tolerance>& tolerances() {
    static const std::map<std::string, Tolerance> t = {
        {"adjust/mnpr", {2e-6, 0.0, "pointwise; the depth division (GLSL x / y, C++ x * (1 / y)) may differ by an ulp"}},
        {"gaps_overlaps/wc18",
         {0.05, 0.005,
          "overlap colours go through an iterative RGB->RYB least-squares inverse: for colours outside the "
          "RYB cube's image it has several local minima and the C++ solver (seeded from a 17^3 table) and the "
          "twin (seeded from a 5^3 RYB lattice) may settle on different ones, up to ~0.04 apart (in gamut they "
          "agree to 2e-7, GlHarness.RybMixMatchesCppInGamut); the hard thresholds (colour difference 0.33, "
          "substrate proximity, edge 2/m and 1/m on bilinear taps) may flip a pixel between branches at exact "
          "ties: at most 0.5% of the values may exceed 0.05"}},
        {"substrate_distort/mnpr",
         {1e-5, 0.002,
          "the depth test on a bilinear depth tap is a hard threshold (0.01): a destination within an ulp "
          "of it may be refused on one side only, flipping the pixel between its own and the shifted colour"}},
    };
    return t;
}

Tolerance tolerance_for(const StageVariant& v) {
    auto it = tolerances().find(v.key());
    return it != tolerances().end() ? it->second : Tolerance{};
}

std::vector<std::string> registry_keys() {
    std::vector<std::string> keys;
    for (auto* v : stylize::builtin_registry().all()) keys.push_back(v->key());
    return keys;
}

const StageVariant& variant_of(const std::string& key) {
    const auto slash = key.find('/');
    return stylize::builtin_registry().get(key.substr(0, slash), key.substr(slash + 1));
}

//! A named input set: a G-buffer (and everything derived from it) and its paper.
struct Scene {
    std::string name;
    Targets targets;
    ImageF paper;
    stylize::Globals globals;
};

Scene make_synthetic(int w, int h, std::uint32_t seed) {
    Scene s;
    s.name = "synthetic_" + std::to_string(w) + "x" + std::to_string(h);
    s.targets = aq::test::synthetic_gbuffer(w, h, seed);
    // Raster-pass outputs (LD06 depth, lighting, shadow and intensity maps) play the G-buffer's part
    // for the stages that read them: synthetic maps in [0, 1] of the same size.
    const auto& passes = stylize::builtin_pass_registry();
    for (const StageVariant* v : passes.all())
        for (const stylize::Port& o : v->outputs)
            if (!s.targets.has(o.default_target))
                s.targets.set(o.default_target, aq::test::synthetic_target(o.default_target, o.channels, w, h, seed));
    stylize::PaperSpec ps;
    ps.file = test::asset("paper/mnpr/rough_default_2k.jpg");
    s.paper = stylize::prepare_paper(ps, w, h);
    s.globals.substrate_color = {0.98f, 0.96f, 0.9f};
    return s;
}

//! Alternative values where the generic rule below would break a cross-parameter constraint.
const std::map<std::string, double> kAltOverrides = {
    {"edge_darken/dog.smooth_low", 0.02}, {"edge_darken/dog.smooth_high", 0.25},
    {"adjust/mnpr.atmosphere_start", 10.0}, {"adjust/mnpr.atmosphere_end", 40.0},
};

//! Alternative parameter values exercising other code paths: booleans flipped, floats and ints
//! moved inside their range.
stylize::ParamValues alt_params(const StageVariant& v) {
    std::map<std::string, double> o;
    for (auto& d : v.params) {
        if (auto it = kAltOverrides.find(v.key() + "." + d.name); it != kAltOverrides.end()) {
            o[d.name] = it->second;
            continue;
        }
        double x = d.def;
        if (d.kind == stylize::ParamKind::Bool) x = d.def != 0 ? 0 : 1;
        else if (d.kind == stylize::ParamKind::Int) x = std::min(d.hi, d.def + 1);
        else x = d.def != 0 ? std::clamp(d.def * 1.37, d.lo, d.hi) : std::clamp(d.lo + 0.3 * std::min(d.hi - d.lo, 2.0), d.lo, d.hi);
        o[d.name] = x;
    }
    return stylize::Registry::resolve_params(v, o, "alt_params");
}

//! One row per comparison, appended to reference_stage_errors.tsv in this test's own output folder
//! (kept when the test fails or AQ_KEEP_TEST_OUTPUT is set; tests/test_support.h). The same numbers
//! are printed on stdout, so `ctest -L reference -V` shows the whole table.
void append_error_row(const std::string& row) {
    const std::string path = test::output_dir() + "/reference_stage_errors.tsv";
    const bool fresh = !std::filesystem::exists(path) || std::filesystem::file_size(path) == 0;
    std::ofstream f(path, std::ios::app);
    if (fresh) f << "variant\tscene\tparams\toutput\tmean_abs\tmax_abs\tfrac_over_tol\tfrac_over_1/255\tpsnr\n";
    f << row << "\n";
}

//! Compares the C++ and GL outputs of one stage run against the variant's tolerance; on failure
//! writes both images and a diff heatmap and names them.
void compare_outputs(const StageVariant& v, const std::vector<const ImageF*>& cpp, const std::vector<ImageF>& gl,
                     const std::string& scene, const std::string& pname) {
    ASSERT_EQ(gl.size(), cpp.size());
    const Tolerance tol = tolerance_for(v);
    for (std::size_t k = 0; k < cpp.size(); ++k) {
        const ImageF& c = *cpp[k];
        const std::string what = v.key() + " output '" + v.outputs[k].name + "' on " + scene + " (" + pname + ")";
        ASSERT_TRUE(c.same_size(gl[k]) && c.channels() == gl[k].channels())
            << what << ": C++ " << c.width() << "x" << c.height() << "x" << c.channels() << " vs GL "
            << gl[k].width() << "x" << gl[k].height() << "x" << gl[k].channels();
        const CompareStats st = compare_images(c, gl[k], 1.0 / 255.0);
        const CompareStats fine = compare_images(c, gl[k], tol.max_abs);
        char row[512];
        std::snprintf(row, sizeof row, "%s\t%s\t%s\t%s\t%.3g\t%.3g\t%.3g\t%.3g\t%.1f", v.key().c_str(), scene.c_str(),
                      pname.c_str(), v.outputs[k].name.c_str(), st.mean_abs, st.max_abs, fine.frac_over, st.frac_over,
                      st.psnr);
        append_error_row(row);
        std::printf("  %-26s %-9s %-22s %-7s mean %.3g max %.3g (at %d,%d c%d) over tol %.3g over 1/255 %.3g\n",
                    v.key().c_str(), v.outputs[k].name.c_str(), scene.c_str(), pname.c_str(), st.mean_abs, st.max_abs,
                    st.max_x, st.max_y, st.max_c, fine.frac_over, st.frac_over);
        bool pass = st.nonfinite == 0;
        if (tol.flip_frac == 0.0) pass = pass && st.max_abs <= tol.max_abs;
        else pass = pass && fine.frac_over <= tol.flip_frac;
        if (!pass) {
            const std::string base =
                test::output_dir() + "/" + safe_file_name(v.key() + "." + v.outputs[k].name + "." + scene + "." + pname);
            write_image(base + ".cpp.exr", c);
            write_image(base + ".gl.exr", gl[k]);
            write_image(base + ".diff.png", diff_heatmap(c, gl[k]));
            ADD_FAILURE() << what << " differs beyond tolerance (max_abs " << tol.max_abs << ", flip fraction "
                          << tol.flip_frac << ": " << tol.why << ")\n"
                          << format_stats(st) << "\nfraction over " << tol.max_abs << ": " << fine.frac_over
                          << "\nwrote " << base << ".cpp.exr, .gl.exr, .diff.png";
        }
    }
}

//! Runs one variant on one scene and parameter set (inputs by default target names, produced by
//! the registered C++ producers); compares every output.
void check_variant(const StageVariant& v, Scene& s, const stylize::ParamValues& params, const std::string& pname) {
    s.globals.paper = &s.paper;
    for (auto& in : v.inputs) {
        const bool ok = resolve_target(s.targets, in.default_target, s.globals);
        if (!ok && !in.optional) FAIL() << v.key() << ": no producer for input '" << in.default_target << "'";
        // An optional input no stage produces by default (edge_darken/rgbd's `crowd`, made by a
        // preset step): a synthetic map, so the twin's path for it is compared too.
        if (!ok) {
            const ImageF& c = s.targets.get(target::kColor);
            s.targets.set(in.default_target, aq::test::synthetic_target(in.default_target, in.channels, c.width(), c.height()));
        }
    }
    auto cpp = run_cpp_stage(v, s.targets, params, s.globals);
    std::vector<const ImageF*> ins;
    for (auto& in : v.inputs) ins.push_back(s.targets.has(in.default_target) ? &s.targets.get(in.default_target) : nullptr);
    auto gl = StageTwin(v).run(ins, params, s.globals);
    std::vector<const ImageF*> cp;
    for (auto& c : cpp) cp.push_back(&c);
    compare_outputs(v, cp, gl, s.name, pname);
}

class StageReference : public ::testing::TestWithParam<std::string> {};

TEST_P(StageReference, MatchesGlslTwinOnSyntheticGBuffer) {
    AQ_REQUIRE_GL();
    const StageVariant& v = variant_of(GetParam());
    ASSERT_TRUE(has_twin(v)) << "no GLSL twin " << shader_dir() << "/" << twin_file(v);
    for (auto [w, h] : {std::pair{96, 64}, std::pair{61, 47}}) {
        Scene s = make_synthetic(w, h, 7);
        check_variant(v, s, stylize::Registry::resolve_params(v, {}, "defaults"), "default");
        check_variant(v, s, alt_params(v), "alt");
    }
}

INSTANTIATE_TEST_SUITE_P(Registry, StageReference, ::testing::ValuesIn(registry_keys()),
                         [](const ::testing::TestParamInfo<std::string>& i) {
                             std::string n = i.param;
                             for (char& c : n)
                                 if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                             return n;
                         });
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(StageReference);

// Every step of every preset pipeline, on G-buffers rasterized from real models and the procedural
// scene (and the synthetic one): the inputs are exactly what the pipeline feeds the step (half-
// resolution bleeding included), the parameters are the preset's.
struct PipelineCase {
    std::string preset, scene;
};
// Readable names in `--gtest_list_tests` (and so in CTest) instead of a byte dump.
void PrintTo(const PipelineCase& c, std::ostream* os) { *os << c.preset << " on " << c.scene; }

std::vector<PipelineCase> pipeline_cases() {
    std::vector<PipelineCase> out;
    for (const char* preset : {"wc16", "wc17", "wc18", "mnpr"})
        for (auto& scene : reference_scene_names()) out.push_back({preset, scene});
    return out;
}

class PipelineReference : public ::testing::TestWithParam<PipelineCase> {};

TEST_P(PipelineReference, EveryStepMatchesItsTwin) {
    AQ_REQUIRE_GL();
    const PipelineCase& pc = GetParam();
    stylize::Pipeline p = stylize::load_pipeline(pc.preset);
    ReferenceScene rs = make_reference_scene(pc.scene, 160, 96);
    if (rs.has_paper) p.paper = rs.paper, p.has_paper = true;
    p.substrate_color = rs.substrate_color;
    Targets t = rs.gbuffer;
    stylize::RunOptions opt;
    opt.exec = Exec::reference();
    stylize::run_pipeline(p, t, opt);
    stylize::Globals g;
    g.substrate_color = p.substrate_color;
    g.paper = &t.get("paper");
    for (std::size_t i = 0; i < p.steps.size(); ++i) {
        const stylize::ResolvedStep st = stylize::resolve_step(p, i);
        const StageVariant& v = *st.variant;
        ASSERT_TRUE(has_twin(v)) << "no GLSL twin for " << v.key();
        std::vector<const ImageF*> ins, cpp;
        for (auto& name : st.inputs) ins.push_back(name.empty() || !t.has(name) ? nullptr : &t.get(name));  // absent optional input
        for (auto& name : st.outputs) cpp.push_back(&t.get(name));
        auto gl = StageTwin(v).run(ins, st.params, g);
        compare_outputs(v, cpp, gl, pc.scene, pc.preset + "#" + std::to_string(i));
    }
}

INSTANTIATE_TEST_SUITE_P(Presets, PipelineReference, ::testing::ValuesIn(pipeline_cases()),
                         [](const ::testing::TestParamInfo<PipelineCase>& i) {
                             std::string n = i.param.preset + "_" + i.param.scene;
                             for (char& c : n)
                                 if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                             return n;
                         });

// The ld06 preset's stages on what its raster passes really produce — 0.72-scale maps resampled to
// the output size, ID packs with empty layers, a real lighting map — for the procedural tree: each
// stage step against its twin (the passes have their own twins, tests/reference/pass_reference_test.cpp).
TEST(PipelineReferenceLd06, EveryStageStepMatchesItsTwinOnThePassOutputs) {
    AQ_REQUIRE_GL();
    stylize::Pipeline p = stylize::load_pipeline("ld06");
    p.has_paper = false;  // flat paper keeps the comparison about the stages' own maths
    const scene::Scene tree = scene::make_procedural("tree");
    raster::PassScene ps = raster::make_pass_scene(tree, test::frame_scene(tree), 200, 180);
    Targets t;
    stylize::RunOptions opt;
    opt.exec = Exec::reference();
    opt.scene = &ps;
    stylize::run_pipeline(p, t, opt);
    stylize::Globals g;
    g.substrate_color = p.substrate_color;
    g.paper = &t.get("paper");
    int compared = 0;
    for (std::size_t i = 0; i < p.steps.size(); ++i) {
        if (p.steps[i].pass) continue;
        const stylize::ResolvedStep st = stylize::resolve_step(p, i);
        const StageVariant& v = *st.variant;
        ASSERT_TRUE(has_twin(v)) << "no GLSL twin for " << v.key();
        std::vector<const ImageF*> ins, cpp;
        for (auto& name : st.inputs) ins.push_back(name.empty() || !t.has(name) ? nullptr : &t.get(name));
        for (auto& name : st.outputs) cpp.push_back(&t.get(name));
        auto gl = StageTwin(v).run(ins, st.params, g);
        compare_outputs(v, cpp, gl, "procedural_tree", "ld06#" + std::to_string(i));
        ++compared;
    }
    EXPECT_GE(compared, 10);
}

TEST(StageReferenceCoverage, EveryRegisteredVariantHasATwin) {
    std::string missing;
    for (auto* v : stylize::builtin_registry().all())
        if (!has_twin(*v)) missing += "  " + v->key() + " -> " + shader_dir() + "/" + twin_file(*v) + "\n";
    EXPECT_TRUE(missing.empty()) << "stage variants without a GLSL twin:\n" << missing;
    EXPECT_FALSE(stylize::builtin_registry().all().empty()) << "the stage registry is empty";
}

TEST(StageReferenceCoverage, EveryTwinParses) {
    for (auto* v : stylize::builtin_registry().all())
        if (has_twin(*v)) {
            EXPECT_NO_THROW(StageTwin t(*v)) << v->key();
        }
}

}  // namespace
}  // namespace aq::ref
