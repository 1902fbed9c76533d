// tests/stylize/pipeline_test.cpp — pipelines as data: presets load and run, every intermediate is
// identical across thread counts (SHA-256), and bad files / overrides / G-buffers give aq::Error
// naming the file and the key.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include <gtest/gtest.h>

#include "core/hash.h"
#include "raster/pass.h"
#include "scenes/procedural.h"
#include "scenes/scene_file.h"
#include "stylize/pipeline.h"
#include "tests/synthetic_gbuffer.h"
#include "tests/test_support.h"

namespace aq::stylize {
namespace {

using test::error_of;

#define EXPECT_ERROR_MENTIONS(stmt, ...)                                                  \
    do {                                                                                  \
        const std::string msg_ = error_of([&] { stmt; });                                 \
        for (const char* s_ : {__VA_ARGS__})                                              \
            EXPECT_NE(msg_.find(s_), std::string::npos) << "'" << s_ << "' not in: " << msg_; \
    } while (0)

//! A pipeline of the stages from adjust to bleed_blend only (none of the later stages).
const char* kBleedPipeline = R"({
  "name": "bleed_chain", "output": "color.bled",
  "steps": [
    {"stage": "adjust", "variant": "mnpr", "in": {"color": "color", "depth": "depth.linear"},
     "out": {"color": "color.adjusted", "depth": "depth"}},
    {"stage": "edge_detect", "variant": "rgbd_sobel", "out": {"edges": "edges"}},
    {"stage": "pigment_density", "variant": "mnpr"},
    {"stage": "bleed", "variant": "joint_bilateral", "in": {"color": "color.density"}},
    {"stage": "edge_blur", "variant": "wc18"},
    {"id": "blur17", "stage": "edge_blur", "variant": "wc17", "in": {"color": "color.adjusted"}},
    {"stage": "extend_edges", "variant": "mnpr", "params": {"width": 5}},
    {"stage": "bleed_blend", "variant": "eq7", "params": {"gain": 5}}
  ]})";

std::string write_temp(const std::string& name, const std::string& text) {
    const std::string dir = test::output_dir();
    std::filesystem::create_directories(dir);
    const std::string path = dir + "/" + name;
    std::ofstream(path) << text;
    return path;
}

TEST(Pipeline, PresetNamesIncludeThePapers) {
    const auto names = preset_names();
    for (const char* n : {"wc16", "wc17", "wc18", "mnpr"})
        EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
}

TEST(Pipeline, EveryPresetLoadsValidatesAndRunsDeterministically) {
    for (const std::string& name : preset_names()) {
        SCOPED_TRACE(name);
        Pipeline p = load_pipeline(name);
        EXPECT_EQ(p.name, name);
        EXPECT_FALSE(p.steps.empty());
        p.has_paper = false;  // flat paper: keep the test independent of the paper files
        // Presets with raster passes (ld06) draw a scene: the procedural tree, as modelled.
        static const scene::Scene tree = scene::make_procedural("tree");
        static const raster::PassScene ps =
            raster::make_pass_scene(tree, scene::frame_bounds(tree.world_bounds(), 61.0f / 37.0f), 61, 37);
        const bool passes = compile_pipeline(p).has_passes;
        std::map<std::string, std::string> first;
        for (int threads : {1, 2, 8}) {
            Targets t = test::synthetic_gbuffer(61, 37);
            RunOptions o;
            o.exec = Exec{threads, Traversal::Fast, 16};
            if (passes) o.scene = &ps;
            int calls = 0;
            o.progress = [&](int i, int n, const std::string&) {
                EXPECT_EQ(i, calls++);
                EXPECT_EQ(n, int(p.steps.size()));
            };
            run_pipeline(p, t, o);
            EXPECT_EQ(calls, int(p.steps.size()));
            ASSERT_TRUE(t.has(p.output));
            EXPECT_EQ(t.get(p.output).width(), 61);
            for (auto& [k, img] : t.all()) {
                const std::string h = sha256_hex(img);
                if (threads == 1) {
                    first[k] = h;
                } else {
                    EXPECT_EQ(first[k], h) << "target '" << k << "' differs with " << threads << " threads";
                }
            }
        }
    }
}

