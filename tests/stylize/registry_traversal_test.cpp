// tests/stylize/registry_traversal_test.cpp — every registered stage variant (any added later
// too: the test iterates builtin_registry()) against its reference traversal, with
// default and alternative parameters, on NaN/Inf-poisoned inputs, and with bad inputs.
#include <cmath>
#include <cstring>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/hash.h"
#include "stylize/stage.h"
#include "tests/stylize/stage_test_util.h"
#include "tests/synthetic_gbuffer.h"

namespace aq::stylize {
namespace {

constexpr int kW = 67, kH = 45;  // odd sizes: half resolution rounds up

std::vector<std::string> variant_keys() {
    std::vector<std::string> out;
    for (auto* v : builtin_registry().all()) out.push_back(v->key());
    return out;
}

const StageVariant& variant_by_key(const std::string& key) {
    const auto slash = key.find('/');
    return builtin_registry().get(key.substr(0, slash), key.substr(slash + 1));
}

struct VariantRun {
    std::vector<ImageF> inputs;
    ImageF paper;
    Globals g;

    VariantRun(const StageVariant& v, bool poison) {
        std::uint32_t seed = 3;
        for (const Port& p : v.inputs) inputs.push_back(test::synthetic_target(p.default_target, p.channels, kW, kH, seed++));
        paper = test::synthetic_target("paper", 3, kW, kH, 99);
        if (poison)
            for (auto& img : inputs)
                for (std::size_t i = 0; i < img.num_values(); i += 7)
                    img.data()[i] = (i / 7) % 3 == 0 ? std::numeric_limits<float>::quiet_NaN()
                                    : (i / 7) % 3 == 1 ? std::numeric_limits<float>::infinity()
                                                       : -std::numeric_limits<float>::infinity();
        g.substrate_color = {0.96f, 0.94f, 0.9f};
        g.paper = &paper;
    }

