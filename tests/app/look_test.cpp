// tests/app/look_test.cpp — issue 10: a bare glTF rendered with default options looks like a
// watercolor painting on paper in every style (docs/look.md). Runs the `aquarelle` CLI on shared
// models (bare, default options, 640x480) in wc16, wc17, wc18 and `--style none`, inside this
// test's own output folder, and measures:
//   paper    mean Rec. 709 luminance and its standard deviation over unpainted paper: pixels
//            farther than kPaperMargin from the object (coverage from the `none` image's alpha);
//   inside   mean over the object (eroded by kInsideErode px) of the largest per-channel
//            |stylised - none| difference;
//   edges    darkening (luminance of stylised - none) on the ring 1..kEdgeRing px inside the
//            silhouette against the ring kInnerFrom..kInnerTo px inside: the silhouette ring must
//            be darker by kMinEdgeContrast. Relative to `none` so the model's own shading (a lit
//            rim) does not count.
//
// look_measure (Look.MeasureEveryModel, not run by CTest) measures every shared glTF model and prints the table (docs/look.md numbers);
// AQ_LOOK_EXE=PATH measures another aquarelle binary (e.g. an older build, for "before");
// AQ_LOOK_EXTRA="OPTIONS" adds options to every stylised render (e.g. "--bypass edge_darken").
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/image.h"
#include "core/io.h"
#include "tests/test_support.h"

namespace aq {
namespace {

// Thresholds (docs/look.md "Acceptance").
constexpr double kPaperLumMin = 0.85;        //!< issue 10: photographs of watercolor paper
constexpr double kPaperLumMax = 0.97;
constexpr double kMinPaperStd = 0.012;       //!< luminance std-dev over the paper: ~3 8-bit levels
constexpr double kMinInsideDiff = 0.03;      //!< mean max-channel |stylised - none| on the object
constexpr double kMinEdgeContrast = 0.01;    //!< silhouette ring darker than the inner ring by this
constexpr double kToneMin = 0.75;            //!< issue 46 item 5: mean object luminance, stylised / none
constexpr double kToneMax = 1.05;
constexpr int kPaperMargin = 16;             //!< px between the object and "unpainted paper"
constexpr int kInsideErode = 2;
constexpr int kEdgeRing = 2;
constexpr int kInnerFrom = 8, kInnerTo = 14;
constexpr int kWidth = 640, kHeight = 480;

std::string exe() {
    if (const char* e = std::getenv("AQ_LOOK_EXE"); e && *e) return e;
    return AQ_CLI_EXE;
}

using test::shell_quote;

ImageF render(const std::string& model, const std::string& style, const std::string& extra = "") {
    const std::string out = test::output_dir() + "/" + std::to_string(std::hash<std::string>{}(model + style + extra)) +
                            "_" + style + ".png";
    std::string more = extra;
    if (const char* e = std::getenv("AQ_LOOK_EXTRA"); e && *e && style != "none") more += std::string(" ") + e;
    const std::string cmd = shell_quote(exe()) + " render " + shell_quote(model) + " --style " + style + " --width " +
                            std::to_string(kWidth) + " --height " + std::to_string(kHeight) + " --quiet " + more +
                            " --out " + shell_quote(out) + " 2>" + shell_quote(out + ".log");
    const int rc = std::system(cmd.c_str());
    EXPECT_EQ(rc, 0) << cmd;
    return read_image(out);
}

double luma(const ImageF& im, int x, int y) {
    return 0.2126 * im.at(x, y, 0) + 0.7152 * im.at(x, y, 1) + 0.0722 * im.at(x, y, 2);
}

//! Chessboard distance of every pixel to the nearest pixel whose `inside` differs from its own
//! (both ways: distance to the object outside it, to the background inside it).
std::vector<int> distance_to_boundary(const std::vector<char>& inside, int w, int h) {
    std::vector<int> d(std::size_t(w) * h, -1);
    std::deque<int> q;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const int i = y * w + x;
            bool border = false;
            for (int dy = -1; dy <= 1 && !border; ++dy)
                for (int dx = -1; dx <= 1 && !border; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    if (xx >= 0 && yy >= 0 && xx < w && yy < h && inside[std::size_t(yy * w + xx)] != inside[std::size_t(i)])
                        border = true;
                }
            if (border) d[std::size_t(i)] = 1, q.push_back(i);
        }
    while (!q.empty()) {
        const int i = q.front();
        q.pop_front();
        const int x = i % w, y = i / w;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int xx = x + dx, yy = y + dy;
                if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
                const int j = yy * w + xx;
                if (d[std::size_t(j)] < 0 && inside[std::size_t(j)] == inside[std::size_t(i)]) {
                    d[std::size_t(j)] = d[std::size_t(i)] + 1;
                    q.push_back(j);
                }
            }
    }
    for (int& v : d)
        if (v < 0) v = 1 << 20;  // no boundary at all
    return d;
}