TEST(Pipeline, PresetPapersResolveToTheSharedAssetsAndRun) {
    for (const char* name : {"wc18", "wc17"}) {
        const Pipeline p = load_pipeline(name);
        ASSERT_TRUE(p.has_paper) << name;
        EXPECT_TRUE(std::filesystem::exists(p.paper.file)) << name << ": " << p.paper.file;
    }
    Pipeline p = load_pipeline("wc18");
    Targets t = test::synthetic_gbuffer(48, 32);
    run_pipeline(p, t, RunOptions{Exec::fast(2), {}});
    ASSERT_TRUE(t.has("paper"));
    EXPECT_EQ(t.get("paper").channels(), 3);
    EXPECT_TRUE(t.get("paper").same_size(t.get(target::kColor)));
    EXPECT_TRUE(t.has(p.output));
}

TEST(Pipeline, BleedChainRunsAndMatchesTheReferenceTraversal) {
    const Pipeline p = parse_pipeline(kBleedPipeline, "bleed_chain.json");
    Targets ref = test::synthetic_gbuffer(53, 41), fast = test::synthetic_gbuffer(53, 41);
    run_pipeline(p, ref, RunOptions{Exec::reference(), {}});
    run_pipeline(p, fast, RunOptions{Exec{2, Traversal::Fast, 16}, {}});
    for (const char* t : {"color.adjusted", "depth", "edges", "color.density", "bleed", "edges.blurred",
                          "color.blurred", "edges.extended", "color.bled", "paper"}) {
        ASSERT_TRUE(ref.has(t)) << t;
        EXPECT_EQ(sha256_hex(ref.get(t)), sha256_hex(fast.get(t))) << t;
    }
    EXPECT_EQ(ref.get("bleed").width(), 27);  // joint_bilateral defaults to half resolution
}

TEST(Pipeline, FrameLoopReusesOutputsAndGivesTheSameBytes) {
    const Pipeline p = parse_pipeline(kBleedPipeline, "bleed_chain.json");
    Targets t = test::synthetic_gbuffer(41, 29);
    RunOptions o;
    o.exec = Exec::fast(2);
    run_pipeline(p, t, o);
    const std::string first = sha256_hex(t.get("color.bled"));
    const float* storage = t.get("bleed").data();
    EXPECT_THROW(run_pipeline(p, t, o), Error) << "outputs present and reuse_outputs off";
    o.reuse_outputs = true;
    run_pipeline(p, t, o);
    EXPECT_EQ(sha256_hex(t.get("color.bled")), first);
    EXPECT_EQ(t.get("bleed").data(), storage) << "the previous frame's storage is reused";
}

TEST(Pipeline, SetParamAndSetVariant) {
    Pipeline p = parse_pipeline(kBleedPipeline, "bleed_chain.json");
    set_param(p, "extend_edges.width=7");
    EXPECT_EQ(p.steps[6].params["width"], 7.0);
    set_param(p, "bleed.half_res=false");
    EXPECT_EQ(p.steps[3].params["half_res"], 0.0);
    set_param(p, "blur17.sigma=1.5");  // by step id
    EXPECT_EQ(p.steps[5].params["sigma"], 1.5);
    set_variant(p, "bleed=naive");  // depth port and depth_threshold dropped
    EXPECT_EQ(p.steps[3].variant, "naive");
    validate_pipeline(p);
    EXPECT_ERROR_MENTIONS(set_param(p, "bleed.bogus=1"), "bogus");
    EXPECT_ERROR_MENTIONS(set_param(p, "extend_edges.width=99"), "width", "99");
    EXPECT_ERROR_MENTIONS(set_param(p, "nostage.width=1"), "nostage");
    set_param(p, "edge_blur.width=4");  // the step whose id is "edge_blur" (the other one is "blur17")
    EXPECT_EQ(p.steps[4].params["width"], 4.0);
    Pipeline twice = parse_pipeline(R"({"steps": [{"stage": "extend_edges"},
        {"stage": "extend_edges", "out": {"extended": "x2"}}]})", "twice.json");
    EXPECT_ERROR_MENTIONS(set_param(twice, "extend_edges.width=3"), "extend_edges", "2 steps");
    EXPECT_ERROR_MENTIONS(set_param(p, "extend_edges.width=abc"), "abc");
    EXPECT_ERROR_MENTIONS(set_param(p, "no_equals"), "no_equals");
    EXPECT_ERROR_MENTIONS(set_variant(p, "bleed=fancy"), "fancy", "naive");
    EXPECT_ERROR_MENTIONS(set_variant(p, "bleed"), "bleed");
}

