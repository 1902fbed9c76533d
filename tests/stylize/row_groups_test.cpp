// tests/stylize/row_groups_test.cpp — row groups (stylize/pipeline.h RowGroup; docs/stylize.md
// "Row groups"): consecutive steps run band by band give every target the bytes of the steps run
// one after the other — every image preset, thread counts 1, 2 and 8, bands of 1, 5 and 16 rows,
// images of one stripe and of several, with in-place steps, released intermediates and a frame
// loop's reused outputs — and every variant that declares a row halo computes exactly the rows of
// its window, reading its inputs only within the halo.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "core/hash.h"
#include "core/targets.h"
#include "stylize/paper.h"
#include "stylize/pipeline.h"
#include "stylize/stage.h"
#include "tests/synthetic_gbuffer.h"

namespace aq::stylize {
namespace {

using Hashes = std::map<std::string, std::string>;

Hashes hashes(const Targets& t) {
    Hashes h;
    for (const auto& [name, img] : t.all()) h[name] = sha256_hex(img);
    return h;
}

struct Mode {
    bool in_place = false, release = false;
};

//! Two frames of `preset` (the second reusing the first's outputs), all targets' hashes of each.
std::vector<Hashes> run_frames(const CompiledPipeline& c, int w, int h, int threads, bool groups, int band, Mode m) {
    const Targets g = test::synthetic_gbuffer(w, h);
    Targets t = g;
    RunOptions o;
    o.exec = Exec::fast(threads);
    o.row_groups = groups;
    o.band_rows = band;
    o.in_place = m.in_place;
    o.release_dead = m.release;
    o.reuse_outputs = true;
    std::vector<Hashes> out;
    for (int f = 0; f < 2; ++f) {
        for (const auto& [name, img] : g.all()) t.get_mut(name) = img;  // the same G-buffer, the outputs kept
        run_pipeline(c, t, o);
        out.push_back(hashes(t));
    }
    return out;
}

std::vector<std::string> image_presets() {
    std::vector<std::string> v;
    for (const std::string& p : preset_names())
        if (!compile_pipeline(load_pipeline(p)).has_passes) v.push_back(p);
    return v;
}

TEST(RowGroups, WatercolorPresetsHaveGroups) {
    // The compiled pipeline decides the grouping (issue 13 item 4): the three watercolor systems
    // run some of their steps in bands.
    for (const char* preset : {"wc16", "wc17", "wc18"}) {
        const CompiledPipeline c = compile_pipeline(load_pipeline(preset));
        EXPECT_FALSE(c.row_groups.empty()) << preset;
        for (const RowGroup& g : c.row_groups) {
            EXPECT_GE(g.last, g.first + 1) << preset;
            ASSERT_EQ(g.depth.size(), g.last - g.first + 1) << preset;
            for (std::size_t s = g.first; s <= g.last; ++s) EXPECT_TRUE(c.steps[s].variant->row_halo) << preset;
        }
    }
}

TEST(RowGroups, BandsGiveTheBytesOfStepByStep) {
    for (const std::string& preset : image_presets()) {
        const CompiledPipeline c = compile_pipeline(load_pipeline(preset));
        for (const auto& [w, h] : {std::pair{96, 70}, std::pair{150, 300}})
            for (const Mode m : {Mode{false, false}, Mode{true, false}, Mode{true, true}}) {
                const std::vector<Hashes> ref = run_frames(c, w, h, 1, false, 16, m);
                for (int threads : {1, 2, 8})
                    for (int band : {1, 5, 16}) {
                        SCOPED_TRACE(preset + " " + std::to_string(w) + "x" + std::to_string(h) + " threads " +
                                     std::to_string(threads) + " band " + std::to_string(band) + " in_place " +
                                     std::to_string(m.in_place) + " release " + std::to_string(m.release));
                        const std::vector<Hashes> got = run_frames(c, w, h, threads, true, band, m);
                        ASSERT_EQ(got.size(), ref.size());
                        for (std::size_t f = 0; f < got.size(); ++f) {
                            EXPECT_EQ(got[f].size(), ref[f].size()) << "frame " << f;
                            for (const auto& [name, hash] : ref[f]) {
                                const auto it = got[f].find(name);
                                ASSERT_NE(it, got[f].end()) << "frame " << f << " lacks " << name;
                                EXPECT_EQ(it->second, hash) << "frame " << f << " target " << name;
                            }
                        }
                    }
            }
    }
}

// A step computing in place over an image that an earlier step of its group reads with a halo
// (pigment_density over the bleed image that edge_detect reads 3 x 3), the image written before
// the group: the step must stay behind the reader, and the reader keeps reading the moved image.
TEST(RowGroups, InPlaceOverAnInputAnotherStepReadsWithAHalo) {
    const Pipeline p = parse_pipeline(R"({"name": "t", "steps": [
        {"stage": "bleed", "variant": "mnpr", "in": {"color": "color", "depth": "depth.linear"}, "out": {"bleed": "soft"}},
        {"stage": "edge_detect", "variant": "rgbd_sobel", "in": {"color": "soft", "depth": "depth.linear"}},
        {"stage": "pigment_density", "variant": "mnpr", "in": {"color": "soft"}, "out": {"color": "out"}}],
        "output": "out"})",
                                      "inline");
    const CompiledPipeline c = compile_pipeline(p);
    ASSERT_EQ(c.row_groups.size(), 1u);
    EXPECT_EQ(c.row_groups[0].first, 1u);
    EXPECT_EQ(c.in_place[2], 0);  // pigment_density over "soft"
    EXPECT_EQ(c.row_groups[0].depth[1], 1);  // behind edge_detect by its halo
    for (int threads : {1, 2})
        for (int band : {1, 7}) {
            SCOPED_TRACE(std::to_string(threads) + " threads, band " + std::to_string(band));
            const std::vector<Hashes> ref = run_frames(c, 90, 200, 1, false, band, Mode{true, false});
            const std::vector<Hashes> got = run_frames(c, 90, 200, threads, true, band, Mode{true, false});
            EXPECT_EQ(got, ref);
            EXPECT_EQ(got[0].count("soft"), 0u);  // computed over in place
        }
}

