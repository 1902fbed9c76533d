// tests/app/manifest_test.cpp — provenance manifests and `aquarelle reproduce` (issue 14 item 1;
// docs/provenance.md), through the CLI in this test's own output folder: render -> reproduce ->
// identical; the manifest does not depend on the thread count or the output folder; the manifest
// is embedded in the files; every listed output's SHA-256 is its file's; a changed input byte is
// named; a missing input, another build and a file that is not a manifest are refused with exit 1.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/hash.h"
#include "tests/test_support.h"

namespace aq {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::file_bytes;
using test::run_command;
using test::shell_quote;

const std::string kSize = " --width 96 --height 64 --quiet ";

std::string cli() { return shell_quote(AQ_CLI_EXE); }

int reproduce(const std::string& manifest, const std::string& extra, std::string* log) {
    return run_command(cli() + " reproduce " + shell_quote(manifest) + " --quiet " + extra, log);
}

json load(const std::string& path) { return json::parse(file_bytes(path)); }

void write(const std::string& path, const std::string& text) {
    std::ofstream f(path, std::ios::binary);
    f << text;
}

//! A copy of the Suzanne glTF in its own folder (so a test may change or remove its files).
std::string copy_suzanne(const std::string& dir) {
    const fs::path src = fs::path(test::asset("gltf/Suzanne/glTF/Suzanne.gltf")).parent_path();
    const fs::path dst = fs::path(dir) / "suzanne";
    fs::create_directories(dst);
    for (const auto& e : fs::directory_iterator(src)) fs::copy_file(e.path(), dst / e.path().filename());
    for (const auto& e : fs::directory_iterator(dst))
        fs::permissions(e.path(), fs::perms::owner_write, fs::perm_options::add);
    return (dst / "Suzanne.gltf").string();
}

TEST(Manifest, RenderReproduceIdenticalAndIndependentOfThreadsAndFolder) {
    const std::string dir = test::output_dir();
    const std::string scene = test::source_dir() + "/scenes/data/suzanne.json";
    std::string log;
    // Two runs: other thread counts, other folders (same layout inside them), other working folder.
    fs::create_directories(dir + "/a");
    fs::create_directories(dir + "/b/deeper");
    ASSERT_EQ(run_command(cli() + " render " + shell_quote(scene) + kSize + "--threads 1 --targets " +
                              shell_quote(dir + "/a/t") + " --out " + shell_quote(dir + "/a/img.png"), &log), 0) << log;
    ASSERT_EQ(run_command("cd " + shell_quote(dir + "/b") + " && " + cli() + " render " + shell_quote(scene) + kSize +
                              "--threads 2 --targets deeper/t --out deeper/img.png", &log), 0) << log;
    const std::string ma = dir + "/a/img.png.json", mb = dir + "/b/deeper/img.png.json";
    ASSERT_TRUE(fs::exists(ma)) << "no sidecar manifest";
    EXPECT_EQ(file_bytes(ma), file_bytes(mb)) << "the manifest depends on the thread count or the output folder";

    const json m = load(ma);
    EXPECT_EQ(m.at("aquarelle_manifest"), 1);
    for (const char* k : {"build", "request", "image", "inputs", "pipeline", "outputs"}) EXPECT_TRUE(m.contains(k)) << k;
    EXPECT_FALSE(m.at("build").at("commit").get<std::string>().empty());
    EXPECT_NE(m.at("build").at("flags").get<std::string>().find("-ffp-contract=off"), std::string::npos);
    // The inputs: the scene file and its glTF, with the SHA-256 of their bytes.
    bool scene_listed = false;
    for (const json& in : m.at("inputs"))
        if (in.at("path") == fs::path(scene).lexically_normal().string()) {
            scene_listed = true;
            const std::string b = file_bytes(scene);
            EXPECT_EQ(in.at("sha256"), sha256_hex(b.data(), b.size()));
        }
    EXPECT_TRUE(scene_listed) << m.at("inputs").dump();
    // The compiled pipeline: every step with its variant and resolved parameters.
    ASSERT_FALSE(m.at("pipeline").at("steps").empty());
    for (const json& s : m.at("pipeline").at("steps")) {
        EXPECT_FALSE(s.at("variant").get<std::string>().empty());
        EXPECT_TRUE(s.at("params").is_object());
    }
    // Outputs: every target's EXR and the image, each with the SHA-256 of the file's bytes; the
    // image last, targets in pipeline order (the G-buffer's before the steps').
    const json& outs = m.at("outputs");
    ASSERT_GT(outs.size(), 10u);
    EXPECT_EQ(outs.back().at("kind"), "out");
    EXPECT_EQ(outs.back().at("file"), "img.png");
    for (const json& o : outs) {
        const std::string b = file_bytes(dir + "/a/" + o.at("file").get<std::string>());
        ASSERT_FALSE(b.empty()) << o.dump();
        EXPECT_EQ(o.at("sha256"), sha256_hex(b.data(), b.size())) << o.dump();
    }
    // Embedded: the manifest without "outputs" is in the PNG (tEXt Description) and the EXRs.
    json core = m;
    core.erase("outputs");
    const std::string png = file_bytes(dir + "/a/img.png");
    EXPECT_NE(png.find("Description"), std::string::npos);
    EXPECT_NE(png.find(core.dump()), std::string::npos) << "the PNG does not embed the manifest";
    EXPECT_NE(file_bytes(dir + "/a/t/depth.linear.exr").find(core.dump()), std::string::npos);

    ASSERT_EQ(reproduce(ma, "--threads 2", &log), 0) << log;
    EXPECT_NE(log.find("identical"), std::string::npos) << log;
}

TEST(Manifest, AnimationFramesAndSweepValuesAreReproducedOneByOne) {
    const std::string dir = test::output_dir();
    std::string log;
    ASSERT_EQ(run_command(cli() + " render procedural:swatches" + kSize + "--frames 0-2 --orbit 15 --out " +
                              shell_quote(dir + "/f_####.png"), &log), 0) << log;
    EXPECT_EQ(load(dir + "/f_0002.png.json").at("request").at("frame"), 2);
    ASSERT_EQ(reproduce(dir + "/f_0002.png.json", "", &log), 0) << log;
    ASSERT_EQ(run_command(cli() + " render procedural:swatches" + kSize + "--sweep edge_darken.intensity=0:4:3 --out " +
                              shell_quote(dir + "/s_####.exr"), &log), 0) << log;
    EXPECT_EQ(load(dir + "/s_0001.exr.json").at("request").at("sweep").at("index"), 1);
    ASSERT_EQ(reproduce(dir + "/s_0001.exr.json", "", &log), 0) << log;
    // Another sweep value's manifest under this image's name is not identical: named, exit 3.
    json other = load(dir + "/s_0001.exr.json");
    other["outputs"] = load(dir + "/s_0002.exr.json").at("outputs");
    write(dir + "/s_0001.exr.json", other.dump());
    EXPECT_EQ(reproduce(dir + "/s_0001.exr.json", "", &log), 3) << log;
    EXPECT_NE(log.find("first differing output: the image (s_0002.exr)"), std::string::npos) << log;
    EXPECT_NE(log.find("max_abs"), std::string::npos) << "no pixel metrics: " << log;
}

// --compression none changes the files' bytes, not their pixels: the request records it, reproduce
// writes the same bytes again; a manifest from before the option (no key) reproduces as "fast".
TEST(Manifest, TheCompressionIsRecordedAndReproduced) {
    const std::string dir = test::output_dir();
    std::string log;
    ASSERT_EQ(run_command(cli() + " render procedural:swatches" + kSize + "--compression none --targets " +
                              shell_quote(dir + "/t") + " --out " + shell_quote(dir + "/n.png"), &log), 0) << log;
    ASSERT_EQ(run_command(cli() + " render procedural:swatches" + kSize + "--out " + shell_quote(dir + "/f.png"), &log), 0)
        << log;
    EXPECT_EQ(load(dir + "/n.png.json").at("request").at("compression"), "none");
    EXPECT_EQ(load(dir + "/f.png.json").at("request").at("compression"), "fast");
    EXPECT_GT(file_bytes(dir + "/n.png").size(), file_bytes(dir + "/f.png").size());
    ASSERT_EQ(reproduce(dir + "/n.png.json", "", &log), 0) << log;
    EXPECT_NE(log.find("identical"), std::string::npos) << log;
    json old = load(dir + "/f.png.json");
    old["request"].erase("compression");
    write(dir + "/old.json", old.dump());
    ASSERT_EQ(reproduce(dir + "/old.json", "", &log), 0) << log;
    json bad = load(dir + "/f.png.json");
    bad["request"]["compression"] = "zip";
    write(dir + "/bad.json", bad.dump());
    EXPECT_EQ(reproduce(dir + "/bad.json", "", &log), 1) << log;
    EXPECT_NE(log.find("compression 'zip'"), std::string::npos) << log;
}

TEST(Manifest, AChangedInputByteIsNamedAndAMissingInputRefused) {
    const std::string dir = test::output_dir();
    const std::string gltf = copy_suzanne(dir);
    std::string log;
    ASSERT_EQ(run_command(cli() + " render " + shell_quote(gltf) + kSize + "--out " + shell_quote(dir + "/s.png"), &log), 0) << log;
    const std::string m = dir + "/s.png.json";
    ASSERT_EQ(reproduce(m, "", &log), 0) << log;
    // One byte of the mesh buffer changed (a vertex coordinate's low mantissa byte).
    const std::string bin = fs::path(gltf).parent_path().string() + "/Suzanne.bin";
    std::string b = file_bytes(bin);
    ASSERT_GT(b.size(), 1000u);
    b[1000] = char(b[1000] ^ 0x01);
    write(bin, b);
    EXPECT_EQ(reproduce(m, "", &log), 3) << log;
    EXPECT_NE(log.find("input changed: " + fs::path(bin).lexically_normal().string()), std::string::npos) << log;
    // Missing: refused before rendering, naming the file.
    fs::remove(bin);
    EXPECT_EQ(reproduce(m, "", &log), 1) << log;
    EXPECT_NE(log.find("missing"), std::string::npos) << log;
    EXPECT_NE(log.find("Suzanne.bin"), std::string::npos) << log;
}

TEST(Manifest, AnotherBuildOrNotAManifestIsRefused) {
    const std::string dir = test::output_dir();
    std::string log;
    ASSERT_EQ(run_command(cli() + " render procedural:swatches" + kSize + "--out " + shell_quote(dir + "/p.png"), &log), 0) << log;
    json m = load(dir + "/p.png.json");
    m["build"]["commit"] = "0123456789abcdef0123456789abcdef01234567";
    write(dir + "/other.json", m.dump());
    EXPECT_EQ(reproduce(dir + "/other.json", "", &log), 1) << log;
    EXPECT_NE(log.find("another build"), std::string::npos) << log;
    EXPECT_NE(log.find("0123456789abcdef"), std::string::npos) << log;
    // --any-version renders and compares, and still says the build differs (exit 3).
    EXPECT_EQ(reproduce(dir + "/other.json", "--any-version", &log), 3) << log;
    EXPECT_NE(log.find("build differs"), std::string::npos) << log;

    write(dir + "/plain.json", "{\"hello\": 1}");
    EXPECT_EQ(reproduce(dir + "/plain.json", "", &log), 1) << log;
    EXPECT_NE(log.find("not an Aquarelle manifest"), std::string::npos) << log;
    m = load(dir + "/p.png.json");
    m["aquarelle_manifest"] = 99;
    write(dir + "/future.json", m.dump());
    EXPECT_EQ(reproduce(dir + "/future.json", "", &log), 1) << log;
    EXPECT_NE(log.find("format 99"), std::string::npos) << log;
    EXPECT_EQ(reproduce(dir + "/nothing_here.json", "", &log), 1) << log;
    EXPECT_EQ(run_command(cli() + " reproduce", &log), 2) << log;
}

}  // namespace
}  // namespace aq