struct LookStats {
    double paper_mean = 0, paper_std = 0, inside_diff = 0, edge_dark = 0, inner_dark = 0;
    double tone = 0;  //!< mean luminance over the object, stylised / none (issue 46 item 5)
    long paper_px = 0, inside_px = 0, edge_px = 0, inner_px = 0;
};

LookStats measure(const ImageF& sty, const ImageF& none) {
    LookStats s;
    const int w = none.width(), h = none.height();
    std::vector<char> in(std::size_t(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) in[std::size_t(y * w + x)] = none.channels() == 4 ? none.at(x, y, 3) > 0.5f : 0;
    const std::vector<int> dist = distance_to_boundary(in, w, h);
    double sum = 0, sum2 = 0, diff = 0, edge = 0, inner = 0, lum_sty = 0, lum_none = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y * w + x);
            const double l = luma(sty, x, y);
            if (!in[i] && dist[i] > kPaperMargin) sum += l, sum2 += l * l, ++s.paper_px;
        }
    if (s.paper_px) {
        s.paper_mean = sum / double(s.paper_px);
        s.paper_std = std::sqrt(std::max(0.0, sum2 / double(s.paper_px) - s.paper_mean * s.paper_mean));
    }
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y * w + x);
            if (!in[i]) continue;
            // The unstylised object laid on the stylised paper's mean tone by its coverage (the
            // silhouette's partly covered pixels are part paper in both images).
            const double a = none.at(x, y, 3);
            const double dl = luma(sty, x, y) - (a * luma(none, x, y) + (1.0 - a) * s.paper_mean);
            if (dist[i] > kInsideErode) {
                lum_sty += luma(sty, x, y), lum_none += luma(none, x, y);
                double m = 0;
                for (int c = 0; c < 3; ++c) m = std::max(m, double(std::fabs(sty.at(x, y, c) - none.at(x, y, c))));
                diff += m, ++s.inside_px;
            }
            if (dist[i] <= kEdgeRing) edge += dl, ++s.edge_px;
            else if (dist[i] >= kInnerFrom && dist[i] <= kInnerTo) inner += dl, ++s.inner_px;
        }
    if (s.inside_px) s.inside_diff = diff / double(s.inside_px);
    if (lum_none > 0) s.tone = lum_sty / lum_none;
    if (s.edge_px) s.edge_dark = edge / double(s.edge_px);
    if (s.inner_px) s.inner_dark = inner / double(s.inner_px);
    return s;
}

struct Case {
    std::string model;  //!< under shared/assets
};

//! What check_input asserts: nothing (measure), the paper, the stylisation and the tone (Paint), or
//! every threshold including the silhouette darkening (All).
enum class Assert { None, Paint, All };

