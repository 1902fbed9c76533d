// tests/stylize/declare_test.cpp — a stage's parameters written once (stylize/stage.h ParamTable
// over the stage's own struct: nested members, arrays, enums and any integer field) and its
// registry entry from a declaration and one typed run (stylize/declare.h): port checks, and a
// compiled step that binds its values once.
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "stylize/declare.h"
#include "stylize/pipeline.h"

namespace aq::stylize {
namespace {

enum class Mode { First, Second, Third };

struct Inner {
    float gain = 0.25f;
    glm::vec3 colour{0.1f, 0.2f, 0.3f};
};

struct Params {
    Inner inner;
    Inner layers[2] = {{0.5f, {0.4f, 0.5f, 0.6f}}, {0.75f, {0.7f, 0.8f, 0.9f}}};
    Mode mode = Mode::Second;
    std::uint32_t seed = 7;
    bool flag = true;
};

ParamTable<Params> table() {
    return ParamTable<Params>()
        .f("gain", field_path(&Params::inner, &Inner::gain), 0, 1, "nested member")
        .f("blue", field_path(&Params::inner, &Inner::colour, 2), 0, 1, "nested vector component")
        .f("layer1_green", field_path(&Params::layers, 1, &Inner::colour, 1), 0, 1, "array element's component")
        .e("mode", &Params::mode, {"first", "second", "third"}, "an enum field")
        .i("seed", &Params::seed, 0, 1000, "an unsigned field")
        .b("flag", &Params::flag, "a bool");
}

const ParamDesc& desc(const ParamTable<Params>& t, const std::string& name) {
    const ParamDesc* d = find_param(t.descs(), name);
    if (!d) throw Error("no parameter " + name);
    return *d;
}

TEST(ParamTable, DefaultsComeFromTheStructThroughPathsAndEnums) {
    const ParamTable<Params> t = table();
    EXPECT_EQ(desc(t, "gain").def, double(0.25f));
    EXPECT_EQ(desc(t, "blue").def, double(0.3f));
    EXPECT_EQ(desc(t, "layer1_green").def, double(0.8f));
    EXPECT_EQ(desc(t, "mode").def, 1.0);
    EXPECT_EQ(desc(t, "mode").kind, ParamKind::Int);
    EXPECT_EQ(desc(t, "mode").hi, 2.0);
    EXPECT_EQ(desc(t, "seed").def, 7.0);
    EXPECT_EQ(desc(t, "flag").kind, ParamKind::Bool);
    EXPECT_EQ(desc(t, "flag").def, 1.0);
}

TEST(ParamTable, ValuesLandInTheirFieldsAndNowhereElse) {
    const ParamTable<Params> t = table();
    const Params p = t.from({{"gain", 0.5}, {"blue", 0.125}, {"layer1_green", 0.0625}, {"mode", 2}, {"seed", 999}, {"flag", 0}});
    EXPECT_EQ(p.inner.gain, 0.5f);
    EXPECT_EQ(p.inner.colour.b, 0.125f);
    EXPECT_EQ(p.inner.colour.r, 0.1f) << "the other components keep their defaults";
    EXPECT_EQ(p.layers[1].colour.g, 0.0625f);
    EXPECT_EQ(p.layers[0].colour.g, 0.5f) << "the other element keeps its default";
    EXPECT_EQ(p.mode, Mode::Third);
    EXPECT_EQ(p.seed, 999u);
    EXPECT_FALSE(p.flag);
}

// The registry entry: the table's parameters, the ports checked before the run (Registry::add),
// the typed values of the pipeline's map given to the run.
const StageVariant& example(Registry& reg, int* runs, Params* seen) {
    reg.add(declare({.stage = "declare_example",
                    .variant = "v",
                    .doc = "test",
                    .inputs = {{"a", "a", 4, false}, {"b", "b", 1, true}},
                    .outputs = {{"out", "out", 1, false}}},
                   table(), [runs, seen](StageIO& io, const Params& p, const Exec&) {
                       ++*runs;
                       *seen = p;
                       ensure_output(*io.out[0], 1, 1, 1);
                   }));
    return reg.get("declare_example", "v");
}

TEST(Declare, TheEntryChecksItsPortsAndRunsWithTypedValues) {
    int runs = 0;
    Params seen;
    Registry reg;
    const StageVariant& v = example(reg, &runs, &seen);
    EXPECT_EQ(v.params.size(), table().descs().size());
    ParamValues pv = Registry::resolve_params(v, {{"gain", 0.75}, {"mode", 0}}, "test");
    ImageF a(2, 2, 4), b1(2, 2, 1), b3(2, 2, 3), out;
    StageIO io{{&a, nullptr}, {&out}, nullptr};
    v.run(io, pv, Exec::reference());
    EXPECT_EQ(runs, 1) << "an absent optional input is fine";
    EXPECT_EQ(seen.inner.gain, 0.75f);
    EXPECT_EQ(seen.mode, Mode::First);
    EXPECT_EQ(seen.seed, 7u) << "defaults of the resolved map";

    StageIO wrong{{&a, &b3}, {&out}, nullptr};
    try {
        v.run(wrong, pv, Exec::reference());
        ADD_FAILURE() << "a 3-channel image on a 1-channel port ran";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("declare_example/v: input 'b' has 3 channels, expected 1"), std::string::npos)
            << e.what();
    }
    StageIO missing{{nullptr, &b1}, {&out}, nullptr};
    EXPECT_THROW(v.run(missing, pv, Exec::reference()), Error);
    StageIO no_output{{&a, &b1}, {nullptr}, nullptr};
    EXPECT_THROW(v.run(no_output, pv, Exec::reference()), Error);
    EXPECT_THROW(v.bound(pv)(wrong, Exec::reference()), Error) << "the bound step is checked too";
    EXPECT_EQ(runs, 1) << "no run after a failed check";
}

// Ports' size relations (Port::size, Port::like), checked with the channels before the run.
TEST(Declare, SizeRelationsOfPortsAreCheckedBeforeTheRun) {
    int runs = 0;
    Registry reg;
    reg.add(declare({.stage = "sized_example",
                     .variant = "v",
                     .doc = "test",
                     .inputs = {{"a", "a", 1, false},
                                {"same", "same", 1, false, SizeRule::Same, "a"},
                                {"half", "half", 1, true, SizeRule::FullOrHalf, "a"}},
                     .outputs = {{"out", "out", 1, false}}},
                    ParamTable<Params>(), [&runs](StageIO& io, const Params&, const Exec&) {
                        ++runs;
                        ensure_output(*io.out[0], 1, 1, 1);
                    }));
    const StageVariant& v = reg.get("sized_example", "v");
    const ParamValues pv = Registry::resolve_params(v, {}, "test");
    ImageF a(5, 3, 1), same(5, 3, 1), other(4, 3, 1), half(3, 2, 1), quarter(2, 1, 1), out;
    StageIO ok{{&a, &same, &half}, {&out}, nullptr};
    v.run(ok, pv, Exec::reference());
    StageIO full{{&a, &same, &same}, {&out}, nullptr};
    v.run(full, pv, Exec::reference());
    StageIO absent{{&a, &same, nullptr}, {&out}, nullptr};
    v.run(absent, pv, Exec::reference());
    EXPECT_EQ(runs, 3) << "the same size, full or half (ceil(5/2) x ceil(3/2)), an absent optional input";
    auto message = [&](StageIO io) {
        try {
            v.run(io, pv, Exec::reference());
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("ran");
    };
    EXPECT_EQ(message({{&a, &other, &half}, {&out}, nullptr}), "sized_example/v: input 'same' is 4x3, expected 5x3 like 'a'");
    EXPECT_NE(message({{&a, &same, &quarter}, {&out}, nullptr}).find("input 'half' is 2x1, expected the size of 'a' (5x3) or half"),
              std::string::npos);
    EXPECT_EQ(runs, 3) << "no run after a failed check";
}

TEST(Declare, ASizeRelationMustNameAnotherInput) {
    auto add = [](std::vector<Port> inputs) {
        Registry reg;
        reg.add(declare({.stage = "bad_size", .variant = "v", .doc = "test", .inputs = std::move(inputs),
                         .outputs = {{"out", "out", 1, false}}},
                        ParamTable<Params>(), [](StageIO&, const Params&, const Exec&) {}));
    };
    EXPECT_THROW(add({{"a", "a", 1, false}, {"b", "b", 1, false, SizeRule::Same, "c"}}), Error) << "no input c";
    EXPECT_THROW(add({{"a", "a", 1, false, SizeRule::Same, "a"}}), Error) << "itself";
    EXPECT_THROW(add({{"a", "a", 1, false}, {"b", "b", 1, false, SizeRule::Same, ""}}), Error) << "a rule without a port";
    EXPECT_THROW(add({{"a", "a", 1, false}, {"b", "b", 1, false, SizeRule::Any, "a"}}), Error) << "a port without a rule";
    EXPECT_NO_THROW(add({{"a", "a", 1, false}, {"b", "b", 1, false, SizeRule::FullOrHalf, "a"}}));
}

TEST(Declare, ABoundStepKeepsTheValuesItWasBoundWith) {
    int runs = 0;
    Params seen;
    Registry reg;
    const StageVariant& v = example(reg, &runs, &seen);
    ParamValues pv = Registry::resolve_params(v, {{"seed", 42}}, "test");
    const StepFn step = v.bound(pv);
    pv["seed"] = 43;  // the map a compiled step came from changes afterwards: the step does not
    ImageF a(2, 2, 4), out;
    StageIO io{{&a, nullptr}, {&out}, nullptr};
    step(io, Exec::reference());
    EXPECT_EQ(seen.seed, 42u);
    // A variant without bind (a hand-written run) is bound by keeping its map.
    StageVariant plain;
    plain.stage = "plain";
    plain.variant = "v";
    double got = -1;
    plain.run = [&got](StageIO&, const ParamValues& p, const Exec&) { got = p.at("x"); };
    plain.bound({{"x", 3.0}})(io, Exec::reference());
    EXPECT_EQ(got, 3.0);
}

// Cross-field rules (StageVariant::validate) are checked when the pipeline compiles, with the
// step named; each --set on its own may pass through a state that breaks them.
TEST(Declare, CrossFieldRulesAreCheckedWhenThePipelineCompiles) {
    Pipeline p = parse_pipeline(R"({"steps": [{"stage": "edge_darken", "variant": "dog"}]})", "rules.json");
    set_param(p, "edge_darken.smooth_low=0.9");  // above the default smooth_high: fine for now
    try {
        validate_pipeline(p);
        ADD_FAILURE() << "smooth_low above smooth_high compiled";
    } catch (const Error& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("rules.json: steps[0].params (edge_darken/dog)"), std::string::npos) << m;
        EXPECT_NE(m.find("smooth_high must exceed smooth_low"), std::string::npos) << m;
    }
    set_param(p, "edge_darken.smooth_high=0.95");
    EXPECT_NO_THROW(validate_pipeline(p));
    Pipeline q = parse_pipeline(R"({"steps": [{"stage": "adjust", "params": {"depth_near": 5, "depth_far": 5}}]})", "a.json");
    EXPECT_THROW(validate_pipeline(q), Error);
    // The variants with rules: the stage's own check, run by its function too.
    for (const char* key : {"adjust/mnpr", "edge_darken/dog"}) {
        const std::string k = key;
        const StageVariant& v = builtin_registry().get(k.substr(0, k.find('/')), k.substr(k.find('/') + 1));
        EXPECT_TRUE(bool(v.validate)) << key;
        EXPECT_NO_THROW(v.validate(Registry::resolve_params(v, {}, "defaults"))) << key << ": the defaults keep the rules";
    }
    for (const char* variant : {"blurred", "blurred_rgba8", "binary"}) {
        const StageVariant& v = builtin_pass_registry().get("particles", variant);
        ASSERT_TRUE(bool(v.validate));
        EXPECT_NO_THROW(v.validate(Registry::resolve_params(v, {}, "defaults")));
        EXPECT_THROW(v.validate(Registry::resolve_params(v, {{"t0", 0.5}, {"t1", 0.1}}, "t")), Error) << "t0 > t1";
        EXPECT_THROW(v.validate(Registry::resolve_params(v, {{"quantity", 10000}, {"height", 10000}}, "t")), Error)
            << "more particles than the limit";
    }
}

// Every built-in stage and pass is declared (stylize/declare.h): a compiled pipeline keeps typed,
// bound steps, not a map converted on every run.
TEST(Declare, EveryBuiltInVariantBindsItsParameters) {
    for (const Registry* reg : {&builtin_registry(), &builtin_pass_registry()})
        for (const StageVariant* v : reg->all()) EXPECT_TRUE(bool(v->bind)) << v->key();
}

}  // namespace
}  // namespace aq::stylize
