// tests/app/coherence_test.cpp — temporal coherence as numbers (issue 14 item 3; docs/coherence.md).
// The two measures on synthetic frames whose answer is known (identical frames; flicker where the
// G-buffer is still; a camera moving over a plane with a texture fixed to the object versus one
// fixed to the screen), then `aquarelle coherence` on CLI renders: 0 for a still camera and a
// static style (ld06 has no tremor), positive for a style that changes every frame (WC18's hand
// tremor), and the errors for missing inputs.
#include <cmath>
#include <filesystem>
#include <string>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "app/coherence.h"
#include "core/hash.h"
#include "raster/vertex.h"
#include "tests/test_support.h"

namespace aq::app {
namespace {

constexpr int kW = 64, kH = 48;
constexpr double kPlaneDepth = 5.0;

//! A frame of a camera at (cx, 0, 0) looking down -Z at the plane z = -5, perspective: every pixel
//! sees the plane at depth 5, normal +Z, object id 1 left of x = 0 and 2 right of it. The colour is
//! f(world x, world y) (texture on the object) or f(pixel) (texture on the screen).
struct PlaneFrame {
    ImageF image{kW, kH, 3}, depth{kW, kH, 1}, normal{kW, kH, 3}, id{kW, kH, 1};
    glm::dmat4 view{1.0}, proj{1.0};
    CoherenceFrame frame() const {
        CoherenceFrame f;
        f.image = &image;
        f.depth = &depth;
        f.normal = &normal;
        f.id = &id;
        f.view = view;
        f.projection = proj;
        return f;
    }
};

double pattern(double u, double v) { return 0.5 + 0.4 * std::sin(3.0 * u) * std::cos(2.0 * v); }

PlaneFrame plane_frame(double cx, bool object_space) {
    PlaneFrame f;
    scene::Camera cam;
    cam.yfov = 0.8f;
    f.proj = glm::dmat4(raster::projection_matrix(cam, float(kW) / float(kH)));
    f.view = glm::translate(glm::dmat4(1.0), glm::dvec3(-cx, 0, 0));
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const double nx = 2.0 * (x + 0.5) / kW - 1.0, ny = 1.0 - 2.0 * (y + 0.5) / kH;
            const double wx = cx + nx * kPlaneDepth / f.proj[0][0], wy = ny * kPlaneDepth / f.proj[1][1];
            const double c = object_space ? pattern(wx, wy) : pattern(0.1 * x, 0.1 * y);
            for (int k = 0; k < 3; ++k) f.image.at(x, y, k) = float(c);
            f.depth.at(x, y, 0) = float(kPlaneDepth);
            f.normal.at(x, y, 2) = 1.0f;
            f.id.at(x, y, 0) = wx < 0 ? 1.0f : 2.0f;
        }
    return f;
}

TEST(Coherence, IdenticalFramesChangeNothing) {
    const PlaneFrame a = plane_frame(0.0, true);
    const CoherenceStats s = frame_coherence(a.frame(), a.frame());
    EXPECT_EQ(s.static_pixels, s.pixels);
    EXPECT_EQ(s.static_mean(), 0.0);
    EXPECT_EQ(s.warped_pixels, s.object_pixels);
    EXPECT_LT(s.warp_mean(), 1e-9);
}

TEST(Coherence, FlickerWhereTheGBufferIsStillIsTheStaticChange) {
    const PlaneFrame a = plane_frame(0.0, true);
    PlaneFrame b = plane_frame(0.0, true);
    // Noise of known mean |change| 0.02 on every third pixel row: 1/3 of the pixels change.
    for (int y = 0; y < kH; y += 3)
        for (int x = 0; x < kW; ++x)
            for (int k = 0; k < 3; ++k) b.image.at(x, y, k) += (hash32(std::uint32_t(x * 131 + y)) & 1) ? 0.02f : -0.02f;
    const CoherenceStats s = frame_coherence(a.frame(), b.frame());
    EXPECT_EQ(s.static_pixels, s.pixels);
    EXPECT_NEAR(s.static_mean(), 0.02 / 3.0, 1e-6);
    EXPECT_EQ(s.static_changed, s.pixels / 3);
    EXPECT_NEAR(s.warp_mean(), 0.02 / 3.0, 1e-6);  // a still camera: the warp is the identity
}

TEST(Coherence, AMovingCameraSeparatesObjectTextureFromScreenTexture) {
    // The camera moves by 0.1 world units (~0.8 px at this size): a texture on the object is
    // reprojected onto itself (warp change ~ bilinear error only), a texture on the screen is not;
    // the static measure sees the opposite, since the plane's G-buffer does not change.
    const PlaneFrame o0 = plane_frame(0.0, true), o1 = plane_frame(0.1, true);
    const PlaneFrame s0 = plane_frame(0.0, false), s1 = plane_frame(0.1, false);
    const CoherenceStats obj = frame_coherence(o0.frame(), o1.frame());
    const CoherenceStats scr = frame_coherence(s0.frame(), s1.frame());
    EXPECT_GT(obj.warped_pixels, obj.object_pixels * 9 / 10);
    EXPECT_LT(obj.warp_mean(), 2e-3);  // measured 7.9e-4 (the sine's bilinear error at ~1.1 px of motion)
    EXPECT_GT(scr.warp_mean(), 10 * obj.warp_mean()) << obj.warp_mean() << " " << scr.warp_mean();  // measured 70x
    EXPECT_EQ(scr.static_mean(), 0.0);
    EXPECT_GT(obj.static_mean(), 10 * obj.warp_mean());
    // Pixels whose reprojection lands on the other object (across x = 0) are not compared.
    EXPECT_LT(obj.warped_pixels, obj.object_pixels);
}

TEST(Coherence, MismatchedSizesAreRefused) {
    const PlaneFrame a = plane_frame(0.0, true);
    PlaneFrame b = plane_frame(0.0, true);
    b.depth = ImageF(kW / 2, kH, 1);
    EXPECT_NE(test::error_of([&] { frame_coherence(a.frame(), b.frame()); }).find("depth.linear"), std::string::npos);
}

// --- through the CLI ---------------------------------------------------------------------------

std::string cli() { return test::shell_quote(AQ_CLI_EXE); }

nlohmann::json measure(const std::string& scene, const std::string& style, const std::string& dir, const std::string& extra) {
    std::filesystem::create_directories(dir);
    std::string log;
    EXPECT_EQ(test::run_command(cli() + " render " + scene + " --style " + style + " --width 96 --height 96 --quiet --frames 0-2 " +
                                    extra + " --targets " + test::shell_quote(dir + "/t") + " --out " +
                                    test::shell_quote(dir + "/f_####.exr"), &log), 0) << log;
    EXPECT_EQ(test::run_command(cli() + " coherence " + test::shell_quote(dir) + " --targets " + test::shell_quote(dir + "/t") +
                                    " --json " + test::shell_quote(dir + "/c.json"), &log), 0) << log;
    EXPECT_NE(log.find("total"), std::string::npos) << log;
    return nlohmann::json::parse(test::file_bytes(dir + "/c.json"));
}

TEST(CoherenceCli, StillCameraStaticStyleIsZeroAndTremorIsNot) {
    const std::string dir = test::output_dir();
    const nlohmann::json still = measure("procedural:tree", "ld06", dir + "/ld06", "");
    ASSERT_EQ(still.at("frames").size(), 2u);
    EXPECT_GT(still.at("total").at("static_pixels").get<long long>(), 0);
    EXPECT_GT(still.at("total").at("warped_pixels").get<long long>(), 0);
    EXPECT_EQ(still.at("total").at("static_mean_abs").get<double>(), 0.0);
    EXPECT_LT(still.at("total").at("warp_mean_abs").get<double>(), 1e-9);
    const nlohmann::json tremor = measure("procedural:swatches", "wc18", dir + "/wc18", "");
    EXPECT_GT(tremor.at("total").at("static_mean_abs").get<double>(), 0.0);
    EXPECT_GT(tremor.at("total").at("warp_mean_abs").get<double>(), 1e-4);
}

TEST(CoherenceCli, MissingInputsAreClearErrors) {
    const std::string dir = test::output_dir();
    std::string log;
    EXPECT_EQ(test::run_command(cli() + " coherence " + test::shell_quote(dir), &log), 2) << log;  // no --targets
    EXPECT_NE(log.find("--targets"), std::string::npos) << log;
    EXPECT_EQ(test::run_command(cli() + " coherence " + test::shell_quote(dir) + " --targets " + test::shell_quote(dir), &log), 1)
        << log;
    EXPECT_NE(log.find("at least two frames"), std::string::npos) << log;
    // A run without --targets: its manifests say so.
    ASSERT_EQ(test::run_command(cli() + " render procedural:swatches --width 32 --height 32 --quiet --frames 0-1 --out " +
                                    test::shell_quote(dir + "/n_####.png"), &log), 0) << log;
    EXPECT_EQ(test::run_command(cli() + " coherence " + test::shell_quote(dir + "/n_0000.png") + " " +
                                    test::shell_quote(dir + "/n_0001.png") + " --targets " + test::shell_quote(dir), &log), 1)
        << log;
    EXPECT_NE(log.find("did not write --targets"), std::string::npos) << log;
}

// Issue 47 item 7: frames pair by the frame numbers their manifests record (9999 -> 10000, not by
// file name), and another run's --targets is refused (its files are not the ones the frames'
// manifests record). Item 4: --json /dev/null writes through the device.
TEST(CoherenceCli, FramesPairByNumberAndAnotherRunsTargetsAreRefused) {
    const std::string dir = test::output_dir();
    std::string log;
    const std::string size = " --width 32 --height 32 --quiet ";
    std::filesystem::create_directories(dir + "/a");
    std::filesystem::create_directories(dir + "/b");
    ASSERT_EQ(test::run_command(cli() + " render procedural:swatches" + size + "--frames 9998-10001 --orbit 5 --targets " +
                                    test::shell_quote(dir + "/a/t") + " --out " + test::shell_quote(dir + "/a/f_####.png"), &log), 0)
        << log;
    ASSERT_EQ(test::run_command(cli() + " coherence " + test::shell_quote(dir + "/a") + " --targets " + test::shell_quote(dir + "/a/t") +
                                    " --json /dev/null", &log), 0) << log;
    const std::size_t p1 = log.find("9998->9999"), p2 = log.find("9999->10000"), p3 = log.find("10000->10001");
    ASSERT_NE(p1, std::string::npos) << log;
    ASSERT_NE(p2, std::string::npos) << log;
    ASSERT_NE(p3, std::string::npos) << log;
    EXPECT_LT(p1, p2);
    EXPECT_LT(p2, p3);
    EXPECT_EQ(log.find("10001->9998"), std::string::npos) << log;
    EXPECT_TRUE(std::filesystem::is_character_file("/dev/null"));

    // Another run (another orbit: other depths) of the same frame numbers: its targets are refused.
    ASSERT_EQ(test::run_command(cli() + " render procedural:swatches" + size + "--frames 9998-10001 --orbit 40 --targets " +
                                    test::shell_quote(dir + "/b/t") + " --out " + test::shell_quote(dir + "/b/f_####.png"), &log), 0)
        << log;
    EXPECT_EQ(test::run_command(cli() + " coherence " + test::shell_quote(dir + "/a") + " --targets " + test::shell_quote(dir + "/b/t"),
                                &log), 1) << log;
    EXPECT_NE(log.find("another run"), std::string::npos) << log;
    // Frames of two runs mixed: refused.
    EXPECT_EQ(test::run_command(cli() + " coherence " + test::shell_quote(dir + "/a/f_9998.png") + " " +
                                    test::shell_quote(dir + "/b/f_9999.png") + " --targets " + test::shell_quote(dir + "/a/t"), &log), 1)
        << log;
    EXPECT_NE(log.find("not frames of one run"), std::string::npos) << log;
}

}  // namespace
}  // namespace aq::app
