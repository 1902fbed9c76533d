// tests/stylize/paper_test.cpp — both real papers load, tile exactly at scale 1, derived normals.
#include "stylize/paper.h"

#include <cmath>
#include <cstring>
#include <filesystem>
#include <future>
#include <thread>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "core/io.h"
#include "tests/test_support.h"

namespace aq::stylize {
namespace {

const char* kMnpr = "paper/mnpr/rough_default_2k.jpg";
const char* kAmbientHeight = "paper/ambientcg_Paper001/Paper001_2K-JPG_Displacement.jpg";

void expect_in_unit_range(const ImageF& img) {
    for (std::size_t i = 0; i < img.num_values(); ++i) {
        ASSERT_GE(img.data()[i], 0.0f);
        ASSERT_LE(img.data()[i], 1.0f);
    }
}

TEST(Paper, MnprPaperLoadsInItsOwnLayoutAndTilesExactly) {
    const std::string path = test::asset(kMnpr);
    const ImageF src = read_image(path);
    const int pw = src.width();
    const int w = pw + 37, h = 24;
    const ImageF paper = prepare_paper({path, "mnpr", 1.0f, 1.0f}, w, h);
    ASSERT_EQ(paper.channels(), 3);
    ASSERT_EQ(paper.width(), w);
    ASSERT_EQ(paper.height(), h);
    expect_in_unit_range(paper);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < 37; ++x)
            for (int c = 0; c < 3; ++c) {
                ASSERT_EQ(paper.at(x + pw, y, c), paper.at(x, y, c));  // wraps with period = paper width
                ASSERT_EQ(paper.at(x, y, c), src.at(x, y, c));          // one texel per pixel at scale 1
            }
}

// Rows are prepared in parallel: every traversal and thread count gives the one-thread bytes, at
// scale 1 (runs of texture rows, wrapping in x and y) and at a resampling scale.
TEST(Paper, ParallelRowsGiveTheOneThreadBytes) {
    const std::string path = test::asset(kMnpr);
    const int th = read_image(path).height();
    for (const auto& [w, h, scale] : {std::tuple{37, th + 52, 1.0f}, std::tuple{4200, 5, 1.0f}, std::tuple{301, 97, 1.7f}}) {
        const PaperSpec spec{path, "mnpr", scale, 1.3f};
        const ImageF one = prepare_paper(spec, w, h, Exec::reference());
        for (const Exec& ex : {Exec::fast(1), Exec::fast(2), Exec::fast(8)})
            EXPECT_EQ(std::memcmp(prepare_paper(spec, w, h, ex).data(), one.data(), one.num_values() * sizeof(float)), 0)
                << w << "x" << h << " scale " << scale << " threads " << ex.threads;
        if (scale == 1.0f && h > th) {
            for (int y = 0; y < h - th; ++y)
                for (int x = 0; x < w; ++x) ASSERT_EQ(one.at(x, y + th, 1), one.at(x, y, 1)) << "wraps in y";
        }
    }
}

TEST(Paper, RoughnessFollowsMnprAdjust) {
    const std::string path = test::asset(kMnpr);
    const ImageF base = prepare_paper({path, "mnpr", 1.0f, 1.0f}, 16, 8);
    const ImageF flat = prepare_paper({path, "mnpr", 1.0f, 0.0f}, 16, 8);
    const ImageF half = prepare_paper({path, "mnpr", 1.0f, 0.5f}, 16, 8);
    for (std::size_t i = 0; i < base.num_values(); ++i) {
        EXPECT_EQ(flat.data()[i], 0.5f);
        EXPECT_NEAR(half.data()[i], (base.data()[i] - 0.5f) * 0.5f + 0.5f, 1e-6f);
    }
}

TEST(Paper, AmbientCgHeightDerivesNormalsInUnitRangeAndTiles) {
    const std::string path = test::asset(kAmbientHeight);
    const ImageF src = read_image(path);
    const int pw = src.width();
    const ImageF paper = prepare_paper({path, "height", 1.0f, 1.0f}, pw + 11, 9);
    ASSERT_EQ(paper.channels(), 3);
    expect_in_unit_range(paper);
    for (int y = 0; y < 9; ++y)
        for (int x = 0; x < 11; ++x) {
            for (int c = 0; c < 3; ++c) ASSERT_EQ(paper.at(x + pw, y, c), paper.at(x, y, c));
            EXPECT_EQ(paper.at(x, y, 2), src.at(x, y, 0));  // height copied into B
        }
    // A real relief: the normals are not all flat.
    double spread = 0;
    for (int y = 0; y < 9; ++y)
        for (int x = 0; x < 11; ++x) spread += std::fabs(paper.at(x, y, 0) - 0.5f);
    EXPECT_GT(spread, 0.0);
}

TEST(Paper, FlatHeightFieldGivesFlatNormals) {
    // A constant height map written to a temporary file: every normal encodes (0, 0, 1).
    const std::string path = test::output_dir() + "/paper_flat_height.exr";
    write_image(path, ImageF(8, 8, 1, 0.3f));
    const ImageF paper = prepare_paper({path, "height", 1.0f, 1.0f}, 20, 10);
    for (int y = 0; y < 10; ++y)
        for (int x = 0; x < 20; ++x) {
            EXPECT_EQ(paper.at(x, y, 0), 0.5f);
            EXPECT_EQ(paper.at(x, y, 1), 0.5f);
            EXPECT_NEAR(paper.at(x, y, 2), 0.3f, 1e-6f);
        }
}

TEST(Paper, HeightRampGivesNormalsLeaningDownhill) {
    // h = x / 16 on a wrapped ramp: interior normals lean towards -x (R < 0.5), none along y.
    ImageF ramp(16, 4, 1);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 16; ++x) ramp.at(x, y, 0) = float(x) / 16.0f;
    const std::string path = test::output_dir() + "/paper_ramp_height.exr";
    write_image(path, ramp);
    const ImageF paper = prepare_paper({path, "height", 1.0f, 1.0f}, 16, 4);
    for (int x = 1; x < 15; ++x) {
        EXPECT_LT(paper.at(x, 1, 0), 0.5f);
        EXPECT_EQ(paper.at(x, 1, 1), 0.5f);
    }
}

