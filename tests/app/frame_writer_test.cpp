// tests/app/frame_writer_test.cpp — app/frame_writer.h: frames are written in submission order
// with every file complete, at most max_in_flight wait, and the first failure stops the job:
// reported by submit()/finish(), nothing written after it.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "app/frame_writer.h"
#include "core/image.h"
#include "core/io.h"
#include "tests/test_support.h"

namespace aq::app {
namespace {
namespace fs = std::filesystem;

FrameWriter::Frame frame_of(const std::string& path, float value, const std::string& message) {
    FrameWriter::Frame f;
    f.files.emplace_back(path, ImageF(8, 4, 3, value));
    f.done_message = message;
    return f;
}

TEST(FrameWriter, WritesEveryFrameInOrderAndReportsEach) {
    const std::string dir = test::output_dir();
    std::vector<std::string> reported;  // written by the writer thread, read after finish()
    {
        FrameWriter w(2, [&](const std::string& s) { reported.push_back(s); });
        for (int i = 0; i < 6; ++i)
            w.submit(frame_of(dir + "/f" + std::to_string(i) + ".exr", float(i) / 8.0f, "frame " + std::to_string(i)));
        w.finish();
    }
    ASSERT_EQ(reported.size(), 6u);
    for (int i = 0; i < 6; ++i) {
        EXPECT_EQ(reported[std::size_t(i)], "frame " + std::to_string(i));
        const ImageF back = read_image(dir + "/f" + std::to_string(i) + ".exr");
        EXPECT_FLOAT_EQ(back.at(7, 3, 2), float(i) / 8.0f);
    }
}

TEST(FrameWriter, TheFirstFailureStopsTheJobAndNothingIsWrittenAfterIt) {
    const std::string dir = test::output_dir();
    FrameWriter w(1, nullptr);
    w.submit(frame_of(dir + "/ok.exr", 0.5f, ""));
    w.submit(frame_of(dir + "/no_such_folder/bad.exr", 0.5f, ""));  // fails: the folder does not exist
    bool threw = false;
    try {
        for (int i = 0; i < 4; ++i) w.submit(frame_of(dir + "/after" + std::to_string(i) + ".exr", 0.5f, ""));
        w.finish();
    } catch (const Error& e) {
        threw = true;
        EXPECT_NE(std::string(e.what()).find("bad.exr"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(threw);
    EXPECT_TRUE(fs::exists(dir + "/ok.exr"));
    for (int i = 0; i < 4; ++i) {
        // A frame queued before the failure was known may be dropped, never written after it.
        if (fs::exists(dir + "/after" + std::to_string(i) + ".exr"))
            ADD_FAILURE() << "after" << i << ".exr written after the failure";
    }
}

}  // namespace
}  // namespace aq::app
