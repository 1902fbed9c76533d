// tests/app/manifest_test.cpp — provenance manifests and `aquarelle reproduce` (issue 14 item 1;
// docs/provenance.md), through the CLI in this test's own output folder: render -> reproduce ->
// identical; the manifest does not depend on the thread count or the output folder; the manifest
// is embedded in the files; every listed output's SHA-256 is its file's; a changed input byte is
// named; a missing input, another build and a file that is not a manifest are refused with exit 1.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
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

// A request key added after manifests were first written: the manifest at `path` (whose image was
// made with the value old manifests mean) reproduces without the key, and `bad` is refused by
// name (exit 1).
void expect_optional_request_key(const std::string& path, const std::string& key, const std::string& bad) {
    const std::string dir = fs::path(path).parent_path().string();
    std::string log;
    json old = load(path);
    old["request"].erase(key);
    write(dir + "/old_" + key + ".json", old.dump());
    ASSERT_EQ(reproduce(dir + "/old_" + key + ".json", "", &log), 0) << log;
    json wrong = load(path);
    wrong["request"][key] = bad;
    write(dir + "/bad_" + key + ".json", wrong.dump());
    EXPECT_EQ(reproduce(dir + "/bad_" + key + ".json", "", &log), 1) << log;
    EXPECT_NE(log.find(key + " '" + bad + "'"), std::string::npos) << log;
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
    expect_optional_request_key(dir + "/f.png.json", "compression", "zip");
}

// --bypass is part of the request and reproduced; a manifest from before the option (no key) means
// no step bypassed; a bypass reproduce cannot apply is refused naming the step.
TEST(Manifest, BypassedStepsAreRecordedAndReproduced) {
    const std::string dir = test::output_dir();
    std::string log;
    ASSERT_EQ(run_command(cli() + " render procedural:swatches" + kSize + "--bypass edge_darken --out " +
                              shell_quote(dir + "/b.png"), &log), 0) << log;
    ASSERT_EQ(run_command(cli() + " render procedural:swatches" + kSize + "--out " + shell_quote(dir + "/f.png"), &log), 0)
        << log;
    EXPECT_EQ(load(dir + "/b.png.json").at("request").at("bypass"), json::array({"edge_darken"}));
    EXPECT_NE(file_bytes(dir + "/b.png"), file_bytes(dir + "/f.png")) << "bypassing edge darkening changed nothing";
    ASSERT_EQ(reproduce(dir + "/b.png.json", "", &log), 0) << log;
    EXPECT_NE(log.find("identical"), std::string::npos) << log;
    json old = load(dir + "/f.png.json");
    old["request"].erase("bypass");
    write(dir + "/old.json", old.dump());
    ASSERT_EQ(reproduce(dir + "/old.json", "", &log), 0) << log;
    json bad = load(dir + "/b.png.json");
    bad["request"]["bypass"] = json::array({"bleed"});
    write(dir + "/bad.json", bad.dump());
    EXPECT_EQ(reproduce(dir + "/bad.json", "", &log), 1) << log;
    EXPECT_NE(log.find("--bypass 'bleed'"), std::string::npos) << log;
    EXPECT_EQ(run_command(cli() + " render procedural:swatches" + kSize + "--style none --bypass edge_darken --out " +
                              shell_quote(dir + "/n.png"), &log), 2) << log;
}

// --timings (issue 48 item 6): the phases on stderr, even with --quiet, and in the sidecar as
// "timings", which is not part of the image: the image's bytes and the request are those of the
// same render without it, and reproduce says identical.
TEST(Manifest, TimingsArePrintedAndRecordedButAreNotPartOfTheImage) {
    const std::string dir = test::output_dir();
    std::string log;
    ASSERT_EQ(run_command(cli() + " render procedural:swatches" + kSize + "--timings --out " + shell_quote(dir + "/t.png"), &log), 0)
        << log;
    for (const char* want : {"timings of ", "load", "gbuffer", "stage edge_darken", "encode+write", "sum"})
        EXPECT_NE(log.find(want), std::string::npos) << want << " not printed: " << log;
    ASSERT_EQ(run_command(cli() + " render procedural:swatches" + kSize + "--out " + shell_quote(dir + "/p.png"), &log), 0)
        << log;
    EXPECT_EQ(log.find("timings"), std::string::npos) << log;
    EXPECT_EQ(file_bytes(dir + "/t.png"), file_bytes(dir + "/p.png"));
    const json t = load(dir + "/t.png.json"), p = load(dir + "/p.png.json");
    EXPECT_EQ(t.at("request"), p.at("request"));
    EXPECT_FALSE(p.contains("timings"));
    std::vector<std::string> names;
    for (const json& ph : t.at("timings").at("phases")) {
        names.push_back(ph.at("phase").get<std::string>());
        EXPECT_GE(ph.at("ms").get<double>(), 0.0) << names.back();
    }
    for (const char* want : {"load", "prepare", "paper", "gbuffer", "convert", "encode+write", "commit"})
        EXPECT_NE(std::find(names.begin(), names.end(), want), names.end()) << want;
    EXPECT_NE(std::find_if(names.begin(), names.end(), [](const std::string& n) { return n.rfind("stage edge_darken", 0) == 0; }),
              names.end());
    ASSERT_EQ(reproduce(dir + "/t.png.json", "", &log), 0) << log;
    EXPECT_NE(log.find("identical"), std::string::npos) << log;
}

