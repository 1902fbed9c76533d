// app/serve.cpp — the live art-direction server: Boost.Beast HTTP + WebSocket on one Asio thread,
// one render thread that takes each page's newest state (docs/serve.md).
#include "app/serve.h"

#include <spawn.h>
#include <sys/random.h>
#include <sys/wait.h>

#include <cerrno>
#include <cstring>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <thread>

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include "app/cli_args.h"
#include "app/manifest.h"
#include "app/render_files.h"
#include "app/visualize.h"
#include "core/input.h"
#include "core/io.h"
#include "core/jpeg.h"
#include "core/json_file.h"
#include "core/png.h"
#include "core/targets.h"
#include "stylize/stage.h"

extern char** environ;

namespace aq::app {
namespace fs = std::filesystem;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace asio = boost::asio;
using tcp = asio::ip::tcp;
using nlohmann::json;

// --- the page's state as render options ---------------------------------------------------------

namespace {

std::string num(double v) { return exact_number_text(v); }

const json& member(const json& state, const char* key) { return state.at(key); }

double number(const json& v, const std::string& what) {
    if (!v.is_number()) throw Error("live state: " + what + " must be a number");
    const double d = v.get<double>();
    if (!std::isfinite(d)) throw Error("live state: " + what + " must be finite");
    return d;
}

int integer(const json& v, const std::string& what, int lo, int hi) {
    const double d = number(v, what);
    if (d != std::floor(d) || d < lo || d > hi)
        throw Error("live state: " + what + " must be a whole number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return int(d);
}

//! A name the CLI accepts in STEP=V / STEP.PARAM=X: letters, digits, '_', '-' (no '=', no spaces).
std::string name(const json& v, const std::string& what) {
    if (!v.is_string()) throw Error("live state: " + what + " must be a string");
    const std::string s = v.get<std::string>();
    if (s.empty() || s.size() > 64) throw Error("live state: " + what + " must be 1-64 characters");
    for (char c : s)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-' && c != '.')
            throw Error("live state: " + what + " '" + s + "' has a character other than letters, digits, '_', '-', '.'");
    return s;
}

//! A JSON pointer the page names in "scene": printable ASCII, no '=' (it ends the pointer in
//! POINTER=VALUE), at most 256 characters; whether it is editable is the loader's check.
std::string pointer(const std::string& p) {
    if (p.empty() || p[0] != '/' || p.size() > 256) throw Error("live state: scene key '" + p.substr(0, 64) + "' is not a JSON pointer (/a/b)");
    for (char c : p)
        if (c < 0x20 || c > 0x7e || c == '=') throw Error("live state: scene key '" + p.substr(0, 64) + "' has a character outside printable ASCII or '='");
    return p;
}

//! A scene edit's value as JSON text: a number, true/false or an array of 2-4 numbers.
std::string scene_value(const json& v, const std::string& what) {
    if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
    if (v.is_number()) return num(number(v, what));
    if (v.is_array() && v.size() >= 2 && v.size() <= 4) {
        std::string t = "[";
        for (std::size_t i = 0; i < v.size(); ++i) t += (i ? "," : "") + num(number(v[i], what));
        return t + "]";
    }
    throw Error("live state: " + what + " must be a number, true/false or an array of 2-4 numbers");
}

std::string shell_quote(const std::string& s) {
    bool plain = !s.empty();
    for (char c : s) plain = plain && (std::isalnum(static_cast<unsigned char>(c)) || std::string("_-.,/:=+@%").find(c) != std::string::npos);
    if (plain) return s;
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

}  // namespace

std::vector<std::string> live_args(const json& state) {
    if (!state.is_object()) throw Error("live state: expected an object");
    static const std::set<std::string> known = {"style", "width", "height", "frame", "view", "variants", "params", "scene", "target"};
    for (auto it = state.begin(); it != state.end(); ++it)
        if (!known.count(it.key())) throw Error("live state: unknown key '" + it.key() + "'");
    namespace lim = request_limits;
    std::vector<std::string> a;
    if (state.contains("style")) {
        // A preset only: a page never names a file (a style file given on the command line stays).
        const std::string st = name(member(state, "style"), "style");
        const std::vector<std::string> presets = stylize::preset_names();
        if (std::find(presets.begin(), presets.end(), st) == presets.end()) throw Error("live state: style '" + st + "' is not a preset");
        a.insert(a.end(), {"--style", st});
    }
    if (state.contains("width"))
        a.insert(a.end(), {"--width", std::to_string(integer(member(state, "width"), "width", 1, serve_limits::kMaxLiveSide))});
    if (state.contains("height"))
        a.insert(a.end(), {"--height", std::to_string(integer(member(state, "height"), "height", 1, serve_limits::kMaxLiveSide))});
    if (state.contains("frame")) {
        const int f = integer(member(state, "frame"), "frame", 0, lim::kMaxFrame);
        if (f) a.insert(a.end(), {"--frame", std::to_string(f)});
    }
    if (state.contains("view")) {
        const json& v = member(state, "view");
        if (!v.is_array() || (v.size() != 3 && v.size() != 5))
            throw Error("live state: view must be [yaw, pitch, zoom] or [yaw, pitch, zoom, pan x, pan y]");
        const double yaw = number(v[0], "view yaw"), pitch = number(v[1], "view pitch"), zoom = number(v[2], "view zoom");
        const double px = v.size() == 5 ? number(v[3], "view pan x") : 0.0, py = v.size() == 5 ? number(v[4], "view pan y") : 0.0;
        std::string arg = num(yaw) + "," + num(pitch) + "," + num(zoom);
        if (px != 0 || py != 0) arg += "," + num(px) + "," + num(py);
        if (yaw != 0 || pitch != 0 || zoom != 1 || px != 0 || py != 0) a.insert(a.end(), {"--view", arg});
    }
    if (state.contains("variants")) {
        const json& v = member(state, "variants");
        if (!v.is_object()) throw Error("live state: variants must be an object {step: variant}");
        for (auto it = v.begin(); it != v.end(); ++it)
            a.insert(a.end(), {"--variant", name(json(it.key()), "variant step") + "=" + name(it.value(), "variant of " + it.key())});
    }
    if (state.contains("params")) {
        const json& p = member(state, "params");
        if (!p.is_object()) throw Error("live state: params must be an object {\"step.param\": value}");
        for (auto it = p.begin(); it != p.end(); ++it)
            a.insert(a.end(), {"--set", name(json(it.key()), "parameter") + "=" + num(number(it.value(), it.key()))});
    }
    if (state.contains("scene")) {
        const json& sc = member(state, "scene");
        if (!sc.is_object() || sc.size() > scene::kMaxSceneEdits)
            throw Error("live state: scene must be an object {\"/json/pointer\": value} of at most " + std::to_string(scene::kMaxSceneEdits) + " edits");
        for (auto it = sc.begin(); it != sc.end(); ++it)
            a.insert(a.end(), {"--scene-set", pointer(it.key()) + "=" + scene_value(it.value(), "scene value " + it.key().substr(0, 64))});
    }
    return a;
}

LiveRequest parse_live_message(const std::string& text) {
    if (text.size() > serve_limits::kMaxMessageBytes) throw Error("message of " + std::to_string(text.size()) + " bytes is too long");
    json msg;
    try {
        msg = json::parse(text);
    } catch (const json::exception& e) {
        throw Error(std::string("message is not JSON: ") + e.what());
    }
    if (!msg.is_object()) throw Error("message: expected an object {\"type\": ...}");
    for (auto it = msg.begin(); it != msg.end(); ++it)
        if (it.key() != "type" && it.key() != "seq" && it.key() != "schema" && it.key() != "moving" && it.key() != "state")
            throw Error("message: unknown key '" + it.key() + "'");
    LiveRequest r;
    if (!msg.contains("type") || !msg["type"].is_string()) throw Error("message: \"type\" must be a string");
    r.type = msg["type"].get<std::string>();
    if (r.type != "render" && r.type != "save") throw Error("message: unknown type '" + r.type + "'");
    if (msg.contains("seq")) {
        if (!msg["seq"].is_number_integer() && !msg["seq"].is_null()) throw Error("message: \"seq\" must be an integer");
        r.seq = msg["seq"];
    }
    if (msg.contains("schema")) {
        if (!msg["schema"].is_boolean()) throw Error("message: \"schema\" must be true or false");
        r.want_schema = msg["schema"].get<bool>();
    }
    if (msg.contains("moving")) {
        if (!msg["moving"].is_boolean()) throw Error("message: \"moving\" must be true or false");
        r.moving = msg["moving"].get<bool>();
    }
    if (!msg.contains("state")) throw Error("message: a " + r.type + " message needs a state");
    r.state = msg["state"];
    r.args = live_args(r.state);
    if (r.state.contains("target")) r.target = name(r.state["target"], "target");
    return r;
}

std::string command_line(const std::string& scene, const std::vector<std::string>& base, const std::vector<std::string>& live,
                         const std::string& out) {
    std::string c = "aquarelle render " + shell_quote(scene);
    for (const auto& s : base) c += " " + shell_quote(s);
    for (const auto& s : live) c += " " + shell_quote(s);
    return c + " --out " + shell_quote(out);
}

json live_schema(const RenderJob& job, const json& knobs) {
    json steps = json::array();
    std::set<std::string> targets;
    for (const target::GBufferTarget& g : target::kGBufferLayout) targets.insert(g.name);
    if (job.stylize && !job.compiled.empty()) {
        const stylize::Pipeline& p = job.styles.at(0);
        const stylize::CompiledPipeline& c = job.compiled.at(0);
        if (p.steps.size() != c.steps.size()) throw Error("live schema: compiled steps do not match the style's");
        for (std::size_t i = 0; i < c.steps.size(); ++i) {
            const stylize::CompiledStep& s = c.steps[i];
            const stylize::Registry& reg = s.pass ? stylize::builtin_pass_registry() : stylize::builtin_registry();
            json variants = json::array();
            for (const stylize::StageVariant* v : reg.variants(s.variant->stage)) variants.push_back({{"name", v->variant}, {"doc", v->doc}});
            json params = json::array();
            for (const stylize::ParamDesc& d : s.variant->params)
                params.push_back({{"name", d.name},
                                  {"kind", stylize::param_kind_name(d.kind)},
                                  {"default", d.def}, {"min", d.lo}, {"max", d.hi}, {"doc", d.doc},
                                  {"value", s.params.count(d.name) ? s.params.at(d.name) : d.def}, {"names", d.names}});
            steps.push_back({{"id", p.steps[i].id.empty() ? p.steps[i].stage : p.steps[i].id},
                             {"stage", s.variant->stage}, {"variant", s.variant->variant}, {"pass", s.pass},
                             {"doc", s.variant->doc}, {"variants", variants}, {"params", params}});
            for (const std::string& o : s.outputs) targets.insert(o);
        }
    }
    json t = json::array({"final"});
    for (const std::string& n : targets) t.push_back(n);
    return {{"style", job.stylize ? job.styles.at(0).name : "none"},
            {"styles", stylize::preset_names()},
            {"steps", steps},
            {"targets", t},
            {"width", job.settings.width},
            {"height", job.settings.height},
            {"scene", knobs}};
}

namespace {

//! A file as it is on disk now: its modification time and size (0 when it cannot be read).
LiveState::Watched watched(const std::string& path) {
    LiveState::Watched x;
    x.path = path;
    std::error_code ec;
    const auto t = fs::last_write_time(path, ec);
    if (!ec) x.mtime_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
    x.size = ec ? 0 : fs::file_size(path, ec);
    return x;
}

bool files_changed(const std::vector<LiveState::Watched>& inputs) {
    return std::any_of(inputs.begin(), inputs.end(), [](const LiveState::Watched& f) { return watched(f.path) != f; });
}

}  // namespace

void load_live_scene(const RenderOptions& options, LiveState& state) {
    const int loads = state.loads;
    state = LiveState{};
    state.loads = loads + 1;
    RenderOptions ro = options;
    ro.keep_loaded = true;
    ro.preloaded = nullptr;
    ro.live_frame = nullptr;
    Reporter quiet;
    InputCapture capture;
    state.scene = prepare_render(ro, quiet).loaded;
    state.edits = scene::edits_key(ro.scene_edits);
    for (const InputRecord& r : capture.records())  // each file once (the capture lists every read)
        if (std::none_of(state.inputs.begin(), state.inputs.end(), [&](const LiveState::Watched& w) { return w.path == r.path; }))
            state.inputs.push_back(watched(r.path));
    if (lower_extension(ro.scene) == ".json")
        for (const scene::SceneKnob& k : scene::scene_knobs(ro.scene))
            state.knobs.push_back({{"pointer", k.pointer}, {"kind", k.kind}, {"value", json::parse(k.value)}, {"group", k.group}, {"name", k.name}});
}

LiveImage render_live(RenderOptions ro, const std::string& key, const std::string& target, bool want_schema, LiveState& state,
                      bool preview) {
    const auto t0 = std::chrono::steady_clock::now();
    ro.keep_intermediates = target != "final";
    ro.live = true;
    LiveImage out;
    if (state.scene && files_changed(state.inputs)) state.scene.reset();  // load_live_scene starts afresh
    if (!state.scene) {
        const bool again = state.loads > 0;
        try {
            load_live_scene(ro, state);
        } catch (const Error& e) {
            if (!again) throw;
            throw Error("a file of the scene changed on disk and the scene does not load now (fix it; the next change loads it "
                        "again): " + std::string(e.what()));
        }
        if (again) out.notice = "a file of the scene changed on disk: loaded again";
    } else if (const std::string edits = scene::edits_key(ro.scene_edits); edits != state.edits) {
        // Another edit of the scene file's art direction: read the file again (small), the model
        // from memory (read on the first edit).
        scene::LoadOptions lo;
        lo.allow_outside_files = ro.allow_outside_files;
        lo.edits = ro.scene_edits;
        lo.load_model = [&state](const std::string& path, const scene::LoadOptions& o) {
            if (!state.model || state.model_path != path) {
                state.model = std::make_shared<const scene::Scene>(scene::load_gltf(path, nullptr, o));
                state.model_path = path;
            }
            return *state.model;
        };
        state.scene = std::make_shared<const scene::SceneDesc>(scene::load_scene(ro.scene, lo));
        state.edits = edits;
    }
    ro.preloaded = state.scene;
    ro.pass_memo = state.pass_memo;
    state.frame.key_next = key;
    ro.live_frame = &state.frame;
    Reporter quiet;
    RenderJob job = prepare_render(ro, quiet);
    if (want_schema || !out.notice.empty()) out.schema = live_schema(job, state.knobs);
    std::string missing;
    run_render(job, [&](RenderedImage& img) {
        ImageF shown;
        if (target == "final") {
            shown = img.final_image();
        } else if (img.targets.has(target)) {
            shown = visualize_target(target, img.targets.get(target));
        } else {
            missing = target;
            return;
        }
        std::vector<unsigned char> bytes, rows;
        if (preview) encode_jpeg(shown, kPreviewJpegQuality, bytes, rows);
        else encode_png(shown, "", bytes, rows);
        out.bytes.assign(bytes.begin(), bytes.end());
        out.format = preview ? "jpeg" : "png";
        for (const auto& [k, v] : img.phases) out.phases[k] = v;
    }, quiet);
    if (!missing.empty()) throw Error("no target '" + missing + "' in this render");
    out.first_step = state.frame.first_step;
    out.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return out;
}

// --- the server ---------------------------------------------------------------------------------

namespace {

std::string random_token() {
    unsigned char b[24];
    std::size_t got = 0;
    while (got < sizeof b) {
        const ssize_t n = ::getrandom(b + got, sizeof b - got, 0);
        if (n < 0) {
            if (errno == EINTR) continue;
            throw Error("serve: no random bytes for the access token");
        }
        got += std::size_t(n);
    }
    static const char* hex = "0123456789abcdef";
    std::string t;
    for (unsigned char c : b) t += hex[c >> 4], t += hex[c & 15];
    return t;
}

bool same_token(const std::string& a, const std::string& b) {
    if (a.size() != b.size()) return false;
    unsigned char d = 0;
    for (std::size_t i = 0; i < a.size(); ++i) d |= static_cast<unsigned char>(a[i] ^ b[i]);
    return d == 0;
}

//! The query parameter `key` of a request target ("/ws?token=..."), else "".
std::string query_param(beast::string_view target, const std::string& key) {
    const auto q = target.find('?');
    if (q == beast::string_view::npos) return {};
    std::string rest(target.substr(q + 1));
    std::size_t p = 0;
    while (p <= rest.size()) {
        const std::size_t e = std::min(rest.find('&', p), rest.size());
        const std::string kv = rest.substr(p, e - p);
        const auto eq = kv.find('=');
        if (eq != std::string::npos && kv.substr(0, eq) == key) return kv.substr(eq + 1);
        p = e + 1;
    }
    return {};
}

std::string path_of(beast::string_view target) {
    const auto q = target.find('?');
    return std::string(q == beast::string_view::npos ? target : target.substr(0, q));
}

struct Asset {
    std::string type, body;
};

//! The page's files, read once at start from the build's web folder: the server never opens a
//! path that came from a client.
std::map<std::string, Asset> load_assets(const std::string& dir, const std::string& token) {
    std::map<std::string, Asset> a;
    const std::pair<const char*, const char*> files[] = {
        {"index.html", "text/html; charset=utf-8"}, {"app.js", "text/javascript; charset=utf-8"},
        {"style.css", "text/css; charset=utf-8"}, {"lil-gui.esm.min.js", "text/javascript; charset=utf-8"}};
    for (const auto& [f, type] : files) {
        std::ifstream in(dir + "/" + f, std::ios::binary);
        if (!in) throw Error("serve: the page's file '" + dir + "/" + f + "' is missing (build the target aquarelle_web)");
        std::string body((std::istreambuf_iterator<char>(in)), {});
        if (std::string(f) == "index.html") {
            for (std::size_t p; (p = body.find("{{TOKEN}}")) != std::string::npos;) body.replace(p, 9, token);
        }
        a[std::string("/") + f] = {type, std::move(body)};
    }
    a["/"] = a["/index.html"];
    return a;
}

class Server;

//! One page's WebSocket. All its members are touched on the Asio thread only; the render thread
//! hands results over with asio::post.
class PageConnection : public std::enable_shared_from_this<PageConnection> {
public:
    PageConnection(tcp::socket&& s, Server& server, int id) : ws_(std::move(s)), server_(server), id_(id) {}
    void start(http::request<http::string_body> req);
    //! Queues a text message and, optionally, a binary one after it (an image); drops the oldest
    //! queued images beyond kMaxQueuedImages (a page that does not read cannot grow memory).
    void send(std::string text, std::optional<std::string> binary = std::nullopt);
    int id() const { return id_; }
    void close();

private:
    void read();
    void on_read(beast::error_code ec, std::size_t);
    void write_next();
    websocket::stream<beast::tcp_stream> ws_;
    beast::flat_buffer buf_;
    Server& server_;
    int id_;
    struct Out {
        std::string data;
        bool binary;
        bool image;  //!< part of an image (header + PNG), droppable
    };
    std::deque<Out> out_;
    bool writing_ = false, closed_ = false;
    std::chrono::steady_clock::time_point window_start_ = std::chrono::steady_clock::now();
    int window_count_ = 0;
};

class Server {
public:
    Server(const ServeOptions& o, const RenderArgsParser& parse)
        : o_(o), parse_(parse), token_(random_token()), acceptor_(io_) {}
    int run(const std::function<void(const std::string&)>& on_url);

    // Called from the connections (Asio thread).
    void on_message(const std::shared_ptr<PageConnection>& s, const std::string& text);
    void on_open(const std::shared_ptr<PageConnection>& s);
    void on_close(int id);
    bool origin_ok(const http::request<http::string_body>& req) const;
    asio::io_context& io() { return io_; }

private:
    void accept();
    void serve_http(tcp::socket socket);
    void render_loop();
    void render_one(int page, const LiveRequest& req);
    void post(int page, std::string text, std::optional<std::string> binary = std::nullopt);
    //! `render` arguments after the command: the scene, the server's options, the page's, --out.
    std::vector<std::string> render_args(const std::vector<std::string>& live, const std::string& out) const {
        std::vector<std::string> a = {o_.scene};
        a.insert(a.end(), o_.render_args.begin(), o_.render_args.end());
        a.insert(a.end(), live.begin(), live.end());
        a.insert(a.end(), {"--out", out, "--quiet"});
        return a;
    }
    std::string save(const json& state);

    ServeOptions o_;
    RenderArgsParser parse_;
    std::string token_;
    asio::io_context io_;
    tcp::acceptor acceptor_;
    std::map<std::string, Asset> assets_;
    std::string host_port_;  //!< "127.0.0.1:PORT" as bound
    std::map<int, std::weak_ptr<PageConnection>> pages_;  // Asio thread only
    int next_id_ = 1;

    // Render thread: each page's newest request, in arrival order.
    std::mutex m_;
    std::condition_variable cv_;
    std::map<int, LiveRequest> pending_;
    std::deque<int> order_;
    bool stop_ = false;
    //! The loaded scene, the passes' scenes and the last live image's targets, for every page
    //! (render thread only): one frame's memory whatever the number of pages; pages taking turns
    //! each render from the start.
    LiveState live_;
};

void PageConnection::start(http::request<http::string_body> req) {
    ws_.read_message_max(serve_limits::kMaxMessageBytes);
    ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    auto self = shared_from_this();
    ws_.async_accept(req, [self](beast::error_code ec) {
        if (ec) return;
        self->server_.on_open(self);
        self->read();
    });
}

void PageConnection::read() {
    auto self = shared_from_this();
    ws_.async_read(buf_, [self](beast::error_code ec, std::size_t n) { self->on_read(ec, n); });
}

void PageConnection::on_read(beast::error_code ec, std::size_t) {
    if (ec) {
        closed_ = true;
        server_.on_close(id_);
        return;
    }
    const auto now = std::chrono::steady_clock::now();
    if (now - window_start_ > std::chrono::seconds(1)) window_start_ = now, window_count_ = 0;
    if (++window_count_ > serve_limits::kMaxMessagesPerSecond) {
        send(json{{"type", "error"}, {"message", "more than " + std::to_string(serve_limits::kMaxMessagesPerSecond) +
                                                  " messages a second: disconnected"}}.dump());
        close();
        return;
    }
    if (!ws_.got_text()) {
        send(json{{"type", "error"}, {"message", "binary messages are not understood"}}.dump());
    } else {
        server_.on_message(shared_from_this(), beast::buffers_to_string(buf_.data()));
    }
    buf_.consume(buf_.size());
    read();
}

void PageConnection::send(std::string text, std::optional<std::string> binary) {
    if (closed_) return;
    const bool image = binary.has_value();
    if (image) {
        // Drop queued images that are not being written (the first entry may be in flight).
        std::size_t images = 0;
        for (const Out& o : out_) images += o.image && !o.binary;
        while (images >= serve_limits::kMaxQueuedImages) {
            auto it = out_.begin() + (writing_ ? 1 : 0);
            while (it != out_.end() && !(it->image && !it->binary)) ++it;
            if (it == out_.end()) break;
            it = out_.erase(it);                              // the header
            if (it != out_.end() && it->image && it->binary) out_.erase(it);  // its PNG
            --images;
        }
    }
    out_.push_back({std::move(text), false, image});
    if (binary) out_.push_back({std::move(*binary), true, true});
    if (!writing_) write_next();
}

void PageConnection::write_next() {
    if (out_.empty() || closed_) {
        writing_ = false;
        return;
    }
    writing_ = true;
    ws_.text(!out_.front().binary);
    auto self = shared_from_this();
    ws_.async_write(asio::buffer(out_.front().data), [self](beast::error_code ec, std::size_t) {
        self->out_.pop_front();
        if (ec) {
            self->closed_ = true;
            self->writing_ = false;
            return;
        }
        self->write_next();
    });
}

void PageConnection::close() {
    if (closed_) return;
    closed_ = true;
    auto self = shared_from_this();
    ws_.async_close(websocket::close_code::policy_error, [self](beast::error_code) {});
    server_.on_close(id_);
}

bool Server::origin_ok(const http::request<http::string_body>& req) const {
    // Same origin only: the page this server served (a page of another site, or a DNS name
    // rebound to this address, cannot drive it).
    const std::string host(req[http::field::host]);
    const std::string origin(req[http::field::origin]);
    const std::string port = host_port_.substr(host_port_.rfind(':') + 1);
    const bool host_ok = host == host_port_ || host == "localhost:" + port || host == "127.0.0.1:" + port ||
                         host == "[::1]:" + port || host == o_.bind + ":" + port;
    return host_ok && origin == "http://" + host;
}

void Server::on_open(const std::shared_ptr<PageConnection>& s) {
    pages_[s->id()] = s;
    {
        std::lock_guard<std::mutex> lock(m_);
        LiveRequest hello;
        hello.type = "hello";
        hello.want_schema = true;
        hello.state = json::object();
        pending_[s->id()] = std::move(hello);
        order_.push_back(s->id());
    }
    cv_.notify_one();
}

void Server::on_close(int id) {
    pages_.erase(id);
    std::lock_guard<std::mutex> lock(m_);
    pending_.erase(id);
}

void Server::on_message(const std::shared_ptr<PageConnection>& s, const std::string& text) {
    LiveRequest req;
    try {
        req = parse_live_message(text);
    } catch (const Error& e) {
        s->send(json{{"type", "error"}, {"message", e.what()}}.dump());
        return;
    }
    {
        std::lock_guard<std::mutex> lock(m_);
        // Coalescing: a page's newer render replaces the one not yet started; a save is kept.
        auto it = pending_.find(s->id());
        if (it != pending_.end() && it->second.type == "save" && req.type == "render") return;
        if (it == pending_.end()) order_.push_back(s->id());
        pending_[s->id()] = std::move(req);
    }
    cv_.notify_one();
}

void Server::post(int page, std::string text, std::optional<std::string> binary) {
    asio::post(io_, [this, page, text = std::move(text), binary = std::move(binary)]() mutable {
        auto it = pages_.find(page);
        if (it == pages_.end()) return;
        if (auto s = it->second.lock()) s->send(std::move(text), std::move(binary));
    });
}

void Server::render_loop() {
    for (;;) {
        int page = 0;
        LiveRequest msg;
        {
            std::unique_lock<std::mutex> lock(m_);
            cv_.wait(lock, [&] { return stop_ || !order_.empty(); });
            if (stop_) return;
            page = order_.front();
            order_.pop_front();
            auto it = pending_.find(page);
            if (it == pending_.end()) continue;  // the page went away
            msg = std::move(it->second);
            pending_.erase(it);
        }
        render_one(page, msg);
    }
}

std::string Server::save(const json& state) {
    std::error_code ec;
    fs::create_directories(o_.out_dir, ec);
    if (ec) throw Error("save: cannot create '" + o_.out_dir + "': " + ec.message());
    std::string stem;
    for (int i = 1; i < 100000; ++i) {
        char b[32];
        std::snprintf(b, sizeof b, "aquarelle_%04d", i);
        if (!fs::exists(o_.out_dir + "/" + b + ".png")) {
            stem = b;
            break;
        }
    }
    if (stem.empty()) throw Error("save: '" + o_.out_dir + "' holds 99999 saved images");
    const std::string png = o_.out_dir + "/" + stem + ".png";
    const std::vector<std::string> live = live_args(state);
    // `aquarelle render` itself, in a child process: the saved files are exactly what that command
    // line writes, and its manifest lists the files that render read (this process has read
    // others: styles a page tried, the scene as it was when the server started).
    std::vector<std::string> args = render_args(live, png);
    args.insert(args.begin(), {"aquarelle", "render"});
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    pid_t pid = 0;
    if (::posix_spawn(&pid, "/proc/self/exe", nullptr, nullptr, argv.data(), environ) != 0)
        throw Error("save: cannot start aquarelle render: " + std::string(std::strerror(errno)));
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
        throw Error("save: aquarelle render failed (exit status " + std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + ")");
    const json saved = {{"state", state}, {"command", command_line(o_.scene, o_.render_args, live, png)}};
    std::ofstream(o_.out_dir + "/" + stem + ".state.json") << saved.dump(2) << "\n";
    return png;
}

void Server::render_one(int page, const LiveRequest& req) {
    const json& state = req.state;
    const json& seq = req.seq;
    try {
        if (req.type == "save") {
            const std::string png = save(state);
            post(page, json{{"type", "saved"}, {"png", png}, {"manifest", manifest_path(png)}}.dump());
            return;
        }
        const std::vector<std::string>& live = req.args;
        const std::vector<std::string> args = render_args(live, "live.png");
        // Every option but the parameter values names the kept targets (RenderOptions::LiveFrame).
        std::string key;
        for (std::size_t i = 0; i < args.size(); ++i) {
            if (args[i] == "--set" && i + 1 < args.size()) {
                ++i;
                continue;
            }
            key += args[i] + '\n';
        }
        LiveImage img = render_live(parse_(args), key, req.target, req.want_schema, live_, req.moving);
        json head = {{"type", "image"}, {"seq", seq}, {"format", img.format}, {"server_ms", img.ms}, {"phases", img.phases}, {"first_step", img.first_step},
                     {"command", command_line(o_.scene, o_.render_args, live, "out.png")}};
        if (!img.notice.empty()) head["notice"] = img.notice;
        if (!img.schema.is_null()) head["schema"] = img.schema;
        post(page, head.dump(), std::move(img.bytes));
    } catch (const std::exception& e) {
        post(page, json{{"type", "error"}, {"seq", seq}, {"message", e.what()}}.dump());
    }
}

void Server::serve_http(tcp::socket socket) {
    // One request per connection on the Asio thread; a WebSocket upgrade hands the socket on.
    struct Conn : std::enable_shared_from_this<Conn> {
        beast::tcp_stream stream;
        beast::flat_buffer buf;
        http::request_parser<http::string_body> parser;
        Server& server;
        Conn(tcp::socket&& s, Server& srv) : stream(std::move(s)), server(srv) {
            parser.header_limit(16 * 1024);
            parser.body_limit(0);
        }
        void start() {
            stream.expires_after(std::chrono::seconds(10));
            auto self = shared_from_this();
            http::async_read(stream, buf, parser, [self](beast::error_code ec, std::size_t) { self->on_request(ec); });
        }
        void reply(http::status st, const std::string& type, std::string body) {
            auto res = std::make_shared<http::response<http::string_body>>(st, parser.get().version());
            res->set(http::field::content_type, type);
            res->set(http::field::cache_control, "no-store");
            res->set("X-Content-Type-Options", "nosniff");
            res->set("Content-Security-Policy",
                     "default-src 'self'; img-src 'self' blob:; connect-src 'self'; style-src 'self' 'unsafe-inline'; font-src 'self' data:");
            res->body() = std::move(body);
            res->prepare_payload();
            res->keep_alive(false);
            auto self = shared_from_this();
            http::async_write(stream, *res, [self, res](beast::error_code, std::size_t) {
                beast::error_code ignored;
                self->stream.socket().shutdown(tcp::socket::shutdown_send, ignored);
            });
        }
        void on_request(beast::error_code ec) {
            if (ec) return;
            const auto& req = parser.get();
            const std::string token = query_param(req.target(), "token");
            if (!same_token(token, server.token_)) {
                reply(http::status::forbidden, "text/plain", "aquarelle serve: this page needs the token of the URL the server printed\n");
                return;
            }
            if (req.method() != http::verb::get) {
                reply(http::status::method_not_allowed, "text/plain", "GET only\n");
                return;
            }
            const std::string path = path_of(req.target());
            if (path == "/ws" && websocket::is_upgrade(req)) {
                if (!server.origin_ok(req)) {
                    reply(http::status::forbidden, "text/plain", "aquarelle serve: WebSocket from another origin refused\n");
                    return;
                }
                if (int(server.pages_.size()) >= serve_limits::kMaxPages) {
                    reply(http::status::service_unavailable, "text/plain", "aquarelle serve: too many pages open\n");
                    return;
                }
                stream.expires_never();
                std::make_shared<PageConnection>(stream.release_socket(), server, server.next_id_++)->start(parser.release());
                return;
            }
            auto it = server.assets_.find(path);
            if (it == server.assets_.end()) {
                reply(http::status::not_found, "text/plain", "not found\n");
                return;
            }
            reply(http::status::ok, it->second.type, it->second.body);
        }
    };
    std::make_shared<Conn>(std::move(socket), *this)->start();
}

void Server::accept() {
    acceptor_.async_accept([this](beast::error_code ec, tcp::socket s) {
        if (!ec) serve_http(std::move(s));
        if (acceptor_.is_open()) accept();
    });
}

int Server::run(const std::function<void(const std::string&)>& on_url) {
    assets_ = load_assets(o_.web_dir, token_);
    beast::error_code ec;
    const auto addr = asio::ip::make_address(o_.bind, ec);
    if (ec) throw Error("serve: --bind '" + o_.bind + "' is not an IP address");
    const tcp::endpoint ep(addr, static_cast<unsigned short>(o_.port));
    acceptor_.open(ep.protocol(), ec);
    if (!ec) acceptor_.set_option(asio::socket_base::reuse_address(true), ec);
    if (!ec) acceptor_.bind(ep, ec);
    if (!ec) acceptor_.listen(asio::socket_base::max_listen_connections, ec);
    if (ec) throw Error("serve: cannot listen on " + o_.bind + ":" + std::to_string(o_.port) + ": " + ec.message());
    const int port = acceptor_.local_endpoint().port();
    const std::string host = addr.is_v6() ? "[" + o_.bind + "]" : o_.bind;
    host_port_ = host + ":" + std::to_string(port);
    // Load the scene once before the first page connects: its errors end the server here.
    {
        load_live_scene(parse_(render_args({}, "live.png")), live_);
    }
    std::thread renderer([this] { render_loop(); });
    asio::signal_set signals(io_, SIGINT, SIGTERM);
    signals.async_wait([this](beast::error_code, int) {
        beast::error_code ignored;
        acceptor_.close(ignored);
        io_.stop();
    });
    accept();
    on_url("http://" + (o_.bind == "0.0.0.0" ? std::string("127.0.0.1") : host) + ":" + std::to_string(port) + "/?token=" + token_);
    io_.run();
    {
        std::lock_guard<std::mutex> lock(m_);
        stop_ = true;
    }
    cv_.notify_one();
    renderer.join();
    return 0;
}

}  // namespace

int serve(const ServeOptions& options, const RenderArgsParser& parse, const std::function<void(const std::string&)>& on_url) {
    Server s(options, parse);
    return s.run(on_url);
}

}  // namespace aq::app