// Enum-like parameters have named values (ParamDesc::names): --set and pipeline files take the name
// or the number, the value is the index, an unknown name lists the names.
TEST(Pipeline, NamedParameterValuesAreTheirIndex) {
    Pipeline p = parse_pipeline(kBleedPipeline, "bleed_chain.json");
    for (const auto& [text, value] : {std::pair{"mirror", 1.0}, {"clamp", 0.0}, {"1", 1.0}}) {
        set_param(p, std::string("extend_edges.border=") + text);
        EXPECT_EQ(p.steps[6].params["border"], value) << text;
    }
    EXPECT_ERROR_MENTIONS(set_param(p, "extend_edges.border=wrap"), "wrap", "clamp, mirror");
    EXPECT_ERROR_MENTIONS(set_param(p, "extend_edges.border=2"), "border", "2");
    EXPECT_ERROR_MENTIONS(set_param(p, "extend_edges.width=mirror"), "mirror", "not a number");
    const Pipeline named = parse_pipeline(R"({"steps": [{"stage": "extend_edges", "params": {"border": "mirror"}}]})", "n.json");
    EXPECT_EQ(named.steps[0].params.at("border"), 1.0);
    EXPECT_ERROR_MENTIONS(parse_pipeline(R"({"steps": [{"stage": "extend_edges", "params": {"border": "wrap"}}]})", "n.json"),
                          "n.json", "steps[0].params.border", "clamp, mirror");
    // Every named parameter is an integer from 0 to the last name, its default one of them.
    for (const Registry* reg : {&builtin_registry(), &builtin_pass_registry()})
        for (const StageVariant* v : reg->all())
            for (const ParamDesc& d : v->params)
                if (!d.names.empty()) {
                    EXPECT_EQ(d.kind, ParamKind::Int) << v->key() << "." << d.name;
                    EXPECT_EQ(d.lo, 0.0) << v->key() << "." << d.name;
                    EXPECT_EQ(d.hi, double(d.names.size() - 1)) << v->key() << "." << d.name;
                    EXPECT_LT(d.def, double(d.names.size())) << v->key() << "." << d.name;
                }
}

// --bypass: the bypassed step's readers (and the pipeline output) get its input of the same port.
TEST(Pipeline, BypassHandsTheStepsInputToItsReaders) {
    const Pipeline full = load_pipeline("wc18");
    Pipeline p = full;
    bypass_step(p, "edge_darken");
    ASSERT_EQ(p.steps.size(), full.steps.size() - 1);
    for (const PipelineStep& s : p.steps) EXPECT_NE(s.stage, "edge_darken");
    const auto go = std::find_if(p.steps.begin(), p.steps.end(), [](auto& s) { return s.stage == "gaps_overlaps"; });
    ASSERT_NE(go, p.steps.end());
    EXPECT_EQ(go->in.at("color"), "color.bled");
    validate_pipeline(p);
    // The last step: the output moves to its input, and the image is the full run's intermediate.
    Pipeline q = full;
    bypass_step(q, "substrate_light");
    EXPECT_EQ(q.output, "color.distorted");
    Targets a = test::synthetic_gbuffer(40, 28), b = test::synthetic_gbuffer(40, 28);
    run_pipeline(full, a, RunOptions{Exec::fast(2), {}});
    run_pipeline(q, b, RunOptions{Exec::fast(2), {}});
    EXPECT_EQ(sha256_hex(b.get(q.output)), sha256_hex(a.get("color.distorted")));
    EXPECT_NE(sha256_hex(b.get(q.output)), sha256_hex(a.get(full.output)));
    // A step whose output has no same-named input: the error names the step that can be bypassed.
    Pipeline r = full;
    EXPECT_ERROR_MENTIONS(bypass_step(r, "bleed"), "--bypass 'bleed'", "bleed_blend", "edge_darken");
    EXPECT_ERROR_MENTIONS(bypass_step(r, "nope"), "nope", "substrate_light");
    EXPECT_EQ(r.steps.size(), full.steps.size()) << "a refused bypass leaves the pipeline as it was";
}

