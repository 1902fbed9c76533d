// tests/stylize/fusion_test.cpp — fused steps (stylize/stage.h Fusion): the fused run of
// color_ramp -> glaze (glaze computing its ramp rows from the lighting map) gives the bytes of the
// two steps run one after the other — lighting maps with NaN rows and infinities, ramps resampled
// from another size or read at the same size, both glaze variants, with and without a picture
// underneath, every traversal and thread count — and compile_pipeline fuses a pair only when
// nothing else needs the producer's outputs. In-place steps: when a step may write over its input.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "core/targets.h"
#include "stylize/pipeline.h"
#include "stylize/stages/color_ramp.h"
#include "stylize/stages/glaze.h"
#include "stylize/stages/stroke_ink.h"

namespace aq::stylize {
namespace {

bool same_bytes(const ImageF& a, const ImageF& b) {
    return a.width() == b.width() && a.height() == b.height() && a.channels() == b.channels() &&
           std::memcmp(a.data(), b.data(), a.num_values() * sizeof(float)) == 0;
}

ColorRampParams some_ramps() {
    ColorRampParams p;
    for (int k = 0; k < 4; ++k) {
        p.layer[k].color = {0.2f + 0.15f * k, 0.6f - 0.1f * k, 0.3f};
        p.layer[k].dark = p.layer[k].color * 0.5f;
        p.layer[k].alpha = 0.5f + 0.1f * k;
        p.layer[k].tone = 0.8f + 0.2f * k;
    }
    return p;
}

// A lighting map of lw x lh with values over [0, 1] and beyond, a row of NaN (when `nan`) and
// infinities; a wash of w x h painting each layer in a band of rows (zero rows elsewhere).
struct Inputs {
    ImageF lighting, wash, base;
};
Inputs inputs(int lw, int lh, int w, int h, bool nan) {
    Inputs in{ImageF(lw, lh, 1), ImageF(w, h, 4, 0.0f), ImageF(w, h, 4)};
    for (int y = 0; y < lh; ++y)
        for (int x = 0; x < lw; ++x) in.lighting.at(x, y, 0) = float((x * 7 + y * 3) % 13) / 10.0f - 0.1f;
    in.lighting.at(1, 2, 0) = std::numeric_limits<float>::infinity();
    in.lighting.at(3, 2, 0) = -std::numeric_limits<float>::infinity();
    if (nan) in.lighting.at(lw / 2, lh - 3, 0) = std::numeric_limits<float>::quiet_NaN();
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            for (int c = 0; c < 4; ++c) in.base.at(x, y, c) = 0.1f + 0.8f * float((x * 5 + y * 3 + c) % 9) / 9.0f;
            for (int k = 0; k < 4; ++k)
                if (y >= 5 * k && y < 5 * k + 8 && (x + k) % 4 != 0) in.wash.at(x, y, k) = float((x + y + k) % 7) / 5.0f;
        }
    return in;
}

TEST(Fusion, GlazeWithComputedRampsHasTheBytesOfColorRampThenGlaze) {
    const ColorRampParams rp = some_ramps();
    struct Size {
        int lw, lh, w, h;
    };
    for (const Size s : {Size{19, 17, 37, 31}, Size{37, 31, 37, 31}})  // resampled; the identity
        for (bool nan : {false, true}) {
            const Inputs in = inputs(s.lw, s.lh, s.w, s.h, nan);
            ImageF r[4];
            ImageF* const rout[4] = {&r[0], &r[1], &r[2], &r[3]};
            color_ramp(rout, in.lighting, rp, Exec::reference());
            const ImageF* const ramps[4] = {&r[0], &r[1], &r[2], &r[3]};
            ComputedRamps computed;
            computed.lighting = &in.lighting;
            computed.ramps = rp;
            for (bool mul : {true, false})
                for (const ImageF* base : {&in.base, static_cast<const ImageF*>(nullptr)}) {
                    ImageF want;
                    glaze(want, base, in.wash, ramps, glm::vec3(0.9f, 0.85f, 0.8f), mul, Exec::reference());
                    for (const Exec& ex : {Exec::reference(), Exec::fast(1), Exec::fast(2), Exec::fast(8)}) {
                        ImageF got;
                        glaze(got, base, in.wash, computed, glm::vec3(0.9f, 0.85f, 0.8f), mul, ex);
                        EXPECT_TRUE(same_bytes(got, want)) << s.lw << " nan " << nan << " mul " << mul << " base "
                                                           << (base != nullptr) << " threads " << ex.threads;
                    }
                }
        }
}

TEST(Fusion, NonFiniteRampParametersStillGiveTheUnfusedBytes) {
    // The API allows any parameters; with a NaN colour every computed ramp is NaN, so no layer may
    // be skipped where its wash is 0 (the unfused product is NaN there too).
    ColorRampParams rp = some_ramps();
    rp.layer[2].color.g = std::numeric_limits<float>::quiet_NaN();
    const Inputs in = inputs(19, 17, 37, 31, false);
    ImageF r[4];
    ImageF* const rout[4] = {&r[0], &r[1], &r[2], &r[3]};
    color_ramp(rout, in.lighting, rp, Exec::reference());
    const ImageF* const ramps[4] = {&r[0], &r[1], &r[2], &r[3]};
    ImageF want, got;
    glaze(want, &in.base, in.wash, ramps, glm::vec3(1.0f), true, Exec::reference());
    ComputedRamps computed{&in.lighting, rp};
    glaze(got, &in.base, in.wash, computed, glm::vec3(1.0f), true, Exec::fast(2));
    EXPECT_TRUE(same_bytes(got, want));
}

// A pipeline of one color_ramp and one glaze over external lighting and wash targets.
Pipeline ramp_glaze_pipeline(const std::string& extra_step) {
    const std::string json = R"({"name": "t", "output": "out", "steps": [
      { "stage": "color_ramp", "id": "ramp", "in": { "lighting": "light" },
        "out": { "ramp0": "r0", "ramp1": "r1", "ramp2": "r2", "ramp3": "r3" } },
      { "stage": "glaze", "in": { "wash": "wash", "ramp0": "r0", "ramp1": "r1", "ramp2": "r2", "ramp3": "r3" },
        "out": { "color": "out" } })" + extra_step + "]}";
    return parse_pipeline(json, "fusion_test");
}