void check_input(const std::string& model, const std::string& rel, Assert level) {
    const bool assert_thresholds = level != Assert::None;
    const ImageF none = render(model, "none");
    ASSERT_EQ(none.channels(), 4) << "--style none keeps the coverage alpha";
    for (const char* style : {"wc16", "wc17", "wc18"}) {
        const ImageF sty = render(model, style);
        ASSERT_TRUE(sty.same_size(none));
        LookStats s = measure(sty, none);
        if (level != Assert::Paint) {
            // Silhouette darkening where no bleeding is painted: a bleeding patch dissolves the
            // silhouette it covers on purpose (WC16's naive bleeding mixes in the paper), so the
            // edges are measured on the same render with bleeding left out (docs/look.md §5).
            const LookStats e = measure(render(model, style, "--bypass bleed_blend"), none);
            s.edge_dark = e.edge_dark, s.inner_dark = e.inner_dark;
        }
        std::printf("LOOK\t%s\t%s\tpaper_mean %.4f\tpaper_std %.4f\tpaper_px %ld\tinside_diff %.4f\tedge_dark %.4f\t"
                    "inner_dark %.4f\tedge_contrast %.4f\ttone %.3f\n",
                    rel.c_str(), style, s.paper_mean, s.paper_std, s.paper_px, s.inside_diff, s.edge_dark, s.inner_dark,
                    s.inner_dark - s.edge_dark, s.tone);
        if (!assert_thresholds) continue;
        const std::string what = rel + " " + style;
        ASSERT_GT(s.paper_px, 1000) << what << ": too little unpainted paper to measure";
        EXPECT_GE(s.paper_mean, kPaperLumMin) << what << ": paper too dark";
        EXPECT_LE(s.paper_mean, kPaperLumMax) << what << ": paper too bright (no paper tone)";
        EXPECT_GE(s.paper_std, kMinPaperStd) << what << ": paper texture not visible";
        EXPECT_GE(s.inside_diff, kMinInsideDiff) << what << ": stylised object too close to --style none";
        EXPECT_GE(s.tone, kToneMin) << what << ": the style darkens the object";
        EXPECT_LE(s.tone, kToneMax) << what << ": the style washes the object out";
        if (level != Assert::All) continue;
        EXPECT_GE(s.inner_dark - s.edge_dark, kMinEdgeContrast) << what << ": silhouette not darkened";
    }
}

void check_model(const std::string& rel, bool assert_thresholds) {
    check_input(test::asset(rel), rel, assert_thresholds ? Assert::All : Assert::None);
}

// Three kinds of bare model: flat baseColorFactor colours (low-poly tree), an sRGB texture with a
// normal map (photoscan), a textured rigged model.
TEST(Look, BareBirchTreeLooksPainted) { check_model("plants/quaternius/BirchTree_4.glb", true); }
TEST(Look, BareAvocadoLooksPainted) { check_model("gltf/Avocado/glTF/Avocado.gltf", true); }
TEST(Look, BareFoxLooksPainted) { check_model("gltf/Fox/glTF/Fox.gltf", true); }
// Plants nobody tuned for (issue 46 item 9): four of each generated kind. Paper,
// stylisation and tone are asserted; the silhouette-vs-interior darkening is printed only: in a
// crown of needles or blades the "interior" ring is leaf edges too (docs/look.md §7).
//! The generated corpus of issue 46 item 9: four plants of each kind, seeds and proportions varied
//! (docs/ld06.md "Procedural plants"); the WC and the LD06 look checks both run it.
const char* const kGeneratedVariants[] = {"&seed=1", "&seed=2&leaves=0.5", "&seed=3&spread=1.4",
                                          "&seed=4&leaves=1.5&leaf_size=0.7"};
void check_generated_wc(const std::string& kind) {
    for (const char* q : kGeneratedVariants)
        check_input("procedural:tree?kind=" + kind + q, "generated " + kind + q, Assert::Paint);
}
TEST(Look, GeneratedBroadleafLooksPainted) { check_generated_wc("broadleaf"); }
TEST(Look, GeneratedLightCrownLooksPainted) { check_generated_wc("light"); }
TEST(Look, GeneratedConiferLooksPainted) { check_generated_wc("conifer"); }
TEST(Look, GeneratedShrubLooksPainted) { check_generated_wc("shrub"); }
TEST(Look, GeneratedGrassLooksPainted) { check_generated_wc("grass"); }
// The shared plants (LD06's inputs) in the WC styles too.
TEST(Look, SharedPlantsLookPainted) {
    for (const char* p : {"plants/ez-tree/ez_oak_large_dense.glb", "plants/ez-tree/ez_ash_large.glb",
                          "plants/ez-tree/ez_bush2.glb", "plants/quaternius/CommonTree_1.glb"})
        check_input(test::asset(p), p, Assert::Paint);
}