TEST(Paper, OtherScalesSampleBilinearlyWithWrap) {
    const std::string path = test::asset(kMnpr);
    const ImageF one = prepare_paper({path, "mnpr", 1.0f, 1.0f}, 64, 64);
    const ImageF two = prepare_paper({path, "mnpr", 2.0f, 1.0f}, 64, 64);
    expect_in_unit_range(two);
    // Scale 2: output pixel x samples texel coordinate (x + 0.5) / 2 - 0.5, i.e. pixel 2k+1 lies a
    // quarter of the way from texel k to texel k+1.
    for (int k = 0; k < 20; ++k)
        for (int c = 0; c < 3; ++c) {
            // pixel (2k+1, 2j+1) -> texel (k + 0.25, j + 0.25)
            const int j = 3;
            const float t00 = one.at(k, j, c), t10 = one.at(k + 1, j, c), t01 = one.at(k, j + 1, c),
                        t11 = one.at(k + 1, j + 1, c);
            const float top = t00 + (t10 - t00) * 0.25f, bot = t01 + (t11 - t01) * 0.25f;
            EXPECT_NEAR(two.at(2 * k + 1, 2 * j + 1, c), top + (bot - top) * 0.25f, 1e-5f);
        }
}

TEST(Paper, MissingFileNamesThePath) {
    const std::string path = "/nonexistent/folder/paper_that_is_not_there.png";
    try {
        prepare_paper({path, "mnpr", 1.0f, 1.0f}, 8, 8);
        FAIL() << "no error for a missing paper";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
}

//! A copy of a real paper under a name of this test's own (the decoded-file cache is per path).
std::string paper_copy(const std::string& name) {
    const std::string path = test::output_dir() + "/" + name;
    std::filesystem::copy_file(test::asset(kMnpr), path, std::filesystem::copy_options::overwrite_existing);
    return path;
}

bool same_bytes(const ImageF& a, const ImageF& b) {
    return a.width() == b.width() && a.height() == b.height() && a.channels() == b.channels() &&
           std::memcmp(a.data(), b.data(), a.num_values() * sizeof(float)) == 0;
}

TEST(Paper, APrefetchedPaperIsThePaperAndIsDecodedOnce) {
    const std::string path = paper_copy("prefetched.jpg");
    const PaperSpec spec{path, "mnpr", 1.0f, 0.8f};
    const ImageF direct = prepare_paper(spec, 301, 97);  // decoded here
    clear_paper_cache();
    // The prefetch fills the cache: with the file gone afterwards the paper is still prepared.
    std::future<void> prefetch = prefetch_paper(spec);
    ASSERT_TRUE(prefetch.valid());
    prefetch.get();
    std::filesystem::remove(path);
    EXPECT_TRUE(same_bytes(prepare_paper(spec, 301, 97), direct));
    clear_paper_cache();
    EXPECT_THROW(prepare_paper(spec, 301, 97), Error);  // without the cache it is not
    // Readers during the decode wait for it (or decode once themselves) and get the same paper.
    paper_copy("prefetched.jpg");
    prefetch = prefetch_paper(spec);
    std::vector<ImageF> during(3);
    std::vector<std::thread> readers;
    for (ImageF& img : during) readers.emplace_back([&img, &spec] { img = prepare_paper(spec, 301, 97); });
    for (std::thread& t : readers) t.join();
    prefetch.get();
    for (const ImageF& img : during) EXPECT_TRUE(same_bytes(img, direct));
}

TEST(Paper, APrefetchThatFailsLeavesTheErrorToPreparePaper) {
    const std::string path = test::output_dir() + "/not_there_yet.jpg";
    const PaperSpec spec{path, "mnpr", 1.0f, 1.0f};
    std::future<void> prefetch = prefetch_paper(spec);
    EXPECT_NO_THROW(prefetch.get());
    try {
        prepare_paper(spec, 8, 8);
        ADD_FAILURE() << "no error for a missing paper";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("paper file '" + path + "' could not be read"), std::string::npos) << e.what();
    }
    // The failure is not cached: once the file exists it is read.
    std::filesystem::copy_file(test::asset(kMnpr), path);
    EXPECT_EQ(prepare_paper(spec, 8, 8).width(), 8);
    EXPECT_FALSE(prefetch_paper(PaperSpec{}).valid());  // no file, nothing started
}

TEST(Paper, BadSpecsAreRefused) {
    const std::string path = test::asset(kMnpr);
    EXPECT_THROW(prepare_paper({path, "normals?", 1.0f, 1.0f}, 8, 8), Error);
    EXPECT_THROW(prepare_paper({path, "mnpr", 0.0f, 1.0f}, 8, 8), Error);
    EXPECT_THROW(prepare_paper({path, "mnpr", NAN, 1.0f}, 8, 8), Error);
    EXPECT_THROW(prepare_paper({path, "mnpr", 1.0f, -1.0f}, 8, 8), Error);
    EXPECT_THROW(prepare_paper({path, "mnpr", 1.0f, 1.0f}, 0, 8), Error);
    // A single-channel height file is not an MNPR-layout paper.
    EXPECT_THROW(prepare_paper({test::asset(kAmbientHeight), "mnpr", 1.0f, 1.0f}, 8, 8), Error);
}

TEST(Paper, FlatPaperIsHalfEverywhere) {
    const ImageF p = flat_paper(5, 3);
    ASSERT_EQ(p.channels(), 3);
    for (std::size_t i = 0; i < p.num_values(); ++i) EXPECT_EQ(p.data()[i], 0.5f);
}

}  // namespace
}  // namespace aq::stylize