// --antialias is part of the request: both settings reproduce; a manifest from before the option
// (no key) reproduces with one sample per pixel, what such images were rendered with; an unknown
// value is refused, by the CLI (usage, exit 2) and by reproduce (exit 1).
TEST(Manifest, TheAntialiasingIsRecordedAndReproduced) {
    const std::string dir = test::output_dir();
    std::string log;
    ASSERT_EQ(run_command(cli() + " render procedural:swatches" + kSize + "--out " + shell_quote(dir + "/c.png"), &log), 0)
        << log;
    ASSERT_EQ(run_command(cli() + " render procedural:swatches" + kSize + "--antialias none --out " +
                              shell_quote(dir + "/n.png"), &log), 0) << log;
    EXPECT_EQ(load(dir + "/c.png.json").at("request").at("antialias"), "coverage");
    EXPECT_EQ(load(dir + "/n.png.json").at("request").at("antialias"), "none");
    EXPECT_NE(file_bytes(dir + "/c.png"), file_bytes(dir + "/n.png")) << "the swatches' edges are antialiased";
    ASSERT_EQ(reproduce(dir + "/c.png.json", "", &log), 0) << log;
    ASSERT_EQ(reproduce(dir + "/n.png.json", "", &log), 0) << log;
    expect_optional_request_key(dir + "/n.png.json", "antialias", "msaa");
    EXPECT_EQ(run_command(cli() + " render procedural:swatches" + kSize + "--antialias msaa --out " +
                              shell_quote(dir + "/x.png"), &log), 2) << log;
    EXPECT_NE(log.find("--antialias expects coverage or none"), std::string::npos) << log;
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

// Issue 47 item 1: "identical" means every file the manifest names is there with its SHA-256, the
// request is read strictly, and the render matches. Each way of fooling it is refused.
TEST(ManifestTrust, ReplacedOrMissingOriginalsAndEditedOutputListsAreNotIdentical) {
    const std::string dir = test::output_dir();
    std::string log;
    ASSERT_EQ(run_command(cli() + " render procedural:swatches" + kSize + "--targets " + shell_quote(dir + "/t") + " --out " +
                              shell_quote(dir + "/p.png"), &log), 0) << log;
    ASSERT_EQ(run_command(cli() + " render procedural:swatches" + kSize + "--set edge_darken.intensity=3 --out " +
                              shell_quote(dir + "/other.png"), &log), 0) << log;
    const std::string m = dir + "/p.png.json";
    ASSERT_EQ(reproduce(m, "", &log), 0) << log;
    const std::string good = file_bytes(dir + "/p.png");

    // The image beside the manifest replaced by another picture: exit 3, named.
    write(dir + "/p.png", file_bytes(dir + "/other.png"));
    EXPECT_EQ(reproduce(m, "", &log), 3) << log;
    EXPECT_NE(log.find("changed since it was written: the image (p.png)"), std::string::npos) << log;
    EXPECT_EQ(log.find("identical"), std::string::npos) << log;
    // ... or gone.
    fs::remove(dir + "/p.png");
    EXPECT_EQ(reproduce(m, "", &log), 3) << log;
    EXPECT_NE(log.find("missing beside the manifest: the image (p.png)"), std::string::npos) << log;
    write(dir + "/p.png", good);
    ASSERT_EQ(reproduce(m, "", &log), 0) << log;

    const json orig = load(m);
    auto try_edit = [&](const std::function<void(json&)>& edit, int status, const std::string& message) {
        json e = orig;
        edit(e);
        write(dir + "/edited.json", e.dump());
        EXPECT_EQ(reproduce(dir + "/edited.json", "", &log), status) << e.dump().substr(0, 300) << "\n" << log;
        EXPECT_NE(log.find(message), std::string::npos) << log;
        EXPECT_EQ(log.find("identical"), std::string::npos) << log;
    };
    // The outputs list emptied, or one target left out, or a file outside the manifest's folder.
    try_edit([](json& e) { e["outputs"] = json::array(); }, 1, "lists no file");
    try_edit([](json& e) { e["outputs"].erase(0); }, 3, "produced again but not in the manifest");
    try_edit([](json& e) { e["outputs"][0]["file"] = "../../../../etc/passwd"; }, 1, "not a file inside the manifest's folder");
    try_edit([](json& e) { e["outputs"].push_back(e["outputs"][0]); }, 1, "listed twice");
    // Request fields typed and ranged exactly as the command line's options.
    try_edit([](json& e) { e["request"]["width"] = 4294967296ull + 96; }, 1, "request.width");
    try_edit([](json& e) { e["request"]["width"] = 96.9; }, 1, "expected an integer");
    try_edit([](json& e) { e["request"]["height"] = true; }, 1, "expected an integer");
    try_edit([](json& e) { e["request"]["width"] = -96; }, 1, "request.width");
    try_edit([](json& e) { e["request"]["ssaa"] = 9; }, 1, "request.ssaa");
    try_edit([](json& e) { e["request"]["frame"] = 2147483647; }, 1, "request.frame");
    try_edit([](json& e) { e["request"]["fps"] = 1e300; }, 1, "request.fps");
    try_edit([](json& e) { e["request"]["orbit_deg"] = "15"; }, 1, "expected a number");
    try_edit([](json& e) { e["request"]["targets"] = 1; }, 1, "expected a boolean");
}

// Item 3: a manifest lifts no safety switch, and its input list is bounded and never read by itself.
TEST(ManifestTrust, SafetySwitchesNeedTheUsersFlagAndInputsAreBoundedAndNotReadForTheManifest) {
    const std::string dir = test::output_dir();
    std::string log;
    ASSERT_EQ(run_command(cli() + " render procedural:swatches" + kSize + "--out " + shell_quote(dir + "/p.png"), &log), 0) << log;
    const json orig = load(dir + "/p.png.json");
    // A render made with --allow-outside-files reproduces only with the user's own flag.
    ASSERT_EQ(run_command(cli() + " render procedural:swatches" + kSize + "--allow-outside-files --out " +
                              shell_quote(dir + "/o.png"), &log), 0) << log;
    EXPECT_EQ(reproduce(dir + "/o.png.json", "", &log), 1) << log;
    EXPECT_NE(log.find("pass --allow-outside-files"), std::string::npos) << log;
    EXPECT_EQ(reproduce(dir + "/o.png.json", "--allow-outside-files", &log), 0) << log;
    // A manifest edited to switch it on: refused without the flag; with it, not identical (the
    // files beside it were made without).
    json e = orig;
    e["request"]["allow_outside_files"] = true;
    write(dir + "/outside.json", e.dump());
    EXPECT_EQ(reproduce(dir + "/outside.json", "", &log), 1) << log;
    EXPECT_NE(log.find("pass --allow-outside-files"), std::string::npos) << log;
    EXPECT_EQ(reproduce(dir + "/outside.json", "--allow-outside-files", &log), 3) << log;

    // A file the render never reads, listed with its true SHA-256: not identical, and its hash is
    // not printed (reproduce does not read it).
    write(dir + "/secret.txt", "not an input of any render");
    const std::string secret = file_bytes(dir + "/secret.txt");
    e = orig;
    e["inputs"].push_back({{"path", fs::path(dir + "/secret.txt").lexically_normal().string()},
                           {"bytes", secret.size()},
                           {"sha256", sha256_hex(secret.data(), secret.size())}});
    write(dir + "/extra.json", e.dump());
    EXPECT_EQ(reproduce(dir + "/extra.json", "", &log), 3) << log;
    EXPECT_NE(log.find("input not read by the render: "), std::string::npos) << log;
    EXPECT_EQ(log.find(sha256_hex(secret.data(), secret.size()).substr(0, 16)), std::string::npos) << log;
    // The same path twice, a relative path, more entries than the bound: refused before rendering.
    e["inputs"].push_back(e["inputs"].back());
    write(dir + "/dup.json", e.dump());
    EXPECT_EQ(reproduce(dir + "/dup.json", "", &log), 1) << log;
    EXPECT_NE(log.find("listed twice"), std::string::npos) << log;
    e = orig;
    e["inputs"] = json::array();
    for (int i = 0; i < 5000; ++i)
        e["inputs"].push_back({{"path", "/nonexistent/" + std::to_string(i)}, {"bytes", 1}, {"sha256", std::string(64, 'a')}});
    write(dir + "/many.json", e.dump());
    EXPECT_EQ(reproduce(dir + "/many.json", "", &log), 1) << log;
    EXPECT_NE(log.find("at most 4096"), std::string::npos) << log;
    e["inputs"] = json::array({{{"path", "relative/file"}, {"bytes", 1}, {"sha256", std::string(64, 'a')}}});
    write(dir + "/rel.json", e.dump());
    EXPECT_EQ(reproduce(dir + "/rel.json", "", &log), 1) << log;
    EXPECT_NE(log.find("not an absolute, normalised path"), std::string::npos) << log;
}

// Item 2: --keep never writes over anything: the manifest's own folder and non-empty folders are
// refused, and the originals keep their bytes.
TEST(ManifestTrust, KeepRefusesTheOriginalsFolderAndNonEmptyFolders) {
    const std::string dir = test::output_dir();
    std::string log;
    fs::create_directories(dir + "/run");
    ASSERT_EQ(run_command(cli() + " render procedural:swatches" + kSize + "--targets " + shell_quote(dir + "/run/t") +
                              " --out " + shell_quote(dir + "/run/p.png"), &log), 0) << log;
    const std::string before = file_bytes(dir + "/run/p.png"), m_before = file_bytes(dir + "/run/p.png.json");
    const auto mtime = fs::last_write_time(dir + "/run/p.png");
    EXPECT_EQ(reproduce(dir + "/run/p.png.json", "--keep " + shell_quote(dir + "/run"), &log), 1) << log;
    EXPECT_NE(log.find("manifest's own folder"), std::string::npos) << log;
    fs::create_directories(dir + "/full");
    write(dir + "/full/x.txt", "x");
    EXPECT_EQ(reproduce(dir + "/run/p.png.json", "--keep " + shell_quote(dir + "/full"), &log), 1) << log;
    EXPECT_NE(log.find("is not empty"), std::string::npos) << log;
    EXPECT_EQ(file_bytes(dir + "/run/p.png"), before);
    EXPECT_EQ(file_bytes(dir + "/run/p.png.json"), m_before);
    EXPECT_EQ(fs::last_write_time(dir + "/run/p.png"), mtime);
    // A new folder and an empty one are fine.
    EXPECT_EQ(reproduce(dir + "/run/p.png.json", "--keep " + shell_quote(dir + "/new"), &log), 0) << log;
    EXPECT_TRUE(fs::exists(dir + "/new/image.png"));
    fs::create_directories(dir + "/empty");
    EXPECT_EQ(reproduce(dir + "/run/p.png.json", "--keep " + shell_quote(dir + "/empty"), &log), 0) << log;
}

// Item 8: SIGTERM during reproduce leaves no temporary folder (the kill is asserted to have landed
// mid-render: the exit status is the signal's), and a folder a SIGKILLed run left is removed by the
// next reproduce.
TEST(ManifestTrust, ATerminatedOrKilledReproduceLeavesNoTemporaryFolder) {
    const std::string dir = test::output_dir();
    std::string log;
    // A render slow enough to be caught (1024 x 1024, 4 x 4 supersampled: a second or more).
    ASSERT_EQ(run_command(cli() + " render procedural:swatches --width 1024 --height 1024 --ssaa 4 --quiet --out " +
                              shell_quote(dir + "/big.png"), &log), 0) << log;
    const std::string tmp = dir + "/tmp";
    fs::create_directories(tmp);
    // A folder of a process that no longer exists (PID 2^22 + 1 is above pid_max's default).
    fs::create_directories(tmp + "/aquarelle-reproduce.4194305.abcdef/targets");
    const std::string script = "TMPDIR=" + shell_quote(tmp) + " " + cli() + " reproduce --quiet " + shell_quote(dir + "/big.png.json") +
                               " & pid=$!; i=0; while [ -z \"$(ls " + shell_quote(tmp) + " | grep -v 4194305)\" ] && [ $i -lt 3000 ]; do "
                               "sleep 0.01; i=$((i+1)); done; kill -TERM $pid; wait $pid; echo \"status=$?\"";
    ASSERT_EQ(run_command(script, &log), 0) << log;
    EXPECT_NE(log.find("status=143"), std::string::npos) << "the reproduce was not terminated mid-render: " << log;
    EXPECT_TRUE(fs::is_empty(tmp)) << "a temporary folder was left in " << tmp;
}

// Item 7: --frames A-B with --frame N is a usage error (it used to render only N).
TEST(ManifestTrust, FramesAndFrameTogetherAreAUsageError) {
    const std::string dir = test::output_dir();
    std::string log;
    EXPECT_EQ(run_command(cli() + " render procedural:swatches" + kSize + "--frames 0-3 --frame 2 --out " +
                              shell_quote(dir + "/f_####.png"), &log), 2) << log;
    EXPECT_NE(log.find("cannot be combined"), std::string::npos) << log;
    EXPECT_EQ(run_command(cli() + " render procedural:swatches" + kSize + "--frame 2 --frames 0-3 --out " +
                              shell_quote(dir + "/f_####.png"), &log), 2) << log;
    EXPECT_FALSE(fs::exists(dir + "/f_0002.png"));
}

}  // namespace
}  // namespace aq
