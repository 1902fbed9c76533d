// tests/app/ld06_test.cpp — issue 12 "done when": the ld06 preset through the `aquarelle` CLI, in
// this test's own output folder. A bare plant glTF (no scene file, no lights) renders to a painting
// made of washes — paper around it, the plant darker than the paper, not the G-buffer colour —
// with the same float bytes at 1, 2 and 8 threads; a model without foliage, δ = 0 (the binary
// limit) and a folded layer pack render; out-of-range layer colours fail with a message naming the
// parameter and leave no output file; --targets writes the colour-ramp maps that the fused render
// never writes, with the same image.
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>

#include "core/image.h"
#include "core/io.h"
#include "tests/test_support.h"

namespace aq {
namespace {

constexpr int kSize = 200;  // small: the test is about behaviour, not the look at 720 px

using test::shell_quote;

//! Runs `aquarelle render MODEL --style STYLE EXTRA --out OUT`; returns the exit status, the log in *log.
int render(const std::string& model, const std::string& style, const std::string& out, const std::string& extra,
           std::string* log = nullptr) {
    const std::string lp = out + ".log";
    const std::string cmd = shell_quote(AQ_CLI_EXE) + " render " + shell_quote(model) + " --style " + style + " --width " +
                            std::to_string(kSize) + " --height " + std::to_string(kSize) + " --quiet " + extra + " --out " +
                            shell_quote(out) + " 2>" + shell_quote(lp);
    const int rc = std::system(cmd.c_str());
    if (log) {
        std::ifstream f(lp);
        *log = std::string(std::istreambuf_iterator<char>(f), {});
    }
    return rc;
}

std::string bytes(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
}

double luma(const ImageF& im, int x, int y) {
    return 0.2126 * im.at(x, y, 0) + 0.7152 * im.at(x, y, 1) + 0.0722 * im.at(x, y, 2);
}

TEST(Ld06Cli, BarePlantIsPaintedWithTheSameBytesForAnyThreadCount) {
    const std::string bush = test::asset("plants/ez-tree/ez_bush2.glb");
    const std::string dir = test::output_dir();
    std::string first;
    for (int threads : {1, 2, 8}) {
        const std::string out = dir + "/bush_t" + std::to_string(threads) + ".exr";
        std::string log;
        ASSERT_EQ(render(bush, "ld06", out, "--threads " + std::to_string(threads), &log), 0) << log;
        const std::string b = bytes(out);
        ASSERT_FALSE(b.empty());
        if (first.empty()) first = b;
        else EXPECT_TRUE(b == first) << threads << " threads: other bytes than 1 thread";
    }
    // A painting of washes: the corners are paper, the plant is painted darker than the paper and
    // differs from the unstylised G-buffer colour.
    const ImageF ld = read_image(dir + "/bush_t1.exr");
    const std::string none_out = dir + "/bush_none.exr";
    ASSERT_EQ(render(bush, "none", none_out, ""), 0);
    const ImageF none = read_image(none_out);
    ASSERT_EQ(ld.width(), kSize);
    double paper = 0;
    for (auto [x, y] : {std::pair{2, 2}, {kSize - 3, 2}, {2, kSize - 3}, {kSize - 3, kSize - 3}}) paper += luma(ld, x, y) / 4;
    EXPECT_GT(paper, 0.8);
    int painted = 0, covered = 0;
    double diff = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            if (none.at(x, y, 3) < 0.5f) continue;  // the plant's coverage in the G-buffer
            ++covered;
            painted += luma(ld, x, y) < paper - 0.05;
            for (int c = 0; c < 3; ++c) diff += std::abs(double(ld.at(x, y, c)) - double(none.at(x, y, c))) / 3;
        }
    ASSERT_GT(covered, 500);
    EXPECT_GT(double(painted) / covered, 0.5) << "most of the plant is painted";
    EXPECT_GT(diff / covered, 0.03) << "the washes are not the G-buffer colour";
}

// Issue 46's bad input: a plant seen from inside its crown (the camera inside the implicit
// surface) and a plant that is only foliage (grass: the texture technique) render and paint.
TEST(Ld06Cli, InsideTheCrownAndFoliageOnlyPlantsRender) {
    const std::string dir = test::output_dir();
    const std::string scene = dir + "/inside.json";
    std::ofstream(scene) << R"({ "gltf": ")" << test::asset("plants/ez-tree/ez_oak_large_dense.glb")
                         << R"(", "camera": { "eye": [0, 70, 0], "target": [10, 70, 10], "yfov_deg": 60 } })";
    std::string log;
    ASSERT_EQ(render(scene, "ld06", dir + "/inside.png", "", &log), 0) << log;
    ASSERT_EQ(render("procedural:tree?kind=grass&seed=2", "ld06", dir + "/grass.png", "--targets " + shell_quote(dir + "/grass"), &log),
              0)
        << log;
    const ImageF crown = read_image(dir + "/grass/ld06.particles.crown.exr");
    double sum = 0;
    for (int y = 0; y < crown.height(); ++y)
        for (int x = 0; x < crown.width(); ++x) sum += crown.at(x, y, 0);
    EXPECT_GT(sum, 200.0) << "the blades' coverage is the crown map";
    for (const char* t : {"ld06.particles.dark", "ld06.particles.medium", "ld06.particles.bright"}) {
        const ImageF m = read_image(dir + "/grass/" + t + ".exr");
        double s2 = 0;
        for (int y = 0; y < m.height(); ++y)
            for (int x = 0; x < m.width(); ++x) s2 += m.at(x, y, 0);
        EXPECT_GT(s2, 20.0) << t << ": the derived detail has every class";
        EXPECT_LT(s2, sum) << t << ": one class is part of the coverage";
    }
}

