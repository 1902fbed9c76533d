// tests/stylize/stage_b_registry_test.cpp — stage group B through the registry: names, ports,
// defaults, and every variant run on synthetic targets of the declared shapes (incl. NaN/Inf),
// reference vs fast traversal.
#include <cmath>
#include <cstring>
#include <set>

#include <gtest/gtest.h>

#include "stylize/paper.h"
#include "stylize/stage.h"
#include "stylize/stages/toolkit.h"
#include "tests/stylize/stage_b_test_util.h"

namespace aq::stylize {
namespace {

TEST(StageBRegistry, EveryStageAndVariantIsRegistered) {
    const Registry& r = builtin_registry();
    for (auto [s, v] : {std::pair{"edge_darken", "dog"}, {"edge_darken", "rgbd"}, {"gaps_overlaps", "wc18"},
                        {"pigment_apply", "wc17"}, {"pigment_apply", "wc18"}, {"substrate_distort", "mnpr"},
                        {"substrate_light", "wc18"}, {"substrate_light", "mnpr"}})
        EXPECT_TRUE(r.has(s, v)) << s << "/" << v;
    EXPECT_EQ(r.default_variant("pigment_apply").variant, "wc18");
    EXPECT_EQ(r.default_variant("substrate_light").variant, "wc18");
}

TEST(StageBRegistry, RunsOnSyntheticTargetsWithBothTraversals) {
    const Registry& r = builtin_registry();
    const int w = 70, h = 66;
    const ImageF paper = testb::noise(w, h, 3, 0.0f, 1.0f, 81);
    Globals g;
    g.substrate_color = {0.95f, 0.93f, 0.9f};
    g.paper = &paper;
    for (const char* stage : {"edge_darken", "gaps_overlaps", "pigment_apply", "substrate_distort", "substrate_light"})
        for (const StageVariant* v : r.variants(stage)) {
            for (bool poisoned : {false, true}) {
                std::vector<ImageF> ins;
                std::uint32_t seed = 100;
                for (const Port& p : v->inputs) {
                    const bool half = p.name == "blurred" || p.name == "bleed";
                    ImageF img = testb::noise(half ? (w + 1) / 2 : w, half ? (h + 1) / 2 : h, p.channels,
                                              p.name.rfind("ctrl", 0) == 0 ? -1.0f : 0.0f, 1.0f, seed++);
                    ins.push_back(poisoned ? testb::poison(img, 5 + int(seed % 7)) : img);
                }
                const ParamValues pv = Registry::resolve_params(*v, {}, "test");
                std::vector<ImageF> ref(v->outputs.size()), fast(v->outputs.size());
                for (auto* outs : {&ref, &fast}) {
                    StageIO io;
                    for (auto& i : ins) io.in.push_back(&i);
                    for (auto& o : *outs) io.out.push_back(&o);
                    io.globals = &g;
                    v->run(io, pv, outs == &ref ? Exec::reference() : Exec::fast(2));
                }
                for (std::size_t k = 0; k < ref.size(); ++k) {
                    ASSERT_EQ(ref[k].width(), w) << v->key();
                    ASSERT_EQ(ref[k].channels(), v->outputs[k].channels) << v->key();
                    EXPECT_TRUE(testb::same_values(ref[k], fast[k]))
                        << v->key() << (poisoned ? " (NaN/Inf inputs)" : "");
                }
            }
        }
}

TEST(StageBRegistry, OptionalBleedInputMayBeAbsent) {
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

TEST(StageBMath, FastPowMatchesStdPow) {
    double worst = 0;
    for (int i = 1; i <= 2000; ++i) {
        const float x = std::pow(10.0f, -6.0f * float(i) / 2000.0f);  // 1e-6 .. 1
        for (float d : {0.0f, 0.3f, 1.0f, 1.0001f, 1.5f, 2.4f, 3.7f, 7.0f, 12.5f, 30.0f}) {
            const double want = std::pow(double(x), double(d));
            const double got = pow_c(x, d);
            if (want > 1e-30) worst = std::max(worst, std::fabs(got - want) / want);
        }
    }
    EXPECT_LT(worst, 1e-5);  // relative; far below an 8-bit output step
    EXPECT_EQ(pow_c(0.0f, 2.0f), 0.0f);
    EXPECT_EQ(pow_c(-0.5f, 2.0f), 0.0f);
    EXPECT_EQ(pow_c(1.0f, 7.0f), 1.0f);
    EXPECT_EQ(pow_c(0.3f, 1.0f), 0.3f);
    EXPECT_TRUE(std::isnan(pow_c(std::nanf(""), 2.0f)));
    EXPECT_TRUE(std::isnan(pow_c(0.5f, std::nanf(""))));
    EXPECT_TRUE(std::isinf(pow_c(INFINITY, 2.0f)));
    for (int i = 1; i < 1000; ++i) {  // darkening never brightens: x^d <= x for d >= 1
        const float x = float(i) / 1000.0f;
        EXPECT_LE(pow_c(x, 1.0000001f), x);
    }
}

}  // namespace
}  // namespace aq::stylize