// Every variant with a row halo, on the synthetic inputs at 70 x 61 with its default parameters:
// windows of random heights in random order give the bytes of the whole run; a window writes no
// row outside itself (a poisoned output keeps its poison there) and reads no input row beyond
// the halo (inputs poisoned there give the same window rows); an empty window writes nothing.
TEST(RowGroups, EveryWindowedVariantComputesItsWindowFromItsHalo) {
    const int w = 70, h = 61;
    const float kPoison = std::numeric_limits<float>::quiet_NaN();
    std::mt19937 rng(7);
    int checked = 0;
    for (const StageVariant* v : builtin_registry().all()) {
        if (!v->row_halo) continue;
        SCOPED_TRACE(v->key());
        ++checked;
        const ParamValues pv = Registry::resolve_params(*v, {}, "test");
        const int halo = v->row_halo(pv);
        ASSERT_GE(halo, 0);
        std::vector<ImageF> in;
        std::uint32_t seed = 3;
        for (const Port& port : v->inputs) in.push_back(test::synthetic_target(port.default_target, port.channels, w, h, seed++));
        const ImageF paper = prepare_paper(load_pipeline("wc18").paper, w, h);
        Globals g;
        g.paper = &paper;
        auto run = [&](const std::vector<ImageF>& inputs, std::vector<ImageF>& outs, const Exec& ex) {
            StageIO io;
            io.globals = &g;
            for (const ImageF& i : inputs) io.in.push_back(&i);
            for (ImageF& o : outs) io.out.push_back(&o);
            v->run(io, pv, ex);
        };
        std::vector<ImageF> whole(v->outputs.size());
        run(in, whole, Exec::fast(1));
        // Windows of 1..9 rows covering every row once, run in a shuffled order.
        std::vector<std::pair<int, int>> windows;
        for (int y = 0; y < h;) {
            const int e = std::min(h, y + 1 + int(rng() % 9));
            windows.push_back({y, e});
            y = e;
        }
        std::shuffle(windows.begin(), windows.end(), rng);
        std::vector<ImageF> banded;
        for (const ImageF& o : whole) banded.push_back(ImageF(o.width(), o.height(), o.channels(), kPoison));
        run(in, banded, Exec::fast(2).rows(0, 0));  // an empty window: the poison stays
        for (std::size_t k = 0; k < banded.size(); ++k)
            for (std::size_t i = 0; i < banded[k].num_values(); ++i) ASSERT_TRUE(std::isnan(banded[k].data()[i]));
        for (const auto& [y0, y1] : windows) {
            std::vector<ImageF> before = banded;
            run(in, banded, Exec::fast(2).rows(y0, y1));
            for (std::size_t k = 0; k < banded.size(); ++k)  // rows outside the window untouched
                for (int y = 0; y < h; ++y)
                    if (y < y0 || y >= y1) {
                        ASSERT_EQ(std::memcmp(&banded[k].at(0, y, 0), &before[k].at(0, y, 0),
                                              sizeof(float) * std::size_t(w) * banded[k].channels()), 0)
                            << "window " << y0 << ".." << y1 << " wrote row " << y;
                    }
        }
        for (std::size_t k = 0; k < whole.size(); ++k)
            EXPECT_EQ(sha256_hex(banded[k]), sha256_hex(whole[k])) << "output " << k;
        // The halo is enough: inputs poisoned beyond it change no row of the window.
        for (const auto& [y0, y1] : {std::pair{0, 5}, std::pair{h / 2 - 3, h / 2 + 4}, std::pair{h - 6, h}}) {
            std::vector<ImageF> poisoned = in;
            for (ImageF& i : poisoned)
                for (int y = 0; y < h; ++y)
                    if (y < y0 - halo || y >= y1 + halo)
                        for (int x = 0; x < w; ++x)
                            for (int c = 0; c < i.channels(); ++c) i.at(x, y, c) = kPoison;
            std::vector<ImageF> outs;
            for (const ImageF& o : whole) outs.push_back(ImageF(o.width(), o.height(), o.channels(), 0.0f));
            run(poisoned, outs, Exec::fast(1).rows(y0, y1));
            for (std::size_t k = 0; k < outs.size(); ++k)
                for (int y = y0; y < y1; ++y)
                    ASSERT_EQ(std::memcmp(&outs[k].at(0, y, 0), &whole[k].at(0, y, 0),
                                          sizeof(float) * std::size_t(w) * outs[k].channels()), 0)
                        << "window " << y0 << ".." << y1 << " row " << y << " read beyond the halo " << halo;
        }
    }
    EXPECT_GE(checked, 10);
}

}  // namespace
}  // namespace aq::stylize
