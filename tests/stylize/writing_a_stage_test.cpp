// tests/stylize/writing_a_stage_test.cpp — the example of docs/stylize.md "Writing a stage", built
// and used as a newcomer would: one declaration and one kernel (between the BEGIN/END lines,
// which tests/docs_check.py compares with the doc's code block), then the reference loop, the fast
// schedule, the registry entry, the parameter checking and the names a pipeline file and --set
// use, all from stylize/schedule/pointwise.h.
#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <random>

#include <gtest/gtest.h>

#include "core/maths.h"
#include "stylize/pipeline.h"

// BEGIN docs/stylize.md "Writing a stage"
#include "stylize/schedule/pointwise.h"

namespace example {
using namespace aq::stylize;

//! Colour towards its luminance (Rec. 709 weights, core/maths.h): c + (L - c) * amount.
struct Desaturate {
    struct Params {
        float amount = 0.5f;
    };
    static ParamTable<Params> params() {
        return ParamTable<Params>().f("amount", &Params::amount, 0, 1, "0 = unchanged, 1 = grey");
    }
    static constexpr std::array<int, 1> kInputs = {4};  // one RGBA input
    static constexpr int kOutput = 4;

    template <class F>  // one pixel (float) or eight (simd::v8f): the same operations
    static void pixel(const schedule::Pixel<F>* in, schedule::Pixel<F>& out, const Params& p) {
        const schedule::Pixel<F>& c = in[0];
        const F l = (aq::maths::kLumaR * c[0] + aq::maths::kLumaG * c[1]) + aq::maths::kLumaB * c[2];
        for (int k = 0; k < 3; ++k) out[k] = c[k] + (l - c[k]) * p.amount;
        out[3] = c[3];
    }
};

StageVariant desaturate() {
    return schedule::pointwise_variant<Desaturate>("desaturate", "luma", "colour towards its luminance",
                                                   {{"color", "color.adjusted", 4, false}},
                                                   {"color", "color.desaturated", 4, false});
}

}  // namespace example
// END docs/stylize.md "Writing a stage"

namespace aq::stylize {
namespace {

ImageF random_image(int w, int h, int c, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-0.25f, 1.25f);  // out of [0, 1] too: no clamping hides a lane
    ImageF img(w, h, c);
    for (std::size_t i = 0; i < img.num_values(); ++i) img.data()[i] = u(rng);
    return img;
}

ImageF run(const StageVariant& v, const ImageF& in, const ParamValues& pv, const Exec& ex) {
    ImageF out;
    StageIO io;
    io.in = {&in};
    io.out = {&out};
    v.run(io, pv, ex);
    return out;
}

bool same_bytes(const ImageF& a, const ImageF& b) {
    return a.same_size(b) && a.channels() == b.channels() &&
           std::equal(a.data(), a.data() + a.num_values(), b.data(),
                      [](float x, float y) { return std::bit_cast<std::uint32_t>(x) == std::bit_cast<std::uint32_t>(y); });
}

TEST(WritingAStage, TheKernelGivesTheSameBitsOnEveryScheduleAndThreadCount) {
    const StageVariant v = example::desaturate();
    const ParamValues pv = Registry::resolve_params(v, {{"amount", 0.37}}, "test");
    for (const auto& [w, h] : {std::pair{37, 13}, std::pair{8, 1}, std::pair{1, 9}, std::pair{256, 64}}) {
        const ImageF in = random_image(w, h, 4, unsigned(w * 100 + h));
        const ImageF ref = run(v, in, pv, Exec{1, Traversal::Reference});
        for (int threads : {1, 2, 0}) EXPECT_TRUE(same_bytes(run(v, in, pv, Exec{threads, Traversal::Fast}), ref)) << w << "x" << h;
    }
}

TEST(WritingAStage, TheKernelComputesWhatItSays) {
    const StageVariant v = example::desaturate();
    const ImageF in = random_image(19, 5, 4, 7);
    // amount 0: the input; amount 1: grey at the luminance, alpha kept.
    EXPECT_TRUE(same_bytes(run(v, in, Registry::resolve_params(v, {{"amount", 0.0}}, "t"), {}), in));
    const ImageF grey = run(v, in, Registry::resolve_params(v, {{"amount", 1.0}}, "t"), {});
    for (int y = 0; y < in.height(); ++y)
        for (int x = 0; x < in.width(); ++x) {
            const float l = maths::luminance(in.at(x, y, 0), in.at(x, y, 1), in.at(x, y, 2));
            for (int k = 0; k < 3; ++k) EXPECT_NEAR(grey.at(x, y, k), l, 1e-6f);
            EXPECT_EQ(grey.at(x, y, 3), in.at(x, y, 3));
        }
}

TEST(WritingAStage, TheDeclarationGivesTheRegistryEntryAndTheParameterChecks) {
    const StageVariant v = example::desaturate();
    EXPECT_EQ(v.key(), "desaturate/luma");
    ASSERT_EQ(v.params.size(), 1u);
    EXPECT_EQ(v.params[0].name, "amount");
    EXPECT_EQ(v.params[0].def, 0.5);
    EXPECT_EQ(v.params[0].hi, 1.0);
    EXPECT_EQ(Registry::resolve_params(v, {}, "t").at("amount"), 0.5);
    EXPECT_THROW(Registry::resolve_params(v, {{"amount", 2.0}}, "t"), Error);
    EXPECT_THROW(Registry::resolve_params(v, {{"amonut", 0.5}}, "t"), Error);
    // Once registered, inputs are checked against the declaration: a 3-channel image is refused.
    Registry registered;
    registered.add(v);
    const StageVariant& entry = registered.get("desaturate", "luma");
    const ImageF rgb = random_image(4, 4, 3, 1);
    EXPECT_THROW(run(entry, rgb, Registry::resolve_params(v, {}, "t"), {}), Error);
    // A parameter declared twice is refused when the variant is registered.
    StageVariant twice = v;
    twice.params.push_back(twice.params[0]);
    Registry r;
    EXPECT_THROW(r.add(twice), Error);
    // A declaration that disagrees with its kernel is refused when it is made.
    EXPECT_THROW(schedule::pointwise_variant<example::Desaturate>("d", "x", "", {{"color", "c", 3, false}}, {"color", "o", 4, false}),
                 Error);
}

TEST(WritingAStage, PipelineFilesAndSetNameIt) {
    register_runtime_stage(example::desaturate());
    Pipeline p = parse_pipeline(R"({"name": "t", "output": "out", "steps": [
      { "stage": "desaturate", "in": { "color": "in" }, "out": { "color": "out" } }]})",
                                "writing_a_stage_test");
    set_param(p, "desaturate.amount=0.8");
    EXPECT_THROW(set_param(p, "desaturate.amount=1.5"), Error);
    Targets t;
    const ImageF in = random_image(33, 7, 4, 3);
    t.set("in", in);
    run_pipeline(p, t);
    const StageVariant v = example::desaturate();
    EXPECT_TRUE(same_bytes(t.get("out"), run(v, in, Registry::resolve_params(v, {{"amount", 0.8}}, "t"), {})));
}

}  // namespace
}  // namespace aq::stylize