// --control neutral keeps today's neutral control: on the procedural swatches (painted by code,
// so no default control applies) both give the same bytes; on a bare model they differ.
TEST(Look, NeutralControlOption) {
    const ImageF a = render("procedural:swatches", "wc18");
    const ImageF b = render("procedural:swatches", "wc18", "--control neutral");
    EXPECT_EQ(std::vector<float>(a.data(), a.data() + a.num_values()), std::vector<float>(b.data(), b.data() + b.num_values()))
        << "painted scenes must not receive the default control";
    const std::string tree = test::asset("plants/quaternius/BirchTree_4.glb");
    const ImageF c = render(tree, "wc18");
    const ImageF d = render(tree, "wc18", "--control neutral");
    EXPECT_NE(std::vector<float>(c.data(), c.data() + c.num_values()), std::vector<float>(d.data(), d.data() + d.num_values()))
        << "a bare model gets the default control unless --control neutral";
}

// ---- Every step visible by default (issue 46 item 8, docs/look.md §9) ------------------------------
//
// Each effect step of wc16, wc17 and wc18 is bypassed in turn (`--bypass STEP`: its readers get its
// input) and the final image compared with the full one over the object: the `--style none`
// coverage dilated by kStepDilate px (edge darkening, overlaps and bleeding act at and across the
// silhouette). `step` = mean over those pixels of the largest per-channel |full - bypassed|.
// `adjust` is not an effect (it loads the colour and lays the paper) and the steps whose outputs
// only feed another step (bleed, edge_blur, edge_detect, extend_edges) are seen through that step.
constexpr int kStepDilate = 3;
constexpr double kMinStepDiff = 0.002;     //!< ~half an 8-bit level on average over the object
constexpr double kMinWc16Wc17Diff = 0.01;  //!< the two papers' bleeding and edge darkening differ

//! Mean largest-channel |a - b| over the pixels within `dilate` px of `none`'s coverage.
double object_diff(const ImageF& a, const ImageF& b, const ImageF& none, int dilate) {
    const int w = none.width(), h = none.height();
    std::vector<char> in(std::size_t(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) in[std::size_t(y * w + x)] = none.at(x, y, 3) > 0.5f;
    const std::vector<int> dist = distance_to_boundary(in, w, h);
    double sum = 0;
    long n = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y * w + x);
            if (!in[i] && dist[i] > dilate) continue;
            double m = 0;
            for (int c = 0; c < 3; ++c) m = std::max(m, double(std::fabs(a.at(x, y, c) - b.at(x, y, c))));
            sum += m, ++n;
        }
    return n ? sum / double(n) : 0.0;
}

struct StyleSteps {
    const char* style;
    std::vector<const char*> steps;
};
const std::vector<StyleSteps> kEffectSteps = {
    {"wc16", {"bleed_blend", "edge_darken", "pigment_apply", "substrate_distort"}},
    {"wc17", {"bleed_blend", "edge_darken", "pigment_apply", "substrate_distort"}},
    {"wc18", {"pigment_density", "bleed_blend", "edge_darken", "gaps_overlaps", "pigment_apply", "substrate_distort",
              "substrate_light"}},
};

void check_steps(const std::string& model, const std::string& rel, bool assert_thresholds) {
    const ImageF none = render(model, "none");
    ASSERT_EQ(none.channels(), 4);
    std::vector<ImageF> full;
    for (const StyleSteps& st : kEffectSteps) {
        full.push_back(render(model, st.style));
        for (const char* step : st.steps) {
            const double d = object_diff(full.back(), render(model, st.style, std::string("--bypass ") + step), none, kStepDilate);
            std::printf("STEP\t%s\t%s\t%s\t%.4f\n", rel.c_str(), st.style, step, d);
            if (assert_thresholds)
                EXPECT_GE(d, kMinStepDiff) << rel << " " << st.style << ": bypassing " << step << " changes too little";
        }
    }
    const double d1617 = object_diff(full[0], full[1], none, kStepDilate);
    std::printf("STEP\t%s\twc16-wc17\t-\t%.4f\n", rel.c_str(), d1617);
    if (assert_thresholds) EXPECT_GE(d1617, kMinWc16Wc17Diff) << rel << ": wc16 and wc17 nearly the same picture";
}

