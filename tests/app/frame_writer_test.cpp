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

// Issue 47 item 8: a frame is written as a set. A failure while its files are prepared leaves the
// old set whole (files and claim); a second writer of the same claim is refused while the first
// holds it; a kill cannot leave a claim on files that are not its own (the old claim is removed
// before the renames, the new one written after them).
FrameWriter::Frame set_of(const std::string& dir, const std::string& second, float value) {
    FrameWriter::Frame f;
    f.files.emplace_back(dir + "/a.exr", ImageF(8, 4, 3, value));
    f.files.emplace_back(second, ImageF(8, 4, 3, value));
    f.files.emplace_back(dir + "/out.png", ImageF(8, 4, 3, value));
    f.claim = dir + "/out.png.json";
    f.after = [claim = f.claim, value](const std::vector<std::string>& sha, double, double) {
        const std::string text = std::to_string(value) + " " + sha[0] + "\n";
        write_file_atomically(claim, text.data(), text.size());
    };
    return f;
}

TEST(FrameWriter, AFrameIsWrittenAsASetOrNotAtAll) {
    const std::string dir = test::output_dir();
    {
        FrameWriter w(1, nullptr);
        w.submit(set_of(dir, dir + "/b.exr", 0.25f));
        w.finish();
    }
    const std::string a = test::file_bytes(dir + "/a.exr"), out = test::file_bytes(dir + "/out.png"),
                      claim = test::file_bytes(dir + "/out.png.json");
    ASSERT_FALSE(claim.empty());
    // The second file cannot be written (its folder is missing): nothing of the new set replaces the old.
    {
        FrameWriter w(1, nullptr);
        w.submit(set_of(dir, dir + "/missing/b.exr", 0.75f));
        EXPECT_THROW(w.finish(), Error);
    }
    EXPECT_EQ(test::file_bytes(dir + "/a.exr"), a) << "the first file of a failed set replaced the old one";
    EXPECT_EQ(test::file_bytes(dir + "/out.png"), out);
    EXPECT_EQ(test::file_bytes(dir + "/out.png.json"), claim) << "the old set lost its claim";
    // A second writer while the claim is held: refused, nothing written.
    {
        WriteLock held(dir + "/out.png.json");
        FrameWriter w(1, nullptr);
        w.submit(set_of(dir, dir + "/b.exr", 0.5f));
        try {
            w.finish();
            ADD_FAILURE() << "a second writer was not refused";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("another process is writing"), std::string::npos) << e.what();
        }
    }
    EXPECT_EQ(test::file_bytes(dir + "/out.png.json"), claim);
    // Released: the next writer succeeds and no lock or temporary is left in the folder.
    {
        FrameWriter w(1, nullptr);
        w.submit(set_of(dir, dir + "/b.exr", 0.5f));
        w.finish();
    }
    EXPECT_NE(test::file_bytes(dir + "/out.png.json"), claim);
    for (const auto& e : fs::directory_iterator(dir))
        EXPECT_NE(e.path().filename().string()[0], '.') << "left behind: " << e.path();
}

}  // namespace
}  // namespace aq::app