TEST(Pipeline, BadFilesNameTheFileAndTheKey) {
    EXPECT_ERROR_MENTIONS(parse_pipeline("{\"steps\": [", "bad.json"), "bad.json", "invalid JSON at key 'steps[0]'");
    EXPECT_ERROR_MENTIONS(parse_pipeline("[1, 2]", "bad.json"), "bad.json");
    EXPECT_ERROR_MENTIONS(parse_pipeline(R"({"steps": [{"stage": "nope"}]})", "x.json"), "x.json", "steps[0].stage",
                          "nope");
    EXPECT_ERROR_MENTIONS(parse_pipeline(R"({"steps": [{"stage": "bleed", "variant": "fancy"}]})", "x.json"),
                          "steps[0].variant", "fancy");
    EXPECT_ERROR_MENTIONS(
        parse_pipeline(R"({"steps": [{"stage": "adjust"}, {"stage": "extend_edges", "params": {"bogus": 1}}]})", "x.json"),
        "x.json", "steps[1].params.bogus");
    EXPECT_ERROR_MENTIONS(
        parse_pipeline(R"({"steps": [{"stage": "adjust"}, {"stage": "extend_edges", "params": {"width": 100}}]})", "x.json"),
        "steps[1].params.width", "100");
    EXPECT_ERROR_MENTIONS(parse_pipeline(R"({"steps": [{"stage": "extend_edges", "params": {"width": "wide"}}]})", "x.json"),
                          "steps[0].params.width", "number");
    EXPECT_ERROR_MENTIONS(parse_pipeline(R"({"steps": [{"stage": "extend_edges", "in": {"edgez": "edges"}}]})", "x.json"),
                          "steps[0].in.edgez");
    EXPECT_ERROR_MENTIONS(parse_pipeline(R"({"steps": [{"stage": "extend_edges", "colour": 1}]})", "x.json"),
                          "steps[0].colour");
    EXPECT_ERROR_MENTIONS(parse_pipeline(R"({"steps": []})", "x.json"), "steps");
    EXPECT_ERROR_MENTIONS(parse_pipeline(R"({"substrate_color": [1, 2], "steps": [{"stage": "adjust"}]})", "x.json"),
                          "substrate_color");
    // from a file: the message names the path
    const std::string path = write_temp("broken_pipeline.json", "{\"steps\": [{\"stage\": \"adjust\",, }]}");
    EXPECT_ERROR_MENTIONS(load_pipeline(path), "broken_pipeline.json", "invalid JSON at key 'steps[0].stage'");
    EXPECT_ERROR_MENTIONS(load_pipeline("no_such_style"), "no_such_style");
    EXPECT_ERROR_MENTIONS(load_pipeline("/nonexistent/dir/p.json"), "/nonexistent/dir/p.json");
}

TEST(Pipeline, ValidationCatchesWiringErrorsBeforeRunning) {
    Targets g = test::synthetic_gbuffer(20, 10);
    // a step writing its own input
    EXPECT_ERROR_MENTIONS(validate_pipeline(parse_pipeline(
                              R"({"output": "edges", "steps": [{"stage": "adjust"}, {"stage": "edge_detect"},
                                  {"stage": "extend_edges", "in": {"edges": "edges"}, "out": {"extended": "edges"}}]})", "self.json"), &g),
                          "self.json", "steps[2]", "own input");
    // an input nobody produced and not in the G-buffer
    EXPECT_ERROR_MENTIONS(validate_pipeline(parse_pipeline(
                              R"({"output": "edges.extended", "steps": [{"stage": "extend_edges", "in": {"edges": "nothing"}}]})",
                              "missing.json"), &g),
                          "missing.json", "steps[0]", "'nothing'");
    // overwriting a G-buffer target
    EXPECT_ERROR_MENTIONS(validate_pipeline(parse_pipeline(
                              R"({"output": "color", "steps": [{"stage": "adjust", "out": {"color": "color"}}]})", "ow.json"), &g),
                          "ow.json", "color");
    // channel mismatch between producer and consumer
    EXPECT_ERROR_MENTIONS(validate_pipeline(parse_pipeline(
                              R"({"output": "edges.extended", "steps": [{"stage": "adjust"},
                                  {"stage": "extend_edges", "in": {"edges": "color.adjusted"}}]})", "ch.json"), &g),
                          "ch.json", "steps[1]", "channels");
    // output never written
    EXPECT_ERROR_MENTIONS(validate_pipeline(parse_pipeline(
                              R"({"output": "color.final", "steps": [{"stage": "adjust"}]})", "out.json"), &g),
                          "out.json", "color.final");
    // G-buffer size mismatch, reported before any stage runs
    Targets bad = test::synthetic_gbuffer(20, 10);
    bad.set(target::kDepthLinear, ImageF(19, 10, 1));
    const Pipeline p = parse_pipeline(kBleedPipeline, "bleed_chain.json");
    EXPECT_ERROR_MENTIONS(run_pipeline(p, bad), "bleed_chain.json", "depth.linear");
    EXPECT_FALSE(bad.has("color.adjusted")) << "nothing may run when validation fails";
    // missing G-buffer target
    Targets none;
    none.set(target::kColor, ImageF(20, 10, 4));
    EXPECT_ERROR_MENTIONS(run_pipeline(p, none), "depth.linear");
}