Targets pipeline_inputs(const Inputs& in) {
    Targets t;
    t.set("light", in.lighting);
    t.set("wash", in.wash);
    return t;
}

TEST(Fusion, ThePipelineFusesColorRampAndGlazeWithTheSameOutput) {
    const Inputs in = inputs(37, 31, 37, 31, true);
    const CompiledPipeline c = compile_pipeline(ramp_glaze_pipeline(""));
    ASSERT_EQ(c.fused_with_next.size(), 2u);
    ASSERT_NE(c.fused_with_next[0], nullptr);
    EXPECT_EQ(c.fused_with_next[1], nullptr);
    for (int threads : {1, 2, 8}) {
        Targets plain = pipeline_inputs(in), fused = pipeline_inputs(in);
        RunOptions ro;
        ro.exec = Exec::fast(threads);
        run_pipeline(c, plain, ro);
        ro.fuse = true;
        std::vector<double> ms;
        ro.step_ms = &ms;
        run_pipeline(c, fused, ro);
        EXPECT_TRUE(same_bytes(fused.get("out"), plain.get("out"))) << threads;
        EXPECT_TRUE(plain.has("r0") && plain.has("r3"));
        EXPECT_FALSE(fused.has("r0") || fused.has("r1") || fused.has("r2") || fused.has("r3"));  // never written
        ASSERT_EQ(ms.size(), 2u);
        EXPECT_EQ(ms[0], 0.0);  // the producer ran inside its consumer
    }
}

TEST(Fusion, APairIsNotFusedWhenItsIntermediatesAreNeeded) {
    // A ramp read by a later step, or a ramp that is the pipeline's output: no fusion.
    const CompiledPipeline read_later = compile_pipeline(ramp_glaze_pipeline(R"(,
      { "stage": "glaze", "id": "again", "in": { "wash": "wash", "ramp0": "r1", "ramp1": "r1", "ramp2": "r1", "ramp3": "r1" },
        "out": { "color": "out2" } })"));
    EXPECT_EQ(read_later.fused_with_next[0], nullptr);
    Pipeline p = ramp_glaze_pipeline("");
    p.output = "r2";
    EXPECT_EQ(compile_pipeline(p).fused_with_next[0], nullptr);
    // The consumer reading a ramp through a port that is not the link: no fusion either.
    const CompiledPipeline crossed = compile_pipeline(parse_pipeline(R"({"name": "t", "output": "out", "steps": [
      { "stage": "color_ramp", "in": { "lighting": "light" }, "out": { "ramp0": "r0", "ramp1": "r1", "ramp2": "r2", "ramp3": "r3" } },
      { "stage": "glaze", "in": { "wash": "wash", "ramp0": "r1", "ramp1": "r0", "ramp2": "r2", "ramp3": "r3" },
        "out": { "color": "out" } }]})", "fusion_test"));
    EXPECT_EQ(crossed.fused_with_next[0], nullptr);
    // Unfused pipelines still run with fuse set, writing every intermediate.
    const Inputs in = inputs(37, 31, 37, 31, false);
    Targets t = pipeline_inputs(in);
    RunOptions ro;
    ro.fuse = true;
    run_pipeline(read_later, t, ro);
    EXPECT_TRUE(t.has("r0") && t.has("out2"));
}