TEST(Ld06Cli, TheRampMapsAreWrittenWhenAskedForAndTheFusedRenderHasTheSameBytes) {
    // Without --targets, each color_ramp runs inside its glaze (stylize/stage.h Fusion) and writes
    // no map; with --targets the steps run one by one and every ramp map is written. The image is
    // the same float bytes either way.
    const std::string dir = test::output_dir();
    std::string log;
    ASSERT_EQ(render("procedural:tree", "ld06", dir + "/fused.exr", "", &log), 0) << log;
    ASSERT_EQ(render("procedural:tree", "ld06", dir + "/kept.exr", "--targets " + shell_quote(dir + "/targets"), &log), 0) << log;
    const ImageF fused = read_image(dir + "/fused.exr"), kept = read_image(dir + "/kept.exr");  // pixels: the
    ASSERT_TRUE(fused.same_size(kept));                                                         // files' manifests
    EXPECT_EQ(0, std::memcmp(fused.data(), kept.data(), fused.num_values() * sizeof(float)))    // name the options
        << "fused and unfused renders differ";
    for (const char* t : {"ld06.ramp.0", "ld06.ramp.3", "ld06.particles.ramp.0", "ld06.particles.ramp.3", "ld06.wash"})
        EXPECT_TRUE(std::filesystem::exists(dir + "/targets/" + t + ".exr")) << t;
}

TEST(Ld06Cli, NoFoliageTheBinaryLimitAndAFoldedLayerPackRender) {
    const std::string dir = test::output_dir();
    std::string log;
    // A tree whose leaf material is not recognisable as foliage: no abstraction, no particles, warned.
    ASSERT_EQ(render(test::asset("plants/quaternius/CommonTree_1.glb"), "ld06", dir + "/common.png", "", &log), 0) << log;
    EXPECT_NE(log.find("no foliage"), std::string::npos) << log;
    // δ = 0 everywhere the blurred depth test is used.
    ASSERT_EQ(render("procedural:tree", "ld06", dir + "/binary.png",
                     "--set particles.delta=0 --set particles.beta=0 --set shadow.delta=0 --set strokes.delta=0", &log),
              0)
        << log;
    EXPECT_TRUE(std::filesystem::exists(dir + "/binary.png"));
    // Layers from 1 on: layer 0 is left out, the rest packed into four (fold).
    ASSERT_EQ(render("procedural:swatches", "ld06", dir + "/fold.png", "--set id_layers.first=1 --set ramp.first=1", &log), 0)
        << log;
}

TEST(Ld06Cli, OutOfRangeLayerColoursFailWithoutAnOutputFile) {
    const std::string out = test::output_dir() + "/bad.png";
    std::string log;
    EXPECT_NE(render("procedural:tree", "ld06", out, "--set ramp.color0_r=1.5", &log), 0);
    EXPECT_NE(log.find("color0_r"), std::string::npos) << log;
    EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace aq