TEST(Pipeline, NanInTheGBufferDoesNotCrash) {
    const Pipeline p = parse_pipeline(kBleedPipeline, "bleed_chain.json");
    Targets t = test::synthetic_gbuffer(33, 21);
    for (const char* name : {target::kColor, target::kDepthLinear, target::kCtrlAbstraction, target::kCtrlEdge})
        for (std::size_t i = 0; i < t.get(name).num_values(); i += 5)
            t.get_mut(name).data()[i] = (i / 5) % 2 ? std::numeric_limits<float>::quiet_NaN()
                                                    : std::numeric_limits<float>::infinity();
    run_pipeline(p, t, RunOptions{Exec{2, Traversal::Fast, 16}, {}});
    EXPECT_TRUE(t.has("color.bled"));
}

TEST(Pipeline, PresetDirCanBeOverriddenByEnvironment) {
    const std::string dir = test::output_dir() + "/presets_override";
    std::filesystem::create_directories(dir);
    std::ofstream(dir + "/mine.json") << kBleedPipeline;
    ::setenv("AQ_PRESET_DIR", dir.c_str(), 1);
    const auto names = preset_names();
    const Pipeline p = load_pipeline("mine");
    ::unsetenv("AQ_PRESET_DIR");
    EXPECT_EQ(names, std::vector<std::string>{"mine"});
    EXPECT_EQ(p.name, "bleed_chain");
}

}  // namespace
}  // namespace aq::stylize

namespace aq::stylize {
namespace {

// Issue 9 item 3: a pipeline is compiled once (variants, parameters, bindings resolved and
// checked); running the plan twice gives what running the description gives, and the plan knows
// which targets come from the G-buffer and when each intermediate is read for the last time.
TEST(CompiledPipeline, RunsAsTheDescriptionAndKnowsItsInputsAndLiveness) {
    const Pipeline p = load_pipeline("wc18");
    const CompiledPipeline c = compile_pipeline(p);
    ASSERT_EQ(c.steps.size(), p.steps.size());
    for (std::size_t i = 0; i < c.steps.size(); ++i) {
        EXPECT_EQ(c.steps[i].variant->stage, p.steps[i].stage);
        EXPECT_EQ(c.steps[i].params.size(), c.steps[i].variant->params.size()) << "every parameter resolved";
    }
    std::set<std::string> external;
    for (const ExternalInput& x : c.external) external.insert(x.target);
    EXPECT_TRUE(external.count(target::kColor));
    EXPECT_TRUE(external.count(target::kDepthLinear));
    for (const std::string& t : c.produced) EXPECT_FALSE(external.count(t)) << t << " is written by a step";
    // Liveness: every read target's last reader is the last step whose inputs name it.
    for (const auto& [t, last] : c.last_read) {
        for (std::size_t i = last + 1; i < c.steps.size(); ++i)
            for (const std::string& in : c.steps[i].inputs) EXPECT_NE(in, t) << "step " << i << " reads " << t;
        bool read_there = false;
        for (const std::string& in : c.steps[last].inputs) read_there |= in == t;
        EXPECT_TRUE(read_there) << t;
    }
    Targets a = test::synthetic_gbuffer(61, 37), b = test::synthetic_gbuffer(61, 37);
    run_pipeline(p, a, RunOptions{Exec::fast(2), {}});
    RunOptions reuse{Exec::fast(2), {}};
    reuse.reuse_outputs = true;
    run_pipeline(c, b, reuse);
    run_pipeline(c, b, reuse);  // a second frame into the same targets
    for (const std::string& t : c.produced) EXPECT_EQ(sha256_hex(a.get(t)), sha256_hex(b.get(t))) << t;
}

TEST(CompiledPipeline, TheGBufferIsCheckedAtEveryRun) {
    const CompiledPipeline c = compile_pipeline(load_pipeline("wc18"));
    Targets t = test::synthetic_gbuffer(16, 12);
    t.erase(target::kDepthLinear);
    EXPECT_ERROR_MENTIONS(run_pipeline(c, t), "wc18.json", target::kDepthLinear);
}

}  // namespace
}  // namespace aq::stylize