// A textured model and a plant of flat factor colours.
TEST(Look, EveryStepIsVisibleOnTheFox) { check_steps(test::asset("gltf/Fox/glTF/Fox.gltf"), "Fox.gltf", true); }
TEST(Look, EveryStepIsVisibleOnTheBirch) {
    check_steps(test::asset("plants/quaternius/BirchTree_4.glb"), "BirchTree_4.glb", true);
}

// ---- LD06 on plants (issue 46 items 1-4, docs/ld06.md "Fitting the abstraction") -------------------
//
// For each plant, at LD06's 720 px output with 520 px intermediates:
//   crown     painted area over the modelled foliage's silhouette, outside the modelled trunk:
//             |P \ K| / |F \ K|, where F and K are the foliage and the trunk as modelled (binary
//             depth passes drawing foliage / non-foliage) and P the painted pixels: the picture
//             before the paper's relief is lit (target color.inked: every wash, shadow and stroke
//             glazed over the flat substrate colour) differs from the substrate by more than
//             kPainted in some channel;
//   covered   the share of the modelled foliage silhouette that is painted, |P ∩ F| / |F|;
//   hue       the chroma-weighted circular mean hue over the plant (`--style none` coverage, eroded
//             by kInsideErode px), ld06's washes (target color.shadowed: before the ink strokes and
//             the paper's relief) against none, in degrees.
constexpr double kPainted = 0.1;          //!< a visible wash over the flat paper colour
// Issue 46's targets, met on every input (docs/ld06.md "What the look check measures").
constexpr double kCrownMin = 0.85, kCrownMax = 1.4;
constexpr double kMinCovered = 0.85;
constexpr double kMaxHueShift = 15.0;     //!< degrees
constexpr int kLd06Size = 720;

//! The measurement pipeline: the modelled foliage (draw 1) and everything else (draw 2) as depth
//! maps at the output size (where the washes are), with no abstraction.
std::string mask_style() {
    const std::string path = test::output_dir() + "/ld06_masks.json";
    if (FILE* f = std::fopen(path.c_str(), "wb")) {
        std::fputs(R"({ "name": "ld06_masks", "output": "m.foliage", "steps": [
  { "pass": "depth", "id": "f", "params": { "scale": 1.0, "draw": 1 }, "out": { "depth": "m.foliage" } },
  { "pass": "depth", "id": "k", "params": { "scale": 1.0, "draw": 2 }, "out": { "depth": "m.trunk" } } ] })",
                   f);
        std::fclose(f);
    }
    return path;
}

struct Ld06Look {
    double crown = 0, covered = 0, hue_shift = 0;
    long foliage_px = 0;
};

//! Chroma-weighted circular mean hue (degrees) over the pixels with `mask`.
double mean_hue(const ImageF& im, const std::vector<char>& mask) {
    double sx = 0, sy = 0;
    for (int y = 0; y < im.height(); ++y)
        for (int x = 0; x < im.width(); ++x) {
            if (!mask[std::size_t(y * im.width() + x)]) continue;
            const double r = im.at(x, y, 0), g = im.at(x, y, 1), b = im.at(x, y, 2);
            const double mx = std::max({r, g, b}), mn = std::min({r, g, b}), c = mx - mn;
            if (c <= 0) continue;
            double hh = mx == r ? std::fmod((g - b) / c + 6.0, 6.0) : mx == g ? (b - r) / c + 2.0 : (r - g) / c + 4.0;
            hh *= M_PI / 3.0;
            sx += c * std::cos(hh), sy += c * std::sin(hh);
        }
    return std::atan2(sy, sx) * 180.0 / M_PI;
}

