// app/manifest.cpp — see manifest.h.
#include "app/manifest.h"

#include <stdlib.h>

#include <algorithm>
#include <filesystem>
#include <map>

#include "app/render_files.h"
#include "core/build_info.h"
#include "core/compare.h"
#include "core/hash.h"
#include "core/input.h"
#include "core/io.h"
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
        {"width", o.width},
        {"height", o.height},
        {"frame", img.frame},
        {"fps", o.fps},
        {"orbit_deg", o.orbit_deg},
        {"ssaa", o.ssaa},
        {"control", o.neutral_control ? "neutral" : "default"},
        {"working_space", o.working_space == WorkingSpace::Linear ? "linear" : "display"},
        {"compression", compression_name(o.compression)},
        {"allow_outside_files", o.allow_outside_files},
        {"targets", !o.targets_dir.empty()},
        {"targets_png", !o.targets_png_dir.empty()},
        {"output_format", fs::path(o.out).extension().string()},
    };
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
                        {"cells_per_radius", c.foliage.cells_per_radius}, {"fit_threshold", c.foliage.fit_threshold}};
    return p;
}

//! Removes a temporary folder when reproduce leaves (also on errors).
struct TempDir {
    std::string path;
    bool keep = false;
    ~TempDir() {
        if (keep || path.empty()) return;
        std::error_code ec;
        fs::remove_all(path, ec);
    }
};

std::string short_sha(const std::string& s) { return s.substr(0, 16); }

}  // namespace

std::string manifest_path(const std::string& image_path) { return image_path + ".json"; }

