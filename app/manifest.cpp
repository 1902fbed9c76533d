// app/manifest.cpp — see manifest.h.
#include "app/manifest.h"

#include <fcntl.h>
#include <stdlib.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdint>
#include <cstring>

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>

#include "app/render_files.h"
#include "core/build_info.h"
#include "core/compare.h"
#include "core/hash.h"
#include "core/input.h"
#include "core/io.h"
#include "core/image.h"
#include "core/json_file.h"
#include "raster/vertex.h"

namespace aq::app {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string absolute_path(const std::string& p) {
    std::error_code ec;
    const fs::path a = fs::absolute(p, ec);
    return (ec ? fs::path(p) : a).lexically_normal().string();
}

bool is_file_style(const std::string& style) {
    return style.size() > 5 && style.compare(style.size() - 5, 5, ".json") == 0;
}

json build_json() {
    const BuildInfo& b = build_info();
    return {{"version", b.version}, {"commit", b.commit},   {"dirty", b.dirty},
            {"compiler", b.compiler}, {"build_type", b.build_type}, {"flags", b.flags}};
}

//! The request for this one image: RenderOptions without what cannot change the bytes (threads,
//! --reference, --shard, --quiet, output paths) and with this image's frame or sweep index.
json request_json(const RenderJob& job, const RenderedImage& img) {
    const RenderOptions& o = job.options;
    const bool procedural = o.scene.rfind("procedural:", 0) == 0;
    json r = {
        {"scene", procedural ? o.scene : absolute_path(o.scene)},
        {"style", o.style_given && is_file_style(o.style) ? absolute_path(o.style) : o.style},
        {"style_given", o.style_given},
        {"set", o.sets},
        {"variant", o.variants},
        {"bypass", o.bypass},
        {"width", o.width},
        {"height", o.height},
        {"frame", img.frame},
        {"fps", o.fps},
        {"orbit_deg", o.orbit_deg},
        {"ssaa", o.ssaa},
        {"antialias", o.antialias == raster::RenderSettings::Antialias::None ? "none" : "coverage"},
        {"control", o.neutral_control ? "neutral" : "default"},
        {"working_space", o.working_space == WorkingSpace::Linear ? "linear" : "display"},
        {"compression", compression_name(o.compression)},
        {"allow_outside_files", o.allow_outside_files},
        {"targets", !o.targets_dir.empty()},
        {"targets_png", !o.targets_png_dir.empty()},
        {"output_format", fs::path(o.out).extension().string()},
    };
    if (!o.scene_edits.empty()) {  // absent: none (older readers know no edits)
        r["scene_set"] = json::array();
        for (const scene::SceneEdit& e : o.scene_edits) r["scene_set"].push_back(scene::to_string(e));
    }
    if (o.has_view()) {  // absent: 0, 0, 1; the pan only when there is one (older readers take three)
        r["view"] = {o.view_yaw, o.view_pitch, o.view_zoom};
        if (o.has_pan()) r["view"].insert(r["view"].end(), {o.view_pan_x, o.view_pan_y});
    }
    if (!o.sweep.empty())
        r["sweep"] = {{"param", o.sweep}, {"from", o.sweep_from}, {"to", o.sweep_to}, {"count", o.sweep_count},
                      {"index", img.index}};
    return r;
}

json pipeline_json(const stylize::CompiledPipeline& c) {
    json steps = json::array();
    for (const stylize::CompiledStep& s : c.steps) {
        json in = json::object(), out = json::object();
        for (std::size_t i = 0; i < s.variant->inputs.size() && i < s.inputs.size(); ++i)
            in[s.variant->inputs[i].name] = s.inputs[i];
        for (std::size_t i = 0; i < s.variant->outputs.size() && i < s.outputs.size(); ++i)
            out[s.variant->outputs[i].name] = s.outputs[i];
        steps.push_back({{"kind", s.pass ? "pass" : "stage"},
                         {"stage", s.variant->stage},
                         {"variant", s.variant->variant},
                         {"params", s.params},
                         {"in", in},
                         {"out", out}});
    }
    json p = {{"name", c.name},
              {"source", c.source},
              {"output", c.output},
              {"substrate_color", {c.substrate_color.x, c.substrate_color.y, c.substrate_color.z}},
              {"steps", steps}};
    if (c.has_paper)
        p["paper"] = {{"file", c.paper.file.empty() ? "" : absolute_path(c.paper.file)},
                      {"layout", c.paper.layout},
                      {"scale", c.paper.scale},
                      {"roughness", c.paper.roughness}};
    if (c.has_foliage)
        p["foliage"] = {{"abstract", c.foliage.abstract},   {"threshold", c.foliage.threshold},
                        {"radius", c.foliage.radius},       {"relative", c.foliage.relative},
                        {"cells_per_radius", c.foliage.cells_per_radius}, {"fit", c.foliage.fit},
                        {"technique", raster::technique_name(c.foliage.technique)}};
    return p;
}

// --- reproduce's temporary folder -------------------------------------------------------------
// `TMPDIR/aquarelle-reproduce.PID.XXXXXX`: removed when reproduce returns or throws, by the signal
// handler on SIGINT, SIGTERM and SIGHUP (async-signal-safe: raw openat/getdents64/unlinkat over
// the folder's two levels), and, after a SIGKILL, by the next reproduce (its PID no longer alive).

constexpr const char* kReproducePrefix = "aquarelle-reproduce.";

std::string temp_base() {
    const char* base = std::getenv("TMPDIR");
    return base && *base ? base : "/tmp";
}

char g_temp_dir[4096];                       // the folder the handler removes ("" when none)
volatile std::sig_atomic_t g_temp_set = 0;

//! Removes the entries of the folder `fd` (files, and folders `depth` levels deep), then closes fd.
//! Only system calls: safe in a signal handler.
void remove_entries_raw(int fd, int depth) {
    alignas(8) char buf[4096];
    for (;;) {
        const long n = ::syscall(SYS_getdents64, fd, buf, sizeof buf);
        if (n <= 0) break;
        for (long off = 0; off < n;) {
            struct Dirent {
                std::uint64_t ino;
                std::int64_t off;
                unsigned short reclen;
                unsigned char type;
                char name[1];
            };
            const auto* d = reinterpret_cast<const Dirent*>(buf + off);
            off += d->reclen;
            const char* nm = d->name;
            if (nm[0] == '.' && (nm[1] == 0 || (nm[1] == '.' && nm[2] == 0))) continue;
            if (::unlinkat(fd, nm, 0) == 0) continue;
            if (depth > 0) {
                const int sub = ::openat(fd, nm, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
                if (sub >= 0) remove_entries_raw(sub, depth - 1);
            }
            ::unlinkat(fd, nm, AT_REMOVEDIR);
        }
    }
    ::close(fd);
}

void remove_temp_dir_on_signal(int sig) {
    if (g_temp_set) {
        const int fd = ::open(g_temp_dir, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
        if (fd >= 0) remove_entries_raw(fd, 3);
        ::rmdir(g_temp_dir);
    }
    std::signal(sig, SIG_DFL);
    std::raise(sig);
}

//! Removes the reproduce folders that killed processes left under TMPDIR.
void remove_stale_reproduce_folders() {
    std::error_code ec;
    const std::string prefix = kReproducePrefix;
    for (fs::directory_iterator it(temp_base(), ec), end; !ec && it != end; it.increment(ec)) {
        const std::string n = it->path().filename().string();
        if (n.rfind(prefix, 0) != 0) continue;
        const std::size_t dot = n.find('.', prefix.size());
        long pid = 0;
        try {
            pid = std::stol(n.substr(prefix.size(), dot - prefix.size()));
        } catch (...) {
            continue;
        }
        if (pid <= 0 || pid == long(::getpid()) || ::kill(pid_t(pid), 0) == 0 || errno != ESRCH) continue;
        std::error_code rm;
        fs::remove_all(it->path(), rm);
    }
}

//! Removes a temporary folder when reproduce leaves (also on errors and the signals above).
struct TempDir {
    std::string path;
    bool keep = false;
    ~TempDir() {
        if (keep || path.empty()) return;
        g_temp_set = 0;
        std::error_code ec;
        fs::remove_all(path, ec);
    }
};

std::string make_reproduce_folder() {
    std::string tmpl = temp_base() + "/" + kReproducePrefix + std::to_string(::getpid()) + ".XXXXXX";
    if (tmpl.size() >= sizeof g_temp_dir) throw Error("reproduce: TMPDIR '" + temp_base() + "' is too long a path");
    if (!::mkdtemp(tmpl.data())) throw Error("reproduce: cannot create a temporary folder under " + temp_base());
    std::memcpy(g_temp_dir, tmpl.c_str(), tmpl.size() + 1);
    g_temp_set = 1;
    for (const int sig : {SIGINT, SIGTERM, SIGHUP}) std::signal(sig, remove_temp_dir_on_signal);
    return tmpl;
}

std::string short_sha(const std::string& s) { return s.substr(0, 16); }

}  // namespace

std::string manifest_path(const std::string& image_path) { return image_path + ".json"; }

json manifest_core(const RenderJob& job, const RenderedImage& img) {
    json inputs = json::array();
    std::vector<InputRecord> read = job.inputs ? job.inputs->records() : inputs_read();
    if (job.inputs) {  // one record per file, sorted by path, as inputs_read lists them
        std::stable_sort(read.begin(), read.end(), [](const InputRecord& a, const InputRecord& b) { return a.path < b.path; });
        read.erase(std::unique(read.begin(), read.end(), [](const InputRecord& a, const InputRecord& b) { return a.path == b.path; }),
                   read.end());
    }
    for (const InputRecord& r : read)
        inputs.push_back({{"path", r.path}, {"bytes", r.bytes}, {"sha256", r.sha256}});
    json m = {{"aquarelle_manifest", kManifestFormat},
              {"build", build_json()},
              {"request", request_json(job, img)},
              {"image", {{"width", job.settings.width}, {"height", job.settings.height}, {"frame", img.frame}}},
              {"inputs", inputs}};
    // The camera of this frame (orbit applied) and its projection at the image's aspect: what
    // `aquarelle coherence` reprojects through (app/coherence.h).
    const scene::Camera cam = frame_camera(job, img.frame);
    const glm::mat4 proj = raster::projection_matrix(cam, float(job.settings.width) / float(job.settings.height));
    auto mat = [](const glm::mat4& a) {
        json v = json::array();
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r) v.push_back(a[c][r]);
        return v;
    };
    m["image"]["camera"] = {{"orthographic", cam.orthographic}, {"view", mat(cam.view)}, {"projection", mat(proj)},
                            {"zfar", cam.zfar}};
    m["pipeline"] = job.stylize && img.style_index < job.compiled.size() ? pipeline_json(job.compiled[img.style_index]) : json(nullptr);
    if (!job.sweep_labels.empty() && img.style_index < job.sweep_labels.size() && !job.sweep_labels[img.style_index].empty())
        m["image"]["sweep_value"] = job.sweep_labels[img.style_index];
    return m;
}

json manifest_with_outputs(json core, const std::string& sidecar_path, const std::vector<OutputFile>& files,
                           const std::vector<std::string>& sha256) {
    const fs::path dir = fs::path(absolute_path(sidecar_path)).parent_path();
    json outs = json::array();
    for (std::size_t i = 0; i < files.size() && i < sha256.size(); ++i)
        outs.push_back({{"file", fs::path(absolute_path(files[i].path)).lexically_relative(dir).string()},
                        {"target", files[i].target},
                        {"kind", files[i].kind},
                        {"sha256", sha256[i]}});
    core["outputs"] = outs;
    return core;
}

std::string manifest_text(const json& manifest) { return manifest.dump(2) + "\n"; }

// --- reproduce --------------------------------------------------------------------------------

namespace {

const json& need(const json& j, const char* key, const std::string& where) {
    if (!j.is_object() || !j.contains(key)) throw Error(where + ": no '" + std::string(key) + "' (not a complete Aquarelle manifest)");
    return j.at(key);
}

//! The render request of a manifest as RenderOptions writing into `dir`. Every field is read
//! strictly (JsonReader: an integer is a JSON integer, not 160.9 or true; a size is not wrapped
//! modulo 2^32) and within the same ranges as the command line's options (request_limits; 0 for
//! width, height and fps: "not given", as the CLI records it). A manifest cannot lift a safety
//! switch: a request made with --allow-outside-files reproduces only when the user passes it again.
RenderOptions options_from(const json& m, const std::string& where, const std::string& dir, const ReproduceOptions& ro) {
    namespace lim = request_limits;
    const json& r = need(m, "request", where);
    const JsonReader rd{where};
    auto at = [&](const json& j, const char* key) -> const json& { return need(j, key, where + ": request"); };
    RenderOptions o;
    o.scene = rd.string(at(r, "scene"), "request.scene");
    o.style = rd.string(at(r, "style"), "request.style");
    o.style_given = rd.boolean(at(r, "style_given"), "request.style_given");
    for (const char* list : {"set", "variant", "bypass"}) {
        // "bypass" is newer than the manifest format: absent in older manifests, meaning none.
        if (std::string(list) == "bypass" && !r.contains(list)) continue;
        const json& v = at(r, list);
        if (!v.is_array()) rd.bad(std::string("request.") + list, "expected a list of strings");
        std::vector<std::string>& dst = list[0] == 's' ? o.sets : list[0] == 'v' ? o.variants : o.bypass;
        for (std::size_t i = 0; i < v.size(); ++i)
            dst.push_back(rd.string(v[i], "request." + std::string(list) + "[" + std::to_string(i) + "]"));
    }
    o.width = rd.integer(at(r, "width"), "request.width", 0, kMaxImageSide);
    o.height = rd.integer(at(r, "height"), "request.height", 0, kMaxImageSide);
    o.frame_first = o.frame_last = rd.integer(at(r, "frame"), "request.frame", 0, lim::kMaxFrame);
    o.fps = rd.number(at(r, "fps"), "request.fps", 0.0, lim::kMaxFps);
    if (o.fps != 0.0 && o.fps < lim::kMinFps) rd.bad("request.fps", "value outside 0 (not given) or [" + std::to_string(lim::kMinFps) + ", " + std::to_string(lim::kMaxFps) + "]");
    o.orbit_deg = rd.number(at(r, "orbit_deg"), "request.orbit_deg", -lim::kMaxOrbitDeg, lim::kMaxOrbitDeg);
    o.ssaa = rd.integer(at(r, "ssaa"), "request.ssaa", 1, lim::kMaxSsaa);
    if (r.contains("scene_set")) {  // newer than the manifest format; absent: no edits
        const json& v = r.at("scene_set");
        if (!v.is_array() || v.size() > scene::kMaxSceneEdits) rd.bad("request.scene_set", "expected a list of \"POINTER=VALUE\" strings");
        for (std::size_t i = 0; i < v.size(); ++i)
            o.scene_edits.push_back(scene::parse_scene_edit(rd.string(v[i], "request.scene_set[" + std::to_string(i) + "]")));
    }
    if (r.contains("view")) {  // newer than the manifest format; absent: the camera as framed
        const json& v = r.at("view");
        if (!v.is_array() || (v.size() != 3 && v.size() != 5)) rd.bad("request.view", "expected [yaw, pitch, zoom] or [yaw, pitch, zoom, pan x, pan y]");
        o.view_yaw = rd.number(v[0], "request.view[0]", -lim::kMaxOrbitDeg, lim::kMaxOrbitDeg);
        o.view_pitch = rd.number(v[1], "request.view[1]", -lim::kMaxViewPitchDeg, lim::kMaxViewPitchDeg);
        o.view_zoom = rd.number(v[2], "request.view[2]", lim::kMinViewZoom, lim::kMaxViewZoom);
        if (v.size() == 5) {
            o.view_pan_x = rd.number(v[3], "request.view[3]", -lim::kMaxViewPan, lim::kMaxViewPan);
            o.view_pan_y = rd.number(v[4], "request.view[4]", -lim::kMaxViewPan, lim::kMaxViewPan);
        }
    }
    const std::string w = where + ": request";
    const std::string control = rd.string(at(r, "control"), "request.control");
    if (control != "default" && control != "neutral") throw Error(w + ": control '" + control + "' is not default or neutral");
    o.neutral_control = control == "neutral";
    const std::string ws = rd.string(at(r, "working_space"), "request.working_space");
    if (ws != "display" && ws != "linear") throw Error(w + ": working_space '" + ws + "' is not display or linear");
    o.working_space = ws == "linear" ? WorkingSpace::Linear : WorkingSpace::Display;
    // Manifests written before --antialias existed have no key: their images had one sample per
    // pixel, so they reproduce with none (the same bytes as then).
    const std::string aa = r.contains("antialias") ? rd.string(r.at("antialias"), "request.antialias") : "none";
    if (aa != "coverage" && aa != "none") throw Error(w + ": antialias '" + aa + "' is not coverage or none");
    o.antialias = aa == "none" ? raster::RenderSettings::Antialias::None : raster::RenderSettings::Antialias::Coverage;
    // Manifests written before --compression existed have no key: their files were compressed "fast".
    const std::string comp = r.contains("compression") ? rd.string(r.at("compression"), "request.compression") : "fast";
    if (!compression_from_name(comp, o.compression)) throw Error(w + ": compression '" + comp + "' is not fast or none");
    o.allow_outside_files = rd.boolean(at(r, "allow_outside_files"), "request.allow_outside_files");
    if (o.allow_outside_files && !ro.allow_outside_files)
        throw Error(where + ": the image was rendered with --allow-outside-files (its model may read files outside "
                            "its own folder); a manifest cannot lift that policy: pass --allow-outside-files to "
                            "reproduce it");
    const std::string ext = rd.string(at(r, "output_format"), "request.output_format");
    if (ext != ".png" && ext != ".exr" && ext != ".tif" && ext != ".tiff" && ext != ".jpg")
        throw Error(w + ": output_format '" + ext + "' is not .png, .exr, .tif or .jpg");
    if (r.contains("sweep")) {
        const json& s = r.at("sweep");
        o.sweep = rd.string(at(s, "param"), "request.sweep.param");
        o.sweep_from = rd.number(at(s, "from"), "request.sweep.from", -lim::kMaxSweepValue, lim::kMaxSweepValue);
        o.sweep_to = rd.number(at(s, "to"), "request.sweep.to", -lim::kMaxSweepValue, lim::kMaxSweepValue);
        o.sweep_count = rd.integer(at(s, "count"), "request.sweep.count", lim::kMinSweepCount, lim::kMaxSweepCount);
        const int index = rd.integer(at(s, "index"), "request.sweep.index", 0, o.sweep_count - 1);
        o.shard_count = o.sweep_count;  // render only this sweep value
        o.shard_index = index;
        o.out = dir + "/image_####" + ext;
    } else {
        o.out = dir + "/image" + ext;
    }
    if (rd.boolean(at(r, "targets"), "request.targets")) o.targets_dir = dir + "/targets";
    if (rd.boolean(at(r, "targets_png"), "request.targets_png")) o.targets_png_dir = dir + "/targets_png";
    o.keep_intermediates = !o.targets_dir.empty() || !o.targets_png_dir.empty();
    o.threads = ro.threads;
    o.quiet = ro.quiet;
    return o;
}

//! One file a manifest lists as written for its image ("outputs").
struct ListedOutput {
    std::string file, target, kind, sha256;
    std::string name() const { return target.empty() ? "the image (" + file + ")" : "target " + target + " (" + file + ")"; }
};

bool is_sha256_hex(const std::string& s) {
    return s.size() == 64 && std::all_of(s.begin(), s.end(), [](char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'); });
}

//! The manifest's "outputs", checked: a non-empty list of at most kMaxManifestOutputs entries, each
//! a file inside the manifest's folder (relative, no '..'), a known kind, a SHA-256; exactly one
//! image ("out"); no (kind, target) or file twice.
std::vector<ListedOutput> listed_outputs(const json& m, const std::string& where) {
    const json& outs = need(m, "outputs", where);
    if (!outs.is_array()) throw Error(where + ": 'outputs' is not a list");
    if (outs.empty()) throw Error(where + ": 'outputs' lists no file; a manifest names at least the image it describes");
    if (outs.size() > kMaxManifestOutputs)
        throw Error(where + ": 'outputs' lists " + std::to_string(outs.size()) + " files (at most " +
                    std::to_string(kMaxManifestOutputs) + ")");
    const JsonReader rd{where};
    std::vector<ListedOutput> v;
    std::set<std::pair<std::string, std::string>> keys;
    std::set<std::string> files;
    int images = 0;
    for (std::size_t i = 0; i < outs.size(); ++i) {
        const std::string k = "outputs[" + std::to_string(i) + "]";
        rd.check_keys(outs[i], k, {"file", "target", "kind", "sha256"});
        ListedOutput o{rd.string(need(outs[i], "file", where), k + ".file"), rd.string(need(outs[i], "target", where), k + ".target"),
                       rd.string(need(outs[i], "kind", where), k + ".kind"), rd.string(need(outs[i], "sha256", where), k + ".sha256")};
        const fs::path f(o.file);
        if (o.file.empty() || f.is_absolute() || f.lexically_normal() != f ||
            std::any_of(f.begin(), f.end(), [](const fs::path& part) { return part == ".." || part == "."; }))
            rd.bad(k + ".file", "'" + o.file + "' is not a file inside the manifest's folder");
        if (o.kind != "out" && o.kind != "exr" && o.kind != "png") rd.bad(k + ".kind", "'" + o.kind + "' is not out, exr or png");
        if ((o.kind == "out") != o.target.empty()) rd.bad(k + ".target", "the image has no target name; every other file has one");
        if (!is_sha256_hex(o.sha256)) rd.bad(k + ".sha256", "not a SHA-256 (64 lower-case hex digits)");
        if (!keys.insert({o.kind, o.target}).second || !files.insert(o.file).second) rd.bad(k, "listed twice");
        images += o.kind == "out";
        v.push_back(std::move(o));
    }
    if (images != 1) throw Error(where + ": 'outputs' lists " + std::to_string(images) + " images (kind \"out\"); exactly one expected");
    return v;
}

//! The manifest's "inputs", checked: at most kMaxManifestInputs entries, each an absolute path
//! listed once with a SHA-256. Nothing is read here: a listed file is hashed only by the render
//! that reads it again, so a manifest cannot make reproduce read files the render does not.
std::map<std::string, std::string> listed_inputs(const json& m, const std::string& where) {
    const json& inputs = need(m, "inputs", where);
    if (!inputs.is_array()) throw Error(where + ": 'inputs' is not a list");
    if (inputs.size() > kMaxManifestInputs)
        throw Error(where + ": 'inputs' lists " + std::to_string(inputs.size()) + " files (at most " +
                    std::to_string(kMaxManifestInputs) + ")");
    const JsonReader rd{where};
    std::map<std::string, std::string> v;
    for (std::size_t i = 0; i < inputs.size(); ++i) {
        const std::string k = "inputs[" + std::to_string(i) + "]";
        const std::string path = rd.string(need(inputs[i], "path", where), k + ".path");
        const std::string sha = rd.string(need(inputs[i], "sha256", where), k + ".sha256");
        if (!fs::path(path).is_absolute() || fs::path(path).lexically_normal() != fs::path(path))
            rd.bad(k + ".path", "'" + path + "' is not an absolute, normalised path (as render records them)");
        if (!is_sha256_hex(sha)) rd.bad(k + ".sha256", "not a SHA-256 (64 lower-case hex digits)");
        if (!v.emplace(path, sha).second) rd.bad(k + ".path", "'" + path + "' listed twice");
    }
    return v;
}

//! The first difference between two JSON values, as "PATH: A -> B" (RFC 6902 patch of nlohmann).
std::string first_difference(const json& a, const json& b) {
    const json patch = json::diff(a, b);
    if (patch.empty()) return "";
    const json& op = patch.front();
    std::string s = op.value("path", std::string("/"));
    const auto ptr = json::json_pointer(s);
    s += ": " + (a.contains(ptr) ? a.at(ptr).dump() : std::string("(absent)")) + " -> " +
         (op.contains("value") ? op.at("value").dump() : std::string("(absent)"));
    if (patch.size() > 1) s += " (and " + std::to_string(patch.size() - 1) + " more)";
    return s;
}

}  // namespace

namespace {

//! Step 1 of reproduce: the same bytes are only promised by the same build. A difference is an
//! error unless --any-version, then a line of the result.
void check_build(const json& m, const std::string& where, const ReproduceOptions& ro, ReproduceResult& res) {
    const json build = need(m, "build", where);
    const json mine = build_json();
    std::vector<std::string> differs;
    for (const auto& [k, v] : mine.items())
        if (!build.contains(k) || build.at(k) != v)
            differs.push_back(k + " " + (build.contains(k) ? build.at(k).dump() : std::string("(absent)")) + " (this build: " + v.dump() + ")");
    if (!differs.empty()) {
        std::string s;
        for (const std::string& d : differs) s += (s.empty() ? "" : "; ") + d;
        if (!ro.any_version)
            throw Error(where + " was made by another build of Aquarelle: " + s +
                        ". Build that commit to reproduce it, or pass --any-version to render and compare anyway");
        res.lines.push_back("build differs: " + s);
        res.status = kReproduceDiffers;
    }

}

//! Step 2: every listed input present before anything is rendered.
void check_inputs_present(const std::map<std::string, std::string>& inputs, const std::string& where) {
    std::vector<std::string> missing;
    for (const auto& [path, sha] : inputs) {
        std::error_code ec;
        if (!fs::is_regular_file(path, ec)) missing.push_back(path);
    }
    if (!missing.empty()) {
        std::string s;
        for (const std::string& p : missing) s += (s.empty() ? "" : ", ") + p;
        throw Error(where + ": " + std::to_string(missing.size()) + " input file(s) missing: " + s);
    }

}

//! Step 3: every output the manifest names is beside it (in mdir) with the SHA-256 it records.
void check_outputs_beside(const std::vector<ListedOutput>& outs, const fs::path& mdir, ReproduceResult& res) {
    for (const ListedOutput& f : outs) {
        const fs::path original = mdir / f.file;
        std::error_code ec;
        if (!fs::is_regular_file(original, ec)) {
            res.lines.push_back("missing beside the manifest: " + f.name());
            res.status = kReproduceDiffers;
            continue;
        }
        const std::vector<unsigned char> bytes = read_input_file(original.string(), kMaxModelFileBytes, "output file");
        forget_input_record(original.string());  // read about the render, not for it (stays protected)
        const std::string now = sha256_hex(bytes.data(), bytes.size());
        if (now != f.sha256) {
            res.lines.push_back("changed since it was written: " + f.name() + " (sha256 " + short_sha(f.sha256) +
                                "... in the manifest, " + short_sha(now) + "... now)");
            res.status = kReproduceDiffers;
        }
    }

}

//! Step 4's folder: a new or empty --keep folder (never the originals'), else a temporary one.
void reproduction_folder(const ReproduceOptions& ro, const fs::path& mdir, TempDir& dir) {
    if (!ro.keep_dir.empty()) {
        std::error_code ec;
        if (fs::exists(ro.keep_dir, ec)) {
            if (!fs::is_directory(ro.keep_dir, ec)) throw Error("reproduce --keep: '" + ro.keep_dir + "' exists and is not a folder");
            if (fs::equivalent(ro.keep_dir, mdir, ec))
                throw Error("reproduce --keep: '" + ro.keep_dir + "' is the manifest's own folder: the reproduction would "
                            "replace the originals. Give a new or empty folder");
            if (!fs::is_empty(ro.keep_dir, ec) || ec)
                throw Error("reproduce --keep: '" + ro.keep_dir + "' is not empty; give a new or empty folder "
                            "(reproduce never writes over existing files)");
        }
        ensure_directory(ro.keep_dir);
        dir.path = ro.keep_dir;
        dir.keep = true;
    } else {
        dir.path = make_reproduce_folder();
    }
}

//! Step 5, the files read: the same set, the same bytes.
void compare_inputs(const std::map<std::string, std::string>& inputs, const std::map<std::string, std::string>& read_again,
                    ReproduceResult& res) {
    for (const auto& [path, sha] : inputs) {
        const auto it = read_again.find(path);
        if (it == read_again.end()) {
            res.lines.push_back("input not read by the render: " + path);
            res.status = kReproduceDiffers;
        } else if (it->second != sha) {
            res.lines.push_back("input changed: " + path + " (sha256 " + short_sha(sha) + "... in the manifest, " +
                                short_sha(it->second) + "... now)");
            res.status = kReproduceDiffers;
        }
    }
    for (const auto& [path, sha] : read_again)
        if (!inputs.count(path)) {
            res.lines.push_back("input not in the manifest: " + path);
            res.status = kReproduceDiffers;
        }
}

//! The line describing the first differing output f (original beside the manifest in mdir, the
//! reproduction's file again_file in ndir): hashes, then size or pixel statistics.
std::string first_difference_line(const ListedOutput& f, const ListedOutput& again_file, const fs::path& mdir,
                                  const fs::path& ndir) {
    const std::string name = f.name();
    std::string line = "first differing output: " + name + ": sha256 " + short_sha(f.sha256) + "... -> " +
                       short_sha(again_file.sha256) + "...";
    const fs::path original = mdir / f.file;
    std::error_code ec;
    if (fs::is_regular_file(original, ec)) {
        const ImageF a = read_image(original.string());
        const ImageF b = read_image((ndir / again_file.file).string());
        if (a.width() != b.width() || a.height() != b.height() || a.channels() != b.channels()) {
            line += "; size " + std::to_string(a.width()) + "x" + std::to_string(a.height()) + "x" +
                    std::to_string(a.channels()) + " -> " + std::to_string(b.width()) + "x" + std::to_string(b.height()) +
                    "x" + std::to_string(b.channels());
        } else {
            const CompareStats s = compare_images(a, b, 1.0 / 255.0);
            line += "; mean_abs " + std::to_string(s.mean_abs) + ", max_abs " + std::to_string(s.max_abs) + " at (" +
                    std::to_string(s.max_x) + ", " + std::to_string(s.max_y) + ") channel " + std::to_string(s.max_c) +
                    ", over 1/255 " + std::to_string(100.0 * s.frac_over) + " %, psnr " + std::to_string(s.psnr) + " dB" +
                    (s.max_abs == 0.0 ? " (same pixels; the file bytes differ, e.g. in the embedded manifest)" : "");
        }
    } else {
        line += "; the original file is not beside the manifest, so pixels are not compared";
    }
    return line;
}

//! Step 5, the outputs: every one in the manifest's order (pipeline order), and nothing produced that
//! the manifest leaves out.
void compare_outputs(const std::vector<ListedOutput>& outs, const json& again, const fs::path& mdir, const fs::path& ndir,
                     ReproduceResult& res) {
    std::map<std::pair<std::string, std::string>, ListedOutput> by_key;
    for (ListedOutput& f : listed_outputs(again, "the reproduction's manifest")) by_key[{f.kind, f.target}] = std::move(f);
    int differing = 0;
    for (const ListedOutput& f : outs) {
        const std::string name = f.name();
        const auto it = by_key.find({f.kind, f.target});
        if (it == by_key.end()) {
            res.lines.push_back("not produced again: " + name);
            res.status = kReproduceDiffers;
            ++differing;
            continue;
        }
        const ListedOutput again_file = it->second;
        by_key.erase(it);
        if (again_file.sha256 == f.sha256) continue;
        res.status = kReproduceDiffers;
        if (differing++ > 0) continue;  // details for the first one only
        res.lines.push_back(first_difference_line(f, again_file, mdir, ndir));
    }
    for (const auto& [key, f] : by_key) {
        res.lines.push_back("produced again but not in the manifest: " + f.name());
        res.status = kReproduceDiffers;
    }
    if (differing > 1) res.lines.push_back(std::to_string(differing) + " of " + std::to_string(outs.size()) + " outputs differ");
}

}  // namespace

ReproduceResult reproduce(const ReproduceOptions& ro, const Reporter& report) {
    const std::string where = "manifest '" + ro.manifest + "'";
    const json m = read_json_file(ro.manifest, "manifest");
    forget_input_record(ro.manifest);  // read about the render, not for it
    if (!m.is_object() || !m.contains("aquarelle_manifest"))
        throw Error(where + ": not an Aquarelle manifest (no 'aquarelle_manifest' key)");
    if (!m.at("aquarelle_manifest").is_number_integer() || m.at("aquarelle_manifest").get<long long>() != kManifestFormat)
        throw Error(where + ": manifest format " + m.at("aquarelle_manifest").dump() + "; this build reads format " +
                    std::to_string(kManifestFormat));
    ReproduceResult res;

    // 1. The build: the same bytes are only promised by the same build.
    check_build(m, where, ro, res);
    // 2. Every input listed (bounded, each once) and present, before anything is rendered; their
    //    bytes are compared with what the render reads again (step 5).
    const std::map<std::string, std::string> inputs = listed_inputs(m, where);
    check_inputs_present(inputs, where);
    // 3. Every output the manifest names is beside it with the SHA-256 it records: "identical" is a
    //    statement about those files. Hashing them also protects them from being written over.
    const std::vector<ListedOutput> outs = listed_outputs(m, where);
    const fs::path mdir = fs::path(absolute_path(ro.manifest)).parent_path();
    check_outputs_beside(outs, mdir, res);
    // 4. Render again into a folder of our own: a new or empty --keep folder (never the originals'),
    //    else a temporary one, removed on every exit (signals included, app/manifest.h).
    remove_stale_reproduce_folders();
    TempDir dir;
    reproduction_folder(ro, mdir, dir);
    RenderOptions o = options_from(m, where, dir.path, ro);
    RenderJob job = prepare_render(o, report);
    if (!o.targets_dir.empty()) ensure_directory(o.targets_dir);
    if (!o.targets_png_dir.empty()) ensure_directory(o.targets_png_dir);
    render_to_files(job, report);
    const int index = o.sweep.empty() ? o.frame_first : o.shard_index;
    const json again = read_json_file(manifest_path(frame_path(o.out, index)), "manifest of the reproduction");

    // 5. Compare: the files read (the same set, the same bytes), the pipeline, then every output in
    //    the manifest's order (pipeline order), and nothing produced that the manifest leaves out.
    const std::map<std::string, std::string> read_again = listed_inputs(again, "the reproduction's manifest");
    compare_inputs(inputs, read_again, res);
    if (m.value("pipeline", json()) != again.value("pipeline", json())) {
        res.lines.push_back("pipeline differs: " + first_difference(m.value("pipeline", json()), again.value("pipeline", json())));
        res.status = kReproduceDiffers;
    }
    const fs::path ndir = fs::path(absolute_path(manifest_path(frame_path(o.out, index)))).parent_path();
    compare_outputs(outs, again, mdir, ndir, res);
    if (res.status == 0)
        res.lines.push_back("identical: " + std::to_string(outs.size()) + " output file(s), same SHA-256, beside the manifest and rendered again");
    if (dir.keep) res.lines.push_back("reproduction kept in " + dir.path);
    return res;
}

}  // namespace aq::app