// In-place steps (StageVariant::in_place_input; stroke_ink declares color -> color): a step runs on
// its input's image only when that input is an intermediate no one reads afterwards, and the
// output has the bytes of the run on separate images.
Pipeline two_inks(const std::string& extra, const std::string& output = "out") {
    return parse_pipeline(R"({"name": "t", "output": ")" + output + R"(", "steps": [
      { "stage": "stroke_ink", "id": "first", "in": { "color": "base", "ink": "ink1" }, "out": { "color": "inked" } },
      { "stage": "stroke_ink", "id": "second", "in": { "color": "inked", "ink": "ink2" }, "out": { "color": "out" } })" +
                              extra + "]}",
                          "fusion_test");
}

TEST(InPlace, AStepRunsOnItsInputsImageOnlyWhenTheInputIsADeadIntermediate) {
    const CompiledPipeline c = compile_pipeline(two_inks(""));
    ASSERT_EQ(c.in_place.size(), 2u);
    EXPECT_EQ(c.in_place[0], -1) << "a G-buffer target is not overwritten";
    EXPECT_EQ(c.in_place[1], 0) << "'inked' is read by the second step alone";
    EXPECT_EQ(compile_pipeline(two_inks(R"(,
      { "stage": "stroke_ink", "id": "third", "in": { "color": "inked", "ink": "ink1" }, "out": { "color": "out2" } })"))
                  .in_place[1], -1) << "read later";
    EXPECT_EQ(compile_pipeline(two_inks("", "inked")).in_place[1], -1) << "the pipeline's output";

    const Inputs in = inputs(37, 31, 37, 31, false);
    for (int threads : {1, 2, 8}) {
        Targets plain, in_place;
        for (Targets* t : {&plain, &in_place}) {
            t->set("base", in.base);
            ImageF ink1(37, 31, 1, 0.0f), ink2(37, 31, 1, 0.0f);
            for (int y = 0; y < 31; ++y) ink1.at(y % 37, y, 0) = 0.7f;
            for (int x = 0; x < 37; x += 2) ink2.at(x, 7, 0) = 1.0f;
            t->set("ink1", std::move(ink1));
            t->set("ink2", std::move(ink2));
        }
        RunOptions ro;
        ro.exec = Exec::fast(threads);
        run_pipeline(c, plain, ro);
        ro.in_place = true;
        run_pipeline(c, in_place, ro);
        EXPECT_TRUE(same_bytes(in_place.get("out"), plain.get("out"))) << threads;
        EXPECT_TRUE(plain.has("inked"));
        EXPECT_FALSE(in_place.has("inked")) << "its image became the output";
        EXPECT_TRUE(same_bytes(in_place.get("base"), in.base)) << "the G-buffer is untouched";
    }
}

TEST(InPlace, RegistryRefusesAPairOfPortsItDoesNotHave) {
    auto variant = [](const std::string& in, const std::string& out, int out_channels) {
        StageVariant v;
        v.stage = "t";
        v.variant = in + "_" + out;
        v.inputs = {{"color", "color", 4, false}};
        v.outputs = {{"color", "out", out_channels, false}};
        v.run = [](StageIO&, const ParamValues&, const Exec&) {};
        v.in_place_input = in;
        v.in_place_output = out;
        return v;
    };
    Registry r;
    EXPECT_NO_THROW(r.add(variant("color", "color", 4)));
    EXPECT_THROW(r.add(variant("colour", "color", 4)), Error) << "no such input";
    EXPECT_THROW(r.add(variant("color", "", 4)), Error) << "no output named";
    EXPECT_THROW(r.add(variant("color", "color", 1)), Error) << "channel counts differ";
}

TEST(Fusion, RegistryRefusesFusionsThatDropAnOutputOrMismatchAPort) {
    Registry r = builtin_registry();
    Fusion f;
    f.producer = "color_ramp/gooch";
    f.consumer = "shadow_layer/multiplicative";  // no such fusion is registered
    f.run = [](const StageIO&, const ParamValues&, StageIO&, const ParamValues&, const Exec&) {};
    f.links = {{"ramp0", "color"}};  // ramp1..3 would be lost
    EXPECT_THROW(r.add_fusion(f), Error);
    f.links = {{"ramp0", "color"}, {"ramp1", "shadow"}, {"ramp2", "color"}, {"ramp3", "color"}};
    EXPECT_THROW(r.add_fusion(f), Error);  // ramp1 has 4 channels, shadow 1
    f.links = {{"ramp0", "color"}, {"ramp1", "nope"}, {"ramp2", "color"}, {"ramp3", "color"}};
    EXPECT_THROW(r.add_fusion(f), Error);  // no such port
    f.links = {{"ramp0", "color"}, {"ramp1", "color"}, {"ramp2", "color"}, {"ramp3", "color"}};
    EXPECT_NO_THROW(r.add_fusion(f));
    EXPECT_THROW(r.add_fusion(f), Error);  // twice
    EXPECT_NE(builtin_registry().fusion("color_ramp/gooch", "glaze/multiplicative"), nullptr);
    EXPECT_NE(builtin_registry().fusion("color_ramp/gooch", "glaze/over"), nullptr);
}

}  // namespace
}  // namespace aq::stylize