json manifest_core(const RenderJob& job, const RenderedImage& img) {
    json inputs = json::array();
    for (const InputRecord& r : inputs_read())
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

template <class T>
T get(const json& j, const char* key, const std::string& where) {
    try {
        return need(j, key, where).get<T>();
    } catch (const json::exception&) {
        throw Error(where + ": key '" + std::string(key) + "' has the wrong type");
    }
}

//! The render request of a manifest as RenderOptions writing into `dir`.
RenderOptions options_from(const json& m, const std::string& where, const std::string& dir, const ReproduceOptions& ro) {
    const json& r = need(m, "request", where);
    const std::string w = where + ": request";
    RenderOptions o;
    o.scene = get<std::string>(r, "scene", w);
    o.style = get<std::string>(r, "style", w);
    o.style_given = get<bool>(r, "style_given", w);
    o.sets = get<std::vector<std::string>>(r, "set", w);
    o.variants = get<std::vector<std::string>>(r, "variant", w);
    o.width = get<int>(r, "width", w);
    o.height = get<int>(r, "height", w);
    o.frame_first = o.frame_last = get<int>(r, "frame", w);
    o.fps = get<double>(r, "fps", w);
    o.orbit_deg = get<double>(r, "orbit_deg", w);
    o.ssaa = get<int>(r, "ssaa", w);
    const std::string control = get<std::string>(r, "control", w);
    if (control != "default" && control != "neutral") throw Error(w + ": control '" + control + "' is not default or neutral");
    o.neutral_control = control == "neutral";
    const std::string ws = get<std::string>(r, "working_space", w);
    if (ws != "display" && ws != "linear") throw Error(w + ": working_space '" + ws + "' is not display or linear");
    o.working_space = ws == "linear" ? WorkingSpace::Linear : WorkingSpace::Display;
    // Manifests written before --compression existed have no key: their files were compressed "fast".
    const std::string comp = r.contains("compression") ? get<std::string>(r, "compression", w) : "fast";
    if (!compression_from_name(comp, o.compression)) throw Error(w + ": compression '" + comp + "' is not fast or none");
    o.allow_outside_files = get<bool>(r, "allow_outside_files", w);
    const std::string ext = get<std::string>(r, "output_format", w);
    if (ext != ".png" && ext != ".exr" && ext != ".tif" && ext != ".tiff" && ext != ".jpg")
        throw Error(w + ": output_format '" + ext + "' is not .png, .exr, .tif or .jpg");
    if (r.contains("sweep")) {
        const json& s = r.at("sweep");
        o.sweep = get<std::string>(s, "param", w + ".sweep");
        o.sweep_from = get<double>(s, "from", w + ".sweep");
        o.sweep_to = get<double>(s, "to", w + ".sweep");
        o.sweep_count = get<int>(s, "count", w + ".sweep");
        const int index = get<int>(s, "index", w + ".sweep");
        if (o.sweep_count < 2 || o.sweep_count > 1000 || index < 0 || index >= o.sweep_count)
            throw Error(w + ".sweep: index " + std::to_string(index) + " of " + std::to_string(o.sweep_count) + " is not a sweep value");
        o.shard_count = o.sweep_count;  // render only this sweep value
        o.shard_index = index;
        o.out = dir + "/image_####" + ext;
    } else {
        o.out = dir + "/image" + ext;
    }
    if (get<bool>(r, "targets", w)) o.targets_dir = dir + "/targets";
    if (get<bool>(r, "targets_png", w)) o.targets_png_dir = dir + "/targets_png";
    o.keep_intermediates = !o.targets_dir.empty() || !o.targets_png_dir.empty();
    o.threads = ro.threads;
    o.quiet = ro.quiet;
    return o;
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

    // 2. Every input, present and unchanged, before anything is rendered.
    const json& inputs = need(m, "inputs", where);
    if (!inputs.is_array()) throw Error(where + ": 'inputs' is not a list");
    std::vector<std::string> missing;
    for (const json& in : inputs) {
        const std::string path = get<std::string>(in, "path", where + ": inputs");
        const std::string sha = get<std::string>(in, "sha256", where + ": inputs");
        std::error_code ec;
        if (!fs::is_regular_file(path, ec)) {
            missing.push_back(path);
            continue;
        }
        const std::vector<unsigned char> bytes = read_input_file(path, kMaxModelFileBytes, "input");
        const std::string now = sha256_hex(bytes.data(), bytes.size());
        if (now != sha) {
            res.lines.push_back("input changed: " + path + " (sha256 " + short_sha(sha) + "... in the manifest, " + short_sha(now) + "... now)");
            res.status = kReproduceDiffers;
        }
    }
    if (!missing.empty()) {
        std::string s;
        for (const std::string& p : missing) s += (s.empty() ? "" : ", ") + p;
        throw Error(where + ": " + std::to_string(missing.size()) + " input file(s) missing: " + s);
    }

    // 3. Render again into a folder of our own.
    TempDir dir;
    if (!ro.keep_dir.empty()) {
        ensure_directory(ro.keep_dir);
        dir.path = ro.keep_dir;
        dir.keep = true;
    } else {
        const char* base = std::getenv("TMPDIR");
        std::string tmpl = std::string(base && *base ? base : "/tmp") + "/aquarelle-reproduce.XXXXXX";
        if (!::mkdtemp(tmpl.data())) throw Error("reproduce: cannot create a temporary folder under " + tmpl);
        dir.path = tmpl;
    }
    RenderOptions o = options_from(m, where, dir.path, ro);
    RenderJob job = prepare_render(o, report);
    if (!o.targets_dir.empty()) ensure_directory(o.targets_dir);
    if (!o.targets_png_dir.empty()) ensure_directory(o.targets_png_dir);
    render_to_files(job, report);
    const int index = o.sweep.empty() ? o.frame_first : o.shard_index;
    const json again = read_json_file(manifest_path(frame_path(o.out, index)), "manifest of the reproduction");

    // 4. Compare: the pipeline, then every output in the manifest's order (pipeline order).
    if (m.value("pipeline", json()) != again.value("pipeline", json())) {
        res.lines.push_back("pipeline differs: " + first_difference(m.value("pipeline", json()), again.value("pipeline", json())));
        res.status = kReproduceDiffers;
    }
    const json& outs = need(m, "outputs", where);
    const json& new_outs = need(again, "outputs", "the reproduction's manifest");
    std::map<std::pair<std::string, std::string>, json> by_key;
    for (const json& f : new_outs) by_key[{f.value("kind", ""), f.value("target", "")}] = f;
    const fs::path mdir = fs::path(absolute_path(ro.manifest)).parent_path();
    const fs::path ndir = fs::path(absolute_path(manifest_path(frame_path(o.out, index)))).parent_path();
    int differing = 0;
    for (const json& f : outs) {
        const std::string kind = get<std::string>(f, "kind", where + ": outputs");
        const std::string target = get<std::string>(f, "target", where + ": outputs");
        const std::string file = get<std::string>(f, "file", where + ": outputs");
        const std::string name = target.empty() ? "the image (" + file + ")" : "target " + target + " (" + file + ")";
        const auto it = by_key.find({kind, target});
        if (it == by_key.end()) {
            res.lines.push_back("not produced again: " + name);
            res.status = kReproduceDiffers;
            ++differing;
            continue;
        }
        if (it->second.value("sha256", "") == get<std::string>(f, "sha256", where + ": outputs")) continue;
        res.status = kReproduceDiffers;
        if (differing++ > 0) continue;  // details for the first one only
        std::string line = "first differing output: " + name + ": sha256 " + short_sha(f.value("sha256", "")) + "... -> " +
                           short_sha(it->second.value("sha256", "")) + "...";
        const fs::path original = mdir / file;
        std::error_code ec;
        if (fs::is_regular_file(original, ec)) {
            const ImageF a = read_image(original.string());
            const ImageF b = read_image((ndir / it->second.value("file", "")).string());
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
        res.lines.push_back(line);
    }
    if (differing > 1) res.lines.push_back(std::to_string(differing) + " of " + std::to_string(outs.size()) + " outputs differ");
    if (res.status == 0) res.lines.push_back("identical: " + std::to_string(outs.size()) + " output file(s), same SHA-256");
    if (dir.keep) res.lines.push_back("reproduction kept in " + dir.path);
    return res;
}

}  // namespace aq::app
