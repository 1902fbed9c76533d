// tests/app/grid_test.cpp — `aquarelle grid` (issue 14 item 2; docs/grid.md): the layout of a 2 x 2
// study, each cell equal to the image `render` makes of that combination, labels drawn; the
// report's content; combinations over the limit and bad axes refused before anything is written.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "app/grid.h"
#include "core/image.h"
#include "core/io.h"
#include "tests/test_support.h"

namespace aq::app {
namespace {

namespace fs = std::filesystem;
constexpr int kW = 320, kH = 48;  // wide enough for the whole labels (narrow cells cut them)

std::string cli() { return test::shell_quote(AQ_CLI_EXE); }
const std::string kScene = "procedural:swatches";
const std::string kSize = " --width " + std::to_string(kW) + " --height " + std::to_string(kH) + " --quiet ";

//! The report's one image folder (img.TAG): "" when there is none or more than one.
std::string img_folder(const std::string& report) {
    std::string found;
    int n = 0;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(report, ec))
        if (e.is_directory() && e.path().filename().string().rfind("img", 0) == 0) found = e.path().filename().string(), ++n;
    return n == 1 ? found : "";
}

TEST(GridCli, TwoByTwoLayoutCellsAndLabels) {
    const std::string dir = test::output_dir();
    std::string log;
    const std::string variants[2] = {"joint_bilateral", "mnpr"};
    const std::string values[2] = {"0.5", "3"};
    ASSERT_EQ(test::run_command(cli() + " grid " + kScene + kSize + "--styles wc18 --variant bleed=" + variants[0] + "," +
                                    variants[1] + " --set edge_darken.intensity=" + values[0] + "," + values[1] + " --out " +
                                    test::shell_quote(dir + "/sheet.png") + " --report " + test::shell_quote(dir + "/report"),
                                &log), 0) << log;
    const ImageF sheet = read_image(dir + "/sheet.png");
    const int cw = kW + kSheetMargin, ch = kH + kSheetLabelHeight + kSheetMargin;
    ASSERT_EQ(sheet.width(), 2 * cw + kSheetMargin);  // 2 columns (the values)
    ASSERT_EQ(sheet.height(), 2 * ch + kSheetMargin);  // 2 rows (the variants)
    double label_ink[4] = {0, 0, 0, 0};
    for (int r = 0; r < 2; ++r)
        for (int c = 0; c < 2; ++c) {
            // The cell is the image render makes of the same combination.
            const std::string one = dir + "/one_" + std::to_string(r) + std::to_string(c) + ".png";
            ASSERT_EQ(test::run_command(cli() + " render " + kScene + kSize + "--style wc18 --variant bleed=" + variants[r] +
                                            " --set edge_darken.intensity=" + values[c] + " --out " + test::shell_quote(one),
                                        &log), 0) << log;
            const ImageF ref = read_image(one);
            const int x0 = kSheetMargin + c * cw, y0 = kSheetMargin + r * ch;
            int differing = 0;
            for (int y = 0; y < kH; ++y)
                for (int x = 0; x < kW; ++x)
                    for (int k = 0; k < 3; ++k) differing += sheet.at(x0 + x, y0 + kSheetLabelHeight + y, k) != ref.at(x, y, k);
            EXPECT_EQ(differing, 0) << "cell " << r << "," << c;
            // Its label strip has text (dark pixels) on the white background.
            for (int y = y0; y < y0 + kSheetLabelHeight; ++y)
                for (int x = x0; x < x0 + kW; ++x) label_ink[r * 2 + c] += 1.0 - sheet.at(x, y, 0);
        }
    for (double ink : label_ink) EXPECT_GT(ink, 20.0);
    // Different labels, different strips ("..., edge_darken.intensity=0.5" vs "...=3").
    EXPECT_NE(label_ink[0], label_ink[1]);
    // The margins stay white.
    for (int y = 0; y < sheet.height(); ++y) EXPECT_EQ(sheet.at(2, y, 0), 1.0f) << y;

    const std::string html = test::file_bytes(dir + "/report/index.html");
    ASSERT_FALSE(html.empty());
    EXPECT_NE(html.find("bleed=joint_bilateral, edge_darken.intensity=0.5"), std::string::npos);
    EXPECT_NE(html.find("bleed=mnpr, edge_darken.intensity=3"), std::string::npos);
    EXPECT_NE(html.find("(baseline)"), std::string::npos);
    EXPECT_NE(html.find("PSNR"), std::string::npos);
    EXPECT_NE(html.find("<th>step 0</th>"), std::string::npos);
    EXPECT_NE(html.find(" ms"), std::string::npos);
    EXPECT_NE(html.find("edge_darken.intensity</th>"), std::string::npos) << "the differing parameter is not listed";
    EXPECT_TRUE(fs::exists(dir + "/report/" + img_folder(dir + "/report") + "/c3_diff.png"));
    EXPECT_TRUE(fs::exists(dir + "/report/" + img_folder(dir + "/report") + "/c0_s0.png"));
}

TEST(GridCli, BadStudiesAreRefusedBeforeAnythingIsWritten) {
    const std::string dir = test::output_dir() + "/bad";  // the process's folder may hold other tests' files
    fs::create_directories(dir);
    const std::string out = " --out " + test::shell_quote(dir + "/sheet.png");
    std::string log;
    // 65 combinations: 5 x 13.
    EXPECT_EQ(test::run_command(cli() + " grid " + kScene + kSize + "--set edge_darken.intensity=0,1,2,3,4 --set "
                                        "bleed.strength=0,0.1,0.2,0.3,0.4,0.5,0.6,0.7,0.8,0.9,1,1.1,1.2" + out, &log), 2) << log;
    EXPECT_NE(log.find("more than 64 combinations"), std::string::npos) << log;
    EXPECT_EQ(test::run_command(cli() + " grid " + kScene + kSize + "--styles wc18,wc18" + out, &log), 2) << log;
    EXPECT_NE(log.find("given twice"), std::string::npos) << log;
    EXPECT_EQ(test::run_command(cli() + " grid " + kScene + kSize + "--styles wc18 --variant bleed=nope,mnpr" + out, &log), 1) << log;
    EXPECT_NE(log.find("nope"), std::string::npos) << log;
    EXPECT_EQ(test::run_command(cli() + " grid " + kScene + kSize + "--styles wc16,wc18 --baseline 2 --report " +
                                    test::shell_quote(dir + "/r") + out, &log), 2) << log;
    EXPECT_EQ(test::run_command(cli() + " grid " + kScene + kSize + "--set edge_darken.intensity=" + out, &log), 2) << log;
    EXPECT_FALSE(fs::exists(dir + "/sheet.png"));
    EXPECT_FALSE(fs::exists(dir + "/r"));
}

// Issue 47 items 7 and 8: cells carry what made them (another study, size or a tampered cell is
// refused by --from-cells); the sheet may not be one of the report's own files; a second report
// replaces the first as a set (one image folder, the one index.html names).
TEST(GridCli, CellsFromAnotherStudyOrSizeAreRefusedAndReportsAreWrittenAsASet) {
    const std::string dir = test::output_dir();
    std::string log;
    const std::string axes = " --set edge_darken.intensity=1,2 ";
    const std::string cells = " --cells " + test::shell_quote(dir + "/cells");
    for (int i = 0; i < 2; ++i)
        ASSERT_EQ(test::run_command(cli() + " grid " + kScene + kSize + axes + "--shard " + std::to_string(i) + "/2" + cells, &log), 0)
            << log;
    const std::string sheet = " --out " + test::shell_quote(dir + "/sheet.png");
    EXPECT_EQ(test::run_command(cli() + " grid " + kScene + kSize + axes + "--from-cells" + cells + sheet, &log), 0) << log;
    EXPECT_TRUE(fs::exists(dir + "/sheet.png"));
    // Another size (the default 640 x 360), another study: refused, naming the field.
    EXPECT_EQ(test::run_command(cli() + " grid " + kScene + " --quiet" + axes + "--from-cells" + cells + sheet, &log), 1) << log;
    EXPECT_NE(log.find("another grid (height: 48, this command: 360)"), std::string::npos) << log;
    EXPECT_EQ(test::run_command(cli() + " grid " + kScene + kSize + "--set edge_darken.intensity=1,3 --from-cells" + cells + sheet, &log),
              1) << log;
    EXPECT_NE(log.find("another grid (sets"), std::string::npos) << log;
    // A cell replaced by another file: refused.
    fs::copy_file(dir + "/cells/cell_0000.exr", dir + "/cells/cell_0001.exr", fs::copy_options::overwrite_existing);
    EXPECT_EQ(test::run_command(cli() + " grid " + kScene + kSize + axes + "--from-cells" + cells + sheet, &log), 1) << log;
    EXPECT_NE(log.find("SHA-256 differs"), std::string::npos) << log;

    // The sheet inside the report's own files: a usage error before anything is rendered.
    const std::string rep = " --report " + test::shell_quote(dir + "/report");
    fs::create_directories(dir + "/report/img");
    EXPECT_EQ(test::run_command(cli() + " grid " + kScene + kSize + axes + rep + " --out " +
                                    test::shell_quote(dir + "/report/img/c0_final.png"), &log), 2) << log;
    EXPECT_NE(log.find("one of the report's own files"), std::string::npos) << log;
    EXPECT_TRUE(fs::is_empty(dir + "/report/img"));
    EXPECT_FALSE(fs::exists(dir + "/report/index.html"));
    // Two reports into one folder: the second's images replace the first's as a set.
    ASSERT_EQ(test::run_command(cli() + " grid " + kScene + kSize + axes + rep + " --out " + test::shell_quote(dir + "/report/s.png"),
                                &log), 0) << log;
    const std::string first = img_folder(dir + "/report");
    ASSERT_FALSE(first.empty());
    ASSERT_EQ(test::run_command(cli() + " grid " + kScene + kSize + " --set edge_darken.intensity=1,3" + rep + " --out " +
                                    test::shell_quote(dir + "/report/s.png"), &log), 0) << log;
    const std::string second = img_folder(dir + "/report");
    ASSERT_FALSE(second.empty()) << "more than one image folder left";
    EXPECT_NE(first, second);
    EXPECT_NE(test::file_bytes(dir + "/report/index.html").find(second + "/c1_final.png"), std::string::npos);
}

TEST(Grid, CellsAndLayoutFollowTheAxes) {
    GridOptions g;
    g.styles = {"wc16", "wc18"};
    g.set_axes = {{"edge_darken.intensity", {"1", "2", "3"}}};
    int rows = 0, cols = 0;
    const auto cells = grid_cells(g, &rows, &cols);
    ASSERT_EQ(cells.size(), 6u);
    EXPECT_EQ(rows, 2);
    EXPECT_EQ(cols, 3);
    EXPECT_EQ(cells[4].style, "wc18");
    EXPECT_EQ(cells[4].assignments.sets, std::vector<std::string>{"edge_darken.intensity=2"});
    EXPECT_EQ(cells[4].assignments.label, "wc18, edge_darken.intensity=2");
    g.set_axes = {{"edge_darken.intensity", {"1"}}};  // a single value is not an axis: one row of styles
    EXPECT_EQ(grid_cells(g, &rows, &cols).size(), 2u);
    EXPECT_EQ(rows, 1);
    EXPECT_EQ(cols, 2);
}

}  // namespace
}  // namespace aq::app
