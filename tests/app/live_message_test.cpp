// The messages a page sends to `aquarelle serve` (app/serve.h): what becomes render arguments,
// and every malformed message refused with a message for the page.
#include "app/serve.h"

#include <gtest/gtest.h>

#include "tests/test_support.h"

namespace aq::app {
namespace {

TEST(LiveMessage, AStateBecomesTheRenderArgumentsOfTheCommandLine) {
    const LiveRequest r = parse_live_message(R"({"type": "render", "seq": 7, "schema": true, "state": {
        "style": "wc18", "width": 320, "height": 180, "frame": 3, "view": [10, -5, 1.5],
        "variants": {"bleed": "naive"}, "params": {"edge_darken.intensity": 2.5}, "target": "depth.linear"}})");
    EXPECT_EQ(r.type, "render");
    EXPECT_EQ(r.seq, 7);
    EXPECT_TRUE(r.want_schema);
    EXPECT_FALSE(r.moving);
    EXPECT_TRUE(parse_live_message(R"({"type": "render", "moving": true, "state": {}})").moving);
    EXPECT_EQ(r.target, "depth.linear");
    const std::vector<std::string> want = {"--style", "wc18", "--width", "320", "--height", "180", "--frame", "3",
                                           "--view", "10,-5,1.5", "--variant", "bleed=naive", "--set", "edge_darken.intensity=2.5"};
    EXPECT_EQ(r.args, want);
    EXPECT_EQ(command_line("a b.glb", {"--ssaa", "2"}, r.args, "out.png"),
              "aquarelle render 'a b.glb' --ssaa 2 --style wc18 --width 320 --height 180 --frame 3 --view 10,-5,1.5 "
              "--variant bleed=naive --set edge_darken.intensity=2.5 --out out.png");
    // The neutral view and frame 0 add nothing: the command line of the page's first image.
    EXPECT_TRUE(parse_live_message(R"({"type": "render", "state": {"view": [0, 0, 1], "frame": 0}})").args.empty());
    EXPECT_TRUE(parse_live_message(R"({"type": "render", "state": {"view": [0, 0, 1, 0, 0]}})").args.empty());
}

TEST(LiveMessage, PanAndSceneEditsBecomeViewAndSceneSet) {
    const LiveRequest r = parse_live_message(R"({"type": "render", "state": {"view": [0, 0, 1, 0.25, -0.5],
        "scene": {"/layers/1/color": [0.5, 0.25, 1], "/foliage/T": 60, "/foliage/relative": false}}})");
    const std::vector<std::string> want = {"--view", "0,0,1,0.25,-0.5", "--scene-set", "/foliage/T=60", "--scene-set",
                                           "/foliage/relative=false", "--scene-set", "/layers/1/color=[0.5,0.25,1]"};
    EXPECT_EQ(r.args, want);
    EXPECT_EQ(command_line("oak.json", {}, r.args, "o.png"),
              "aquarelle render oak.json --view 0,0,1,0.25,-0.5 --scene-set /foliage/T=60 --scene-set /foliage/relative=false "
              "--scene-set '/layers/1/color=[0.5,0.25,1]' --out o.png");
}

TEST(LiveMessage, MalformedMessagesAreRefusedWithAReason) {
    const std::pair<const char*, const char*> bad[] = {
        {"", "not JSON"},
        {"[1, 2]", "expected an object"},
        {R"({"type": "render"})", "needs a state"},
        {R"({"type": "delete", "state": {}})", "unknown type"},
        {R"({"type": 3, "state": {}})", "must be a string"},
        {R"({"type": "render", "state": {}, "x": 1})", "unknown key 'x'"},
        {R"({"type": "render", "state": {"colour": 1}})", "unknown key 'colour'"},
        {R"({"type": "render", "state": {"width": 1e9}})", "width"},
        {R"({"type": "render", "state": {"width": 12.5}})", "whole number"},
        {R"({"type": "render", "state": {"params": {"a.b": "x"}}})", "must be a number"},
        {R"({"type": "render", "state": {"params": {"a.b=1 --out /etc/x": 1}}})", "character"},
        {R"({"type": "render", "state": {"variants": {"bleed": "../x"}}})", "character"},
        {R"({"type": "render", "state": {"view": [1, 2]}})", "view"},
        {R"({"type": "render", "state": {"view": [1, 2, 1, 0]}})", "view"},
        {R"({"type": "render", "state": {"view": [1, 2, 1, 0, "x"]}})", "pan"},
        {R"({"type": "render", "state": {"scene": [1]}})", "scene must be an object"},
        {R"({"type": "render", "state": {"scene": {"foliage/T": 1}}})", "not a JSON pointer"},
        {R"({"type": "render", "state": {"scene": {"/a=1 --out /etc/x": 1}}})", "'='"},
        {R"({"type": "render", "state": {"scene": {"/a\u0001b": 1}}})", "printable"},
        {R"({"type": "render", "state": {"scene": {"/a": "red"}}})", "must be a number, true/false or an array"},
        {R"({"type": "render", "state": {"scene": {"/a": [1, 2, 3, 4, 5]}}})", "array of 2-4 numbers"},
        {R"({"type": "render", "state": {"scene": {"/a": [1, "x"]}}})", "must be a number"},
        {R"({"type": "render", "state": {"scene": {"/a": {"b": 1}}}})", "must be a number"},
        {R"({"type": "render", "state": {"style": "/etc/passwd"}})", "character"},
        {R"({"type": "render", "state": {"style": ".."}})", "not a preset"},
        {R"({"type": "render", "seq": "a", "state": {}})", "seq"},
        {R"({"type": "render", "schema": 1, "state": {}})", "schema"},
        {R"({"type": "render", "moving": "yes", "state": {}})", "moving"},
    };
    for (const auto& b : bad) {
        const std::string text = b.first;
        const std::string e = test::error_of([&] { (void)parse_live_message(text); });
        EXPECT_NE(e.find(b.second), std::string::npos) << text << " -> " << e;
    }
    // NaN and infinities cannot be written in JSON; numbers beyond double are refused by the parser.
    EXPECT_NE(test::error_of([] { (void)parse_live_message(R"({"type": "render", "state": {"params": {"a.b": 1e999}}})"); }), "(no error)");
    EXPECT_NE(test::error_of([] { (void)parse_live_message(std::string(serve_limits::kMaxMessageBytes + 1, ' ')); }).find("too long"),
              std::string::npos);
}

}  // namespace
}  // namespace aq::app