    std::vector<ImageF> exec(const StageVariant& v, const ParamValues& pv, const Exec& ex) const {
        StageIO io;
        io.globals = &g;
        for (auto& i : inputs) io.in.push_back(&i);
        std::vector<ImageF> outs(v.outputs.size());
        for (auto& o : outs) io.out.push_back(&o);
        v.run(io, pv, ex);
        return outs;
    }
};

//! Defaults, and the same with every Bool flipped (covers half_res on/off, literal, ...).
std::vector<ParamValues> param_sets(const StageVariant& v) {
    ParamValues d = Registry::resolve_params(v, {}, "test");
    ParamValues alt = d;
    for (auto& p : v.params)
        if (p.kind == ParamKind::Bool) alt[p.name] = d[p.name] != 0.0 ? 0.0 : 1.0;
    return {d, alt};
}

//! Bit-identical values, NaN equal to NaN (tests/stylize/stage_test_util.h).
using testb::same_values;

const char* reference_kind(const StageVariant& v) {
    switch (v.reference) {
        case StageVariant::Reference::PlainLoop: return "plain loop over the per-pixel maths";
        case StageVariant::Reference::SharedMaths: return "the per-pixel function the fast schedule calls";
        default: return "the fast kernel on one thread";
    }
}

class EveryVariant : public ::testing::TestWithParam<std::string> {};

TEST_P(EveryVariant, FastEqualsReference) {
    const StageVariant& v = variant_by_key(GetParam());
    const VariantRun run(v, false);
    for (const ParamValues& pv : param_sets(v)) {
        const auto ref = run.exec(v, pv, Exec::reference());
        for (int threads : {1, 2, 8}) {
            const auto fast = run.exec(v, pv, Exec{threads, Traversal::Fast, 16});
            ASSERT_EQ(ref.size(), fast.size());
            for (std::size_t k = 0; k < ref.size(); ++k) {
                ASSERT_EQ(ref[k].channels(), v.outputs[k].channels) << v.outputs[k].name;
                ASSERT_TRUE(ref[k].same_size(fast[k]));
                EXPECT_TRUE(same_values(ref[k], fast[k]))
                    << v.key() << " output '" << v.outputs[k].name << "' threads " << threads
                    << ": fast schedule differs from the reference (" << reference_kind(v) << ") ("
                    << sha256_hex(ref[k]) << " vs " << sha256_hex(fast[k]) << ")";
            }
        }
    }
}

// A variant that declares an in-place port pair (StageVariant::in_place_input) must give, handed
// one image as that input and its output, the bytes of its run on separate images: clean,
// poisoned (NaN, +-Inf) and background-like inputs (every input zero, -0 in the colour, on the
// left 40 columns: the chunks a stage leaves unwritten in place), every traversal.
TEST_P(EveryVariant, InPlaceGivesTheBytesOfSeparateImages) {
    const StageVariant& v = variant_by_key(GetParam());
    if (v.in_place_input.empty()) return;  // not an in-place variant: nothing to check
    std::size_t k_in = 0, k_out = 0;
    while (v.inputs[k_in].name != v.in_place_input) ++k_in;
    while (v.outputs[k_out].name != v.in_place_output) ++k_out;
    for (int mode = 0; mode < 3; ++mode) {
        VariantRun run(v, mode == 1);
        if (mode == 2)
            for (std::size_t k = 0; k < run.inputs.size(); ++k) {
                ImageF& img = run.inputs[k];
                for (int y = 0; y < img.height(); ++y)
                    for (int x = 0; x < std::min(40, img.width()); ++x)
                        for (int c = 0; c < img.channels(); ++c)
                            img.at(x, y, c) = k == k_in && c < 3 && (x + y) % 3 == 0 ? -0.0f : 0.0f;
            }
        for (const ParamValues& pv : param_sets(v))
            for (const Exec& ex : {Exec::reference(), Exec{1, Traversal::Fast, 16}, Exec{2, Traversal::Fast, 16}}) {
                const auto separate = run.exec(v, pv, ex);
                StageIO io;
                io.globals = &run.g;
                for (auto& i : run.inputs) io.in.push_back(&i);
                std::vector<ImageF> outs(v.outputs.size());
                outs[k_out] = run.inputs[k_in];  // the input's copy becomes the output
                io.in[k_in] = &outs[k_out];
                for (auto& o : outs) io.out.push_back(&o);
                v.run(io, pv, ex);
                for (std::size_t k = 0; k < outs.size(); ++k)
                    EXPECT_EQ(0, std::memcmp(separate[k].data(), outs[k].data(), separate[k].num_values() * sizeof(float)))
                        << v.key() << " output '" << v.outputs[k].name << "' in place differs (inputs " << mode
                        << ", traversal " << int(ex.traversal) << ", threads " << ex.threads << ")";
            }
    }
}

TEST_P(EveryVariant, NanAndInfInputsNeverCrash) {
    const StageVariant& v = variant_by_key(GetParam());
    const VariantRun run(v, true);
    for (const ParamValues& pv : param_sets(v)) {
        const auto ref = run.exec(v, pv, Exec::reference());
        const auto fast = run.exec(v, pv, Exec{2, Traversal::Fast, 16});
        for (std::size_t k = 0; k < ref.size(); ++k) {
            EXPECT_FALSE(ref[k].empty());
            EXPECT_TRUE(ref[k].same_size(fast[k]));
            EXPECT_TRUE(same_values(ref[k], fast[k])) << v.key() << " on poisoned input (" << reference_kind(v) << ")";
        }
    }
}

TEST_P(EveryVariant, WrongChannelCountIsAnError) {
    const StageVariant& v = variant_by_key(GetParam());
    for (std::size_t k = 0; k < v.inputs.size(); ++k) {
        VariantRun run(v, false);
        const int wrong = v.inputs[k].channels == 1 ? 4 : 1;
        run.inputs[k] = ImageF(kW, kH, wrong, 0.5f);
        EXPECT_THROW(run.exec(v, Registry::resolve_params(v, {}, "test"), Exec::reference()), Error)
            << v.key() << " input '" << v.inputs[k].name << "' with " << wrong << " channels";
    }
}

TEST_P(EveryVariant, MismatchedSizesAreAnError) {
    const StageVariant& v = variant_by_key(GetParam());
    if (v.inputs.size() < 2) return;  // nothing to mismatch against (the paper is sized by the runner)
    // Stages whose every other input is resampled by contract: stroke_ink paints an ink map of any
    // size (the strokes pass renders at its own scale; stroke_ink.h).
    if (v.key() == "stroke_ink/over") return;
    // The first input (the image being stylised) at another size than every other input. Some
    // inputs may legitimately be resampled (half-resolution bleed/blur), but not all of them.
    VariantRun run(v, false);
    run.inputs[0] = test::synthetic_target(v.inputs[0].default_target, v.inputs[0].channels, kW + 3, kH - 2);
    try {
        run.exec(v, Registry::resolve_params(v, {}, "test"), Exec::reference());
        ADD_FAILURE() << v.key() << ": input '" << v.inputs[0].name << "' of another size than the others was accepted";
    } catch (const Error& e) {
        SUCCEED() << e.what();
    }
}

INSTANTIATE_TEST_SUITE_P(Registry, EveryVariant, ::testing::ValuesIn(variant_keys()),
                         [](const ::testing::TestParamInfo<std::string>& i) {
                             std::string s = i.param;
                             for (char& c : s)
                                 if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                             return s;
                         });

// Issue 9 "algorithm plus schedule": for every variant, Traversal::Reference is an independent
// plain loop over the per-pixel maths, or the fast schedule calls that maths itself — never the
// fast row kernel run on one thread (which proves thread independence, not correctness;
// docs/stylize.md "Algorithm and schedule"). A new stage must state which.
TEST(Registry, ReferenceIsIndependentOfTheFastKernel) {
    for (auto* v : builtin_registry().all())
        EXPECT_NE(v->reference, StageVariant::Reference::SameKernel) << v->key();
}

TEST(Registry, OptionalBleedInputMayBeAbsent) {
    const Registry& r = builtin_registry();
    for (auto [s, var] : {std::pair{"edge_darken", "rgbd"}, {"gaps_overlaps", "wc18"}}) {
        const StageVariant& v = r.get(s, var);
        ASSERT_TRUE(v.inputs.back().optional);
        std::vector<ImageF> ins;
        for (std::size_t k = 0; k + 1 < v.inputs.size(); ++k)
            ins.push_back(testb::noise(20, 10, v.inputs[k].channels, 0.0f, 1.0f, 200 + unsigned(k)));
        ImageF out;
        StageIO io;
        for (auto& i : ins) io.in.push_back(&i);
        io.in.push_back(nullptr);
        io.out.push_back(&out);
        v.run(io, Registry::resolve_params(v, {}, "test"), Exec::reference());
        EXPECT_EQ(out.width(), 20);
    }
}

TEST(Registry, EveryStageAndVariantIsRegistered) {
    const Registry& r = builtin_registry();
    for (auto [s, v] : {std::pair{"adjust", "mnpr"}, {"edge_detect", "rgbd_sobel"}, {"pigment_density", "mnpr"},
                        {"bleed", "naive"}, {"bleed", "joint_bilateral"}, {"bleed", "mnpr"}, {"edge_blur", "wc17"},
                        {"edge_blur", "wc18"}, {"extend_edges", "mnpr"}, {"bleed_blend", "eq7"}, {"edge_darken", "dog"},
                        {"edge_darken", "rgbd"}, {"gaps_overlaps", "wc18"}, {"pigment_apply", "wc17"},
                        {"pigment_apply", "wc18"}, {"substrate_distort", "mnpr"}, {"substrate_light", "wc18"},
                        {"substrate_light", "mnpr"}})
        EXPECT_TRUE(r.has(s, v)) << s << "/" << v;
    EXPECT_EQ(r.default_variant("pigment_apply").variant, "wc18");
    EXPECT_EQ(r.default_variant("substrate_light").variant, "wc18");
    for (auto* v : r.all()) {
        EXPECT_FALSE(v->doc.empty()) << v->key();
        EXPECT_TRUE(bool(v->run)) << v->key();
        for (auto& p : v->params) EXPECT_TRUE(p.def >= p.lo && p.def <= p.hi) << v->key() << "." << p.name;
    }
}

}  // namespace
}  // namespace aq::stylize
