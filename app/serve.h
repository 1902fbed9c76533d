// app/serve.h — `aquarelle serve`: a local web page that art-directs a scene live (docs/serve.md).
//
// HTTP and WebSocket come from Boost.Beast (header-only in Debian's libboost-dev; chosen over
// websocketpp for being part of Boost, maintained with Asio, with HTTP and WebSocket in one
// library); the page's controls are lil-gui, from npm, pinned by app/web/package-lock.json and
// copied into the build so the page needs no network. The server turns the page's state into
// `aquarelle render` options (live_args) and renders them through the same code as the CLI, so
// what the page shows is what `render` writes for the command line the page prints.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/render_job.h"

namespace aq::app {

struct ServeOptions {
    std::string scene;
    std::string bind = "127.0.0.1";
    int port = 0;  //!< 0: any free port
    std::string out_dir = "aquarelle-saved";
    std::string web_dir;  //!< the page's files (the build's app/web)
    bool quiet = false;
    //! render options given on the command line (--style, --width, --set, ...), parsed for every
    //! image with the page's state added after them.
    std::vector<std::string> render_args;
};

//! Parses `aquarelle render` arguments (the CLI's own parser: app/main.cpp). Throws
//! cli::UsageError or aq::Error.
using RenderArgsParser = std::function<RenderOptions(const std::vector<std::string>&)>;

//! Limits of the live server (docs/serve.md "Safety").
namespace serve_limits {
inline constexpr std::size_t kMaxMessageBytes = 64 * 1024;  //!< one WebSocket message from a page
inline constexpr int kMaxPages = 16;                     //!< pages connected at once
inline constexpr int kMaxMessagesPerSecond = 200;           //!< per page; beyond: disconnected
inline constexpr int kMaxLiveSide = 4096;                   //!< width and height of the live view
inline constexpr std::size_t kMaxQueuedImages = 2;          //!< unsent images per page (newest kept)
}  // namespace serve_limits

//! The page's state as `render` arguments after the scene: --style, --width, --height, --frame,
//! --view, --variant STEP=V and --set STEP.PARAM=X (every value checked for type here, for range by
//! the render itself). Keys it does not know are an aq::Error naming them.
std::vector<std::string> live_args(const nlohmann::json& state);

//! One message of a page, checked: {"type": "render" | "save", "seq": integer (optional),
//! "schema": bool (optional: send the panel's schema with the image), "moving": bool (optional:
//! a preview JPEG will do), "state": {...}}.
struct LiveRequest {
    std::string type;
    nlohmann::json seq;  //!< echoed in the reply (null when absent)
    bool want_schema = false;
    bool moving = false;  //!< "moving": true while the page's view or a slider moves: a preview JPEG
    nlohmann::json state;
    std::vector<std::string> args;  //!< live_args(state)
    std::string target = "final";   //!< the target shown
};
//! Parses a page's message (at most serve_limits::kMaxMessageBytes). Throws aq::Error with the
//! text the page shows, for malformed JSON, unknown keys or types, and bad values.
LiveRequest parse_live_message(const std::string& text);

//! The equivalent command line, quoted for a POSIX shell.
std::string command_line(const std::string& scene, const std::vector<std::string>& base, const std::vector<std::string>& live,
                         const std::string& out);

//! What the page builds its panel from: the style's steps (id, stage, variant, the variants
//! registered for that stage, every parameter with kind, default, range, doc and its value in this
//! style), the targets it can show, the presets, the scene file's editable values (`knobs`: each
//! {pointer, kind, value, group, name}). Throws aq::Error.
nlohmann::json live_schema(const RenderJob& job, const nlohmann::json& knobs = nlohmann::json::array());

//! What the live server keeps between images (render thread only): the scene as loaded (with the
//! page's edits of its art direction), the scene file's model as read once, the LD06 passes'
//! scenes by foliage parameters, the last image's targets, and the files the load read.
struct LiveState {
    std::shared_ptr<const scene::SceneDesc> scene;
    std::string edits;  //!< scene::edits_key of the edits `scene` was loaded with
    //! The scene file's model (glTF) as read on the first edit: later edits load from it.
    std::shared_ptr<const scene::Scene> model;
    std::string model_path;
    nlohmann::json knobs = nlohmann::json::array();  //!< the scene file's editable values (scene::scene_knobs)
    //! Every file the load read, with its modification time and size when read: when one changes
    //! the scene is loaded again (the page is told; a file that no longer loads is its error).
    struct Watched {
        std::string path;
        std::int64_t mtime_ns = 0;
        std::uintmax_t size = 0;
        bool operator==(const Watched&) const = default;
    };
    std::vector<Watched> inputs;
    int loads = 0;  //!< loads of the scene so far (a later one: its files changed on disk)
    std::shared_ptr<RenderOptions::PassSceneMemo> pass_memo = std::make_shared<RenderOptions::PassSceneMemo>();
    RenderOptions::LiveFrame frame;
};

//! Loads `ro.scene` (with its edits) into `state` afresh, as `render` would, recording what it
//! read. Throws aq::Error.
void load_live_scene(const RenderOptions& ro, LiveState& state);

//! One live image as the page gets it — a PNG (no text chunk), or a preview JPEG while the view
//! or a slider moves — its phases and wall time.
struct LiveImage {
    std::string bytes;
    std::string format = "png";  //!< "png" or "jpeg"
    nlohmann::json phases = nlohmann::json::object();
    nlohmann::json schema;  //!< live_schema, when asked or when the scene was loaded again
    std::string notice;     //!< e.g. that the scene file changed on disk and was loaded again
    int first_step = 0;     //!< the pipeline ran from this step (0: everything, G-buffer included)
    double ms = 0;
};

//! Renders `ro` (the page's state parsed as `render` options) as the server does: from
//! state.scene (loaded on the first call, again when a file it read changed, from state.model
//! when the scene edits changed), continuing the last image where only parameter values changed
//! (`key`: every option but those values); `target` "final" or a target's name; `preview`: a
//! JPEG of kPreviewJpegQuality (the page asks while its view or a slider moves, and for the PNG
//! when it stops). Throws aq::Error. The server-side benchmark (bench/serve_bench.cpp) times this.
LiveImage render_live(RenderOptions ro, const std::string& key, const std::string& target, bool want_schema, LiveState& state,
                      bool preview = false);

//! Runs the server until SIGINT/SIGTERM. `on_url` receives the page's URL (token included) once
//! it listens. Returns the exit status.
int serve(const ServeOptions& options, const RenderArgsParser& parse, const std::function<void(const std::string&)>& on_url);

}  // namespace aq::app