Ld06Look measure_ld06(const std::string& input, const std::string& extra = "") {
    Ld06Look L;
    const std::string key = std::to_string(std::hash<std::string>{}(input + extra));
    const std::string dm = test::output_dir() + "/ld06m_" + key, dl = test::output_dir() + "/ld06_" + key;
    const std::string size = " --width " + std::to_string(kLd06Size) + " --height " + std::to_string(kLd06Size) + " --quiet ";
    auto run = [&](const std::string& args, const std::string& log) {
        const std::string cmd = shell_quote(exe()) + " render " + shell_quote(input) + size + args + " 2>" + shell_quote(log);
        EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
    };
    run("--style " + shell_quote(mask_style()) + " --targets " + shell_quote(dm) + " --out " + shell_quote(dm + ".exr"), dm + ".log");
    run("--style ld06 " + extra + " --targets " + shell_quote(dl) + " --out " + shell_quote(dl + ".png"), dl + ".log");
    run("--style none --out " + shell_quote(dl + "_none.png"), dl + "_none.log");
    const ImageF fol = read_image(dm + "/m.foliage.exr"), trunk = read_image(dm + "/m.trunk.exr");
    const ImageF inked = read_image(dl + "/color.inked.exr");
    EXPECT_TRUE(fol.same_size(inked) && trunk.same_size(inked)) << input;
    constexpr float kSubstrate[3] = {0.97f, 0.955f, 0.92f};  // stylize/presets/ld06.json substrate_color
    long F = 0, PnotK = 0, FnotK = 0, PF = 0;
    for (int y = 0; y < fol.height(); ++y)
        for (int x = 0; x < fol.width(); ++x) {
            const bool f = fol.at(x, y, 0) < 1.0f, k = trunk.at(x, y, 0) < 1.0f;
            double p = 0;
            for (int c = 0; c < 3; ++c) p = std::max(p, std::fabs(double(inked.at(x, y, c)) - double(kSubstrate[c])));
            const bool painted = p > kPainted;
            F += f, PF += f && painted, FnotK += f && !k, PnotK += painted && !k;
        }
    L.foliage_px = F;
    if (FnotK > 0) L.crown = double(PnotK) / double(FnotK);
    if (F > 0) L.covered = double(PF) / double(F);
    // The washes' colour before the ink strokes (LD06 §4.4's sepia contours, a colour of their own by
    // design) and the paper's relief: what the ramps and glazes make of the object's colour.
    const ImageF none = read_image(dl + "_none.png"), sty = read_image(dl + "/color.shadowed.exr");
    const int w = none.width(), h = none.height();
    std::vector<char> in(std::size_t(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) in[std::size_t(y * w + x)] = none.at(x, y, 3) > 0.5f;
    const std::vector<int> dist = distance_to_boundary(in, w, h);
    for (std::size_t i = 0; i < in.size(); ++i) in[i] = in[i] && dist[i] > kInsideErode;
    double d = mean_hue(sty, in) - mean_hue(none, in);
    L.hue_shift = std::remainder(d, 360.0);
    return L;
}

void check_ld06(const std::string& input, const std::string& label, bool assert_thresholds = true) {
    const Ld06Look L = measure_ld06(input);
    std::printf("LD06LOOK\t%s\tfoliage_px %ld\tcrown %.3f\tcovered %.3f\thue_shift %+.1f\n", label.c_str(), L.foliage_px, L.crown,
                L.covered, L.hue_shift);
    if (!assert_thresholds) return;
    EXPECT_LE(std::fabs(L.hue_shift), kMaxHueShift) << label << ": LD06 moves the plant's hue";
    if (L.foliage_px == 0) return;  // no foliage by the default rule: drawn as modelled
    EXPECT_GE(L.covered, kMinCovered) << label << ": LD06 loses foliage";
    EXPECT_GE(L.crown, kCrownMin) << label << ": painted crown smaller than the foliage";
    EXPECT_LE(L.crown, kCrownMax) << label << ": painted crown larger than the foliage";
}

TEST(LookLd06, SharedPlantsKeepTheirFoliage) {
    for (const char* p : {"plants/ez-tree/ez_oak_large_dense.glb", "plants/ez-tree/ez_ash_large.glb", "plants/ez-tree/ez_bush2.glb",
                          "plants/quaternius/BirchTree_4.glb", "plants/quaternius/CommonTree_1.glb"})
        check_ld06(test::asset(p), p);
}

//! Four seeds of each generated kind (20 plants), default proportions but for the leaf count.
void check_generated(const std::string& kind) {
    for (const char* q : kGeneratedVariants) check_ld06("procedural:tree?kind=" + kind + q, kind + q);
}
TEST(LookLd06, GeneratedBroadleaf) { check_generated("broadleaf"); }
TEST(LookLd06, GeneratedLightCrown) { check_generated("light"); }
TEST(LookLd06, GeneratedConifer) { check_generated("conifer"); }
TEST(LookLd06, GeneratedShrub) { check_generated("shrub"); }
TEST(LookLd06, GeneratedGrass) { check_generated("grass"); }

//! A saturated red model (the issue's apple): LD06's ramps keep its hue.
TEST(LookLd06, SaturatedModelKeepsItsHue) {
    const std::string path = test::output_dir() + "/red_suzanne.json";
    if (FILE* f = std::fopen(path.c_str(), "wb")) {
        std::fprintf(f, R"({ "gltf": "%s", "materials": { "*": { "base_color": [0.6, 0.03, 0.02] } } })",
                     test::asset("gltf/Suzanne/glTF/Suzanne.gltf").c_str());
        std::fclose(f);
    }
    check_ld06(path, "red Suzanne");
}

// Measurement, not a check (numbers on stdout for docs/look.md): compiled only into the separate
// `look_measure` executable, which CTest does not run. Run it with
//   build/tests/app/look_measure
#ifdef AQ_LOOK_MEASURE
TEST(Look, MeasureEveryModel) {
    for (const char* m : {"gltf/Avocado/glTF/Avocado.gltf", "gltf/Box/glTF-Embedded/Box.gltf",
                          "gltf/BoxTextured/BoxTextured.gltf", "gltf/BoxVertexColors_CC0/glTF-Embedded/BoxVertexColors.gltf",
                          "gltf/Cube/glTF/Cube.gltf", "gltf/Fox/glTF/Fox.gltf", "gltf/OrientationTest/glTF/OrientationTest.gltf",
                          "gltf/Suzanne/glTF/Suzanne.gltf", "gltf/WaterBottle/glTF/WaterBottle.gltf",
                          "plants/quaternius/BirchTree_4.glb", "plants/quaternius/CommonTree_1.glb"})
        check_model(m, false);
}
// WC numbers of any inputs: AQ_LOOK_INPUTS="a.glb;procedural:tree?kind=conifer" look_measure
// --gtest_filter=Look.MeasureInputs.
TEST(Look, MeasureInputs) {
    const char* list = std::getenv("AQ_LOOK_INPUTS");
    const std::string all = list ? list : "";
    for (std::size_t at = 0; at < all.size();) {
        const std::size_t end = std::min(all.find(';', at), all.size());
        const std::string in = all.substr(at, end - at);
        at = end + 1;
        check_input(in, in, Assert::None);
    }
}
// The bypass measure on every shared model (docs/look.md §9).
TEST(Look, MeasureEveryStep) {
    for (const char* m : {"gltf/Avocado/glTF/Avocado.gltf", "gltf/BoxTextured/BoxTextured.gltf", "gltf/Fox/glTF/Fox.gltf",
                          "gltf/Suzanne/glTF/Suzanne.gltf", "gltf/WaterBottle/glTF/WaterBottle.gltf",
                          "plants/quaternius/BirchTree_4.glb", "plants/quaternius/CommonTree_1.glb"})
        check_steps(test::asset(m), m, false);
    check_steps("procedural:tree?kind=broadleaf&seed=1", "generated broadleaf", false);
}
// LD06 numbers of any inputs: AQ_LD06_INPUTS="a.glb;procedural:tree?kind=conifer;scene.json" look_measure
// --gtest_filter=LookLd06.MeasureInputs (EXTRA: AQ_LD06_EXTRA, e.g. "--set particles.spread=0.05").
TEST(LookLd06, MeasureInputs) {
    const char* list = std::getenv("AQ_LD06_INPUTS");
    const char* extra = std::getenv("AQ_LD06_EXTRA");
    std::string all = list ? list : "";
    for (std::size_t at = 0; at < all.size();) {
        std::size_t end = all.find(';', at);
        if (end == std::string::npos) end = all.size();
        const std::string in = all.substr(at, end - at);
        at = end + 1;
        const Ld06Look L = measure_ld06(in, extra ? extra : "");
        std::printf("LD06LOOK\t%s\tfoliage_px %ld\tcrown %.3f\tcovered %.3f\thue_shift %+.1f\n", in.c_str(), L.foliage_px, L.crown,
                    L.covered, L.hue_shift);
    }
}
#endif  // AQ_LOOK_MEASURE

}  // namespace
}  // namespace aq
