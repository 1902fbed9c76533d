// scenes/scene_file.cpp — JSON scene files (the LD06 sections in scene_file_ld06.cpp; the control
// mapping rules in control_rules.cpp) and automatic framing.
#include "scenes/scene_file.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>
#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include "core/json_file.h"
#include "scenes/gltf_loader.h"
#include "scenes/material_params.h"
#include "scenes/procedural.h"
#include "scenes/scene_file_reader.h"

namespace aq::scene {
namespace {

namespace fs = std::filesystem;
using namespace file;  // Ctx, the LD06 sections (scenes/scene_file_reader.h)

std::string lower(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

bool ends_with(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

Light default_light() {
    Light l;
    l.direction = glm::normalize(glm::vec3(-0.4f, 0.75f, 0.55f));
    l.color = glm::vec3(1.0f);
    l.intensity = 1.0f;
    return l;
}

Camera frame_bounds(const Bounds& b, float aspect, glm::vec3 view_dir, float yfov) {
    Camera c;
    c.name = "auto";
    if (!(yfov > 0.01f && yfov < 3.0f)) yfov = 0.6f;
    if (!(aspect > 0.0f) || !std::isfinite(aspect)) aspect = 16.0f / 9.0f;
    c.yfov = yfov;
    if (!(glm::length(view_dir) > 0.0f) || !std::isfinite(glm::length(view_dir))) view_dir = {-0.35f, -0.3f, -1.0f};
    view_dir = glm::normalize(view_dir);
    if (!b.valid) {
        c.view = glm::lookAt(glm::vec3(0, 0, 5), glm::vec3(0), glm::vec3(0, 1, 0));
        c.znear = 0.1f;
        c.zfar = 100.0f;
        return c;
    }
    const glm::vec3 center = 0.5f * (b.min + b.max);
    float radius = 0.5f * glm::length(b.max - b.min);
    if (!(radius > 1e-6f) || !std::isfinite(radius)) radius = std::max(1e-3f, std::abs(center.x) * 1e-3f);
    const float xfov = 2.0f * std::atan(std::tan(0.5f * yfov) * aspect);
    const float fov = std::min(yfov, xfov);
    const float dist = radius / std::sin(0.5f * fov) * 1.05f;  // 5 % margin
    const glm::vec3 eye = center - view_dir * dist;
    const glm::vec3 up = std::abs(view_dir.y) > 0.999f ? glm::vec3(0, 0, -1) : glm::vec3(0, 1, 0);
    c.view = glm::lookAt(eye, center, up);
    c.znear = std::max(dist - radius * 1.1f, dist * 0.01f);
    c.zfar = dist + radius * 1.1f;
    return c;
}

namespace {

Camera parse_camera(const Ctx& ctx, const json& j, const Scene& scene, float aspect, SceneDesc& desc) {
    auto auto_cam = [&](glm::vec3 dir, float yfov) {
        desc.camera_auto = true;
        desc.auto_view_dir = dir;
        desc.auto_yfov = yfov;
        desc.auto_aspect = aspect;
        return frame_bounds(scene.world_bounds(), aspect, dir, yfov);
    };
    if (j.is_string()) {
        if (j.get<std::string>() != "auto") ctx.bad("camera", "expected \"auto\", a glTF camera index or an object");
        return auto_cam(desc.auto_view_dir, desc.auto_yfov);
    }
    if (j.is_number_integer()) {
        const int i = ctx.integer(j, "camera", 0, 1 << 30);
        if (std::size_t(i) >= scene.cameras.size())
            ctx.bad("camera", "camera " + std::to_string(i) + " does not exist (the model has " +
                                  std::to_string(scene.cameras.size()) + " cameras on its nodes)");
        return scene.cameras[std::size_t(i)];
    }
    ctx.check_keys(j, "camera", {"auto", "view_dir", "eye", "target", "up", "yfov", "yfov_deg", "near", "far", "orthographic", "ymag", "xmag"});
    float yfov = 0.6f;
    if (j.contains("yfov") && j.contains("yfov_deg")) ctx.bad("camera.yfov", "give yfov (radians) or yfov_deg, not both");
    if (j.contains("yfov")) yfov = float(ctx.number(j["yfov"], "camera.yfov", 0.01, 3.0));
    if (j.contains("yfov_deg")) yfov = float(glm::radians(ctx.number(j["yfov_deg"], "camera.yfov_deg", 0.5, 170.0)));
    const bool is_auto = j.contains("auto") && ctx.boolean(j["auto"], "camera.auto");
    if (is_auto) {
        for (const char* k : {"eye", "target", "up", "near", "far", "orthographic", "ymag", "xmag"})
            if (j.contains(k)) ctx.bad(std::string("camera.") + k, "not allowed with \"auto\": true");
        glm::vec3 dir = desc.auto_view_dir;
        if (j.contains("view_dir")) dir = ctx.vec3(j["view_dir"], "camera.view_dir");
        if (!(glm::length(dir) > 0.0f)) ctx.bad("camera.view_dir", "must not be zero");
        return auto_cam(dir, yfov);
    }
    if (j.contains("view_dir")) ctx.bad("camera.view_dir", "only with \"auto\": true");
    if (!j.contains("eye")) ctx.bad("camera.eye", "missing (or use \"auto\": true)");
    if (!j.contains("target")) ctx.bad("camera.target", "missing");
    Camera c;
    c.name = "scene file";
    const glm::vec3 eye = ctx.vec3(j["eye"], "camera.eye"), target = ctx.vec3(j["target"], "camera.target");
    const glm::vec3 up = j.contains("up") ? ctx.vec3(j["up"], "camera.up") : glm::vec3(0, 1, 0);
    if (!(glm::length(target - eye) > 0.0f)) ctx.bad("camera.target", "equals the eye");
    if (!(glm::length(glm::cross(target - eye, up)) > 1e-6f * glm::length(target - eye) * glm::length(up)))
        ctx.bad("camera.up", "parallel to the view direction");
    c.view = glm::lookAt(eye, target, up);
    c.yfov = yfov;
    c.znear = j.contains("near") ? float(ctx.number(j["near"], "camera.near", 1e-6, 1e9)) : 0.1f;
    c.zfar = j.contains("far") ? float(ctx.number(j["far"], "camera.far", 1e-6, 1e12)) : 1000.0f;
    if (!(c.zfar > c.znear)) ctx.bad("camera.far", "must be greater than near");
    if (j.contains("orthographic")) c.orthographic = ctx.boolean(j["orthographic"], "camera.orthographic");
    if (j.contains("ymag")) c.ymag = float(ctx.number(j["ymag"], "camera.ymag", 1e-9, 1e9));
    c.xmag = j.contains("xmag") ? float(ctx.number(j["xmag"], "camera.xmag", 1e-9, 1e9)) : c.ymag * aspect;
    if (!c.orthographic && (j.contains("ymag") || j.contains("xmag"))) ctx.bad("camera.ymag", "only for orthographic cameras");
    return c;
}

std::vector<int> match_materials(const Ctx& ctx, const Scene& s, const std::string& name, const std::string& key) {
    std::vector<int> out;
    for (std::size_t i = 0; i < s.materials.size(); ++i)
        if (name == "*" || s.materials[i].name == name) out.push_back(int(i));
    if (out.empty() && !name.empty() && std::all_of(name.begin(), name.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); })) {
        const long long i = name.size() < 10 ? std::stoll(name) : -1;
        if (i >= 0 && i < (long long)s.materials.size()) out.push_back(int(i));
    }
    if (out.empty()) {
        std::string known;
        for (const Material& m : s.materials) known += (known.empty() ? "" : ", ") + ("'" + m.name + "'");
        ctx.bad(key, "no material named or numbered '" + name + "' (materials: " + known + ")");
    }
    return out;
}

// --- editing the art direction (SceneEdit, SceneKnob) ------------------------------------------

//! The blocks whose values may be edited, in the order knobs are listed.
constexpr const char* kEditableRoots[] = {"control", "layers", "foliage", "lights", "ambient", "substrate_color", "materials"};

//! Keys whose three numbers in [0, 1] are a colour (a panel shows a colour picker).
bool colour_key(const std::string& key) {
    const std::string k = lower(key);
    return k.find("color") != std::string::npos || k == "dark" || k == "light" || k == "ambient";
}

//! Keys whose integer values are counts or seeds (a panel steps them by 1).
bool integer_key(const std::string& key) { return key == "seed" || key == "octaves" || key == "cells_per_radius"; }

std::string pointer_token(const std::string& key) {  // RFC 6901 escaping
    std::string t;
    for (char c : key) t += c == '~' ? std::string("~0") : c == '/' ? std::string("~1") : std::string(1, c);
    return t;
}

//! `group`: the block, or the block's element ("layers[1] crown"); `path`: the keys inside it.
void collect_knobs(const json& v, const std::string& ptr, const std::string& group, const std::string& path, const std::string& key,
                   bool top, std::vector<SceneKnob>& out) {
    if (out.size() >= kMaxSceneKnobs) return;
    const std::string name = path.empty() ? key : path;
    if (v.is_boolean()) {
        out.push_back({ptr, "bool", v.dump(), group, name});
    } else if (v.is_number()) {
        out.push_back({ptr, v.is_number_integer() && integer_key(key) ? "integer" : "number", v.dump(), group, name});
    } else if (v.is_object()) {
        for (auto it = v.begin(); it != v.end(); ++it)
            collect_knobs(it.value(), ptr + "/" + pointer_token(it.key()), group, path.empty() ? it.key() : path + "." + it.key(),
                          it.key(), false, out);
    } else if (v.is_array()) {
        const bool numbers = std::all_of(v.begin(), v.end(), [](const json& x) { return x.is_number(); });
        if (numbers && v.size() >= 2 && v.size() <= 4) {
            const bool unit = std::all_of(v.begin(), v.end(), [](const json& x) { return x.get<double>() >= 0.0 && x.get<double>() <= 1.0; });
            out.push_back({ptr, v.size() == 3 && unit && colour_key(key) ? "color" : "vector", v.dump(), group, name});
            return;
        }
        for (std::size_t i = 0; i < v.size(); ++i) {
            if (!v[i].is_object()) continue;  // names, lists of names: not values
            const std::string index = "[" + std::to_string(i) + "]";
            std::string g = group, p = path + index;
            if (top) {  // an element of a block: its own group, named by its name, target or comment
                g = group + index;
                for (const char* k : {"name", "target", "comment"})
                    if (v[i].contains(k) && v[i][k].is_string()) {
                        g += " " + v[i][k].get<std::string>().substr(0, 60);
                        break;
                    }
                p.clear();
            }
            collect_knobs(v[i], ptr + "/" + std::to_string(i), g, p, key, false, out);
        }
    }
}

std::vector<SceneKnob> knobs_of(const json& j) {
    std::vector<SceneKnob> out;
    if (!j.is_object()) return out;
    for (const char* root : kEditableRoots)
        if (j.contains(root)) collect_knobs(j[root], std::string("/") + root, root, "", root, true, out);
    return out;
}

//! Applies SceneEdits to a scene file's JSON: each must name one of the file's knobs and bring a
//! value of that knob's kind (the ranges are the reader's, checked when the file is read).
void apply_edits(json& j, const std::vector<SceneEdit>& edits, const Ctx& ctx) {
    if (edits.size() > kMaxSceneEdits)
        ctx.bad("", std::to_string(edits.size()) + " edits (--scene-set); at most " + std::to_string(kMaxSceneEdits));
    const std::vector<SceneKnob> knobs = knobs_of(j);
    for (const SceneEdit& e : edits) {
        const std::string what = "--scene-set " + e.pointer;
        const auto k = std::find_if(knobs.begin(), knobs.end(), [&](const SceneKnob& x) { return x.pointer == e.pointer; });
        if (k == knobs.end())
            throw Error(ctx.where + ": " + what + ": not an editable value of this file (numbers, bools and colours under "
                        "control, layers, foliage, lights, ambient, substrate_color and materials; `aquarelle scene-values " +
                        "FILE` lists them)");
        const json v = json::parse(e.value, nullptr, false);
        bool ok = false;
        if (k->kind == "bool") ok = v.is_boolean();
        else if (k->kind == "number") ok = v.is_number();
        else if (k->kind == "integer") ok = v.is_number_integer();
        else ok = v.is_array() && v.size() == json::parse(k->value).size() &&
                  std::all_of(v.begin(), v.end(), [](const json& x) { return x.is_number(); });
        if (!ok) throw Error(ctx.where + ": " + what + ": expected " + (k->kind == "color" || k->kind == "vector"
                                 ? "an array of " + std::to_string(json::parse(k->value).size()) + " numbers"
                                 : k->kind == "bool" ? std::string("true or false") : "a" + std::string(k->kind == "integer" ? "n integer" : " number")) +
                             ", got '" + e.value.substr(0, 80) + "'");
        j[json::json_pointer(e.pointer)] = v;
    }
}

//! "gltf" or "procedural" (exactly one): the scene's geometry. Returns whether it is procedural.
bool read_geometry(const Ctx& ctx, const json& j, const LoadOptions& options, SceneDesc& d) {
    if (j.contains("gltf") == j.contains("procedural")) ctx.bad("gltf", "give exactly one of \"gltf\" and \"procedural\"");
    bool procedural = false;
    if (j.contains("procedural")) {
        const std::string name = ctx.string(j["procedural"], "procedural");
        try {
            d.scene = make_procedural(name);
        } catch (const Error& e) {
            ctx.bad("procedural", e.what());
        }
        procedural = true;
    } else {
        const std::string g = ctx.string(j["gltf"], "gltf");
        if (g.rfind(kProceduralPrefix, 0) == 0) {
            try {
                d.scene = make_procedural(g.substr(std::string(kProceduralPrefix).size()));
            } catch (const Error& e) {
                ctx.bad("gltf", e.what());
            }
            d.scene.decode_budget = render_decode_budget(options.texture_budget_bytes);
            procedural = true;
        } else {
            const std::string model = ctx.file(j["gltf"], "gltf");
            d.scene = options.load_model ? options.load_model(model, options) : load_gltf(model, nullptr, options);
        }
    }
    return procedural;
}

// Uniform scale of the whole model (instances and its glTF cameras), e.g. to bring a 20 cm
// scan into the scene-unit range the depth-based stages expect (MNPR: 8..50 units).
void read_scale(const Ctx& ctx, const json& j, Scene& scene) {
    if (!j.contains("scale")) return;
    const float k = float(ctx.number(j["scale"], "scale", 1e-6, 1e6));
    const glm::mat4 S = glm::scale(glm::mat4(1.0f), glm::vec3(k));
    for (Instance& inst : scene.instances) inst.world = S * inst.world;
    for (Camera& c : scene.cameras) {
        c.view[3] = glm::vec4(glm::vec3(c.view[3]) * k, 1.0f);
        c.znear *= k;
        c.zfar *= k;
        c.xmag *= k;
        c.ymag *= k;
    }
}

void read_style(const Ctx& ctx, const json& j, SceneDesc& d) {
    if (!j.contains("style")) return;
    const json& s = j["style"];
    if (s.is_string()) {
        d.style = s.get<std::string>();
        if (ends_with(lower(d.style), ".json")) d.style = ctx.file(s, "style");
    } else {
        ctx.check_keys(s, "style", {"preset", "set", "variant"});
        if (s.contains("preset")) {
            d.style = ctx.string(s["preset"], "style.preset");
            if (ends_with(lower(d.style), ".json")) d.style = ctx.file(s["preset"], "style.preset");
        }
        if (s.contains("set")) {
            if (!s["set"].is_object()) ctx.bad("style.set", "expected an object of \"stage.param\": number");
            for (auto it = s["set"].begin(); it != s["set"].end(); ++it) {
                if (it.key().find('.') == std::string::npos) ctx.bad("style.set." + it.key(), "expected \"stage.param\"");
                d.style_set[it.key()] = ctx.number(it.value(), "style.set." + it.key(), -1e9, 1e9);
            }
        }
        if (s.contains("variant")) {
            if (!s["variant"].is_object()) ctx.bad("style.variant", "expected an object of \"stage\": \"variant\"");
            for (auto it = s["variant"].begin(); it != s["variant"].end(); ++it)
                d.style_variant[it.key()] = ctx.string(it.value(), "style.variant." + it.key());
        }
    }
}

// Lights (procedural scenes bring their own unless the file names some), ambient.
void read_lights(const Ctx& ctx, const json& j, Scene& scene) {
    if (j.contains("lights")) {
        const json& l = j["lights"];
        if (!l.is_array()) ctx.bad("lights", "expected an array");
        scene.lights.clear();
        for (std::size_t i = 0; i < l.size(); ++i) {
            const std::string k = "lights[" + std::to_string(i) + "]";
            ctx.check_keys(l[i], k, {"direction", "color", "intensity"});
            Light li = default_light();
            if (l[i].contains("direction")) {
                const glm::vec3 dir = ctx.vec3(l[i]["direction"], k + ".direction");
                if (!(glm::length(dir) > 0.0f)) ctx.bad(k + ".direction", "must not be zero");
                li.direction = glm::normalize(dir);
            }
            if (l[i].contains("color")) li.color = ctx.vec3(l[i]["color"], k + ".color", 0.0, 1e3);
            if (l[i].contains("intensity")) li.intensity = float(ctx.number(l[i]["intensity"], k + ".intensity", 0.0, 1e3));
            scene.lights.push_back(li);
        }
    } else if (scene.lights.empty()) {
        scene.lights.push_back(default_light());
    }
    if (j.contains("ambient")) scene.ambient = ctx.vec3(j["ambient"], "ambient", 0.0, 1e3);
    if (j.contains("ambient")) scene.ambient = ctx.vec3(j["ambient"], "ambient", 0.0, 1e3);
}

// Per-material overrides.
void read_materials(const Ctx& ctx, const json& j, Scene& scene) {
    if (!j.contains("materials")) return;
    const json& m = j["materials"];
    if (!m.is_object()) ctx.bad("materials", "expected an object keyed by material name, index or \"*\"");
    std::map<std::string, int> intensity_of;  // one decode per file, however many keys name it
    for (auto it = m.begin(); it != m.end(); ++it) {
        const std::string k = "materials." + it.key();
        int intensity = -1;  // LD06 §4.3: one texture, shared by the matched materials
        if (it.value().is_object() && it.value().contains("intensity_texture")) {
            const std::string file = ctx.file(it.value()["intensity_texture"], k + ".intensity_texture");
            if (const auto seen = intensity_of.find(file); seen != intensity_of.end()) {
                intensity = seen->second;
            } else {
                Texture t = read_texture(file, &scene.decode_budget);
                finish_texture(t);
                scene.textures.push_back(std::move(t));
                intensity = intensity_of[file] = int(scene.textures.size()) - 1;
            }
        }
        for (int mi : match_materials(ctx, scene, it.key(), k)) {
            detail::apply_material_json(scene.materials[std::size_t(mi)], it.value(), ctx.where, k + ".",
                                        {"intensity_texture"});
            if (intensity >= 0) scene.materials[std::size_t(mi)].intensity_texture.texture = intensity;
        }
    }
}

// Control mapping.
void read_control(const Ctx& ctx, const json& j, SceneDesc& d) {
    ControlLayout layout = ControlLayout::WC18;
    if (j.contains("control_layout")) {
        const std::string s = ctx.string(j["control_layout"], "control_layout");
        if (s == "wc18") layout = ControlLayout::WC18;
        else if (s == "wc17") layout = ControlLayout::WC17;
        else ctx.bad("control_layout", "'" + s + "': expected \"wc18\" or \"wc17\"");
    }
    if (j.contains("control")) {
        d.control_rules = true;
        const json& c = j["control"];
        if (!c.is_array()) ctx.bad("control", "expected an array of rules");
        std::vector<ControlRule> rules;
        for (std::size_t i = 0; i < c.size(); ++i) {
            const std::string k = "control[" + std::to_string(i) + "]";
            rules.push_back(parse_rule(ctx, c[i], k, layout));
            for (const std::string& mname : rules.back().materials)
                match_materials(ctx, d.scene, mname, k + ".materials");
        }
        apply_control_rules(d.scene, rules, layout, ctx.where + " control");
    }
}

SceneDesc load_scene_file(const std::string& path, const LoadOptions& options) {
    Ctx ctx{{"scene file '" + path + "'"}, fs::path(path).parent_path()};
    json j = read_json_file(path, "scene file");
    if (!options.edits.empty()) apply_edits(j, options.edits, ctx);
    ctx.check_keys(j, "", {"description", "gltf", "procedural", "scale", "camera", "lights", "ambient", "control_layout", "control",
                           "materials", "style", "width", "height", "fps", "paper", "substrate_color", "foliage", "strokes", "layers"});
    if (j.contains("description")) ctx.string(j["description"], "description");

    SceneDesc d;
    // Output settings first: the automatic framing needs the aspect.
    if (j.contains("width")) d.width = ctx.integer(j["width"], "width", 1, kMaxImageSide);
    if (j.contains("height")) d.height = ctx.integer(j["height"], "height", 1, kMaxImageSide);
    if (j.contains("fps")) d.fps = float(ctx.number(j["fps"], "fps", 1e-3, 1000.0));
    if (j.contains("paper")) d.paper = ctx.file(j["paper"], "paper");
    if (!d.paper.empty() && options.paper_known) options.paper_known(d.paper);
    if (j.contains("substrate_color")) {
        d.substrate_color = ctx.vec3(j["substrate_color"], "substrate_color", 0.0, 1.0);
        d.substrate_color_set = true;
    }
    const float aspect = (d.width > 0 && d.height > 0) ? float(d.width) / float(d.height) : 16.0f / 9.0f;

    const bool procedural = read_geometry(ctx, j, options, d);
    read_scale(ctx, j, d.scene);
    read_style(ctx, j, d);
    read_lights(ctx, j, d.scene);
    read_materials(ctx, j, d.scene);
    // LD06 selections by name (scenes/scene_file_ld06.cpp), after the materials and before control.
    const SceneNames names(d.scene);
    read_foliage(ctx, j, names, d);
    read_layers(ctx, j, names, d);
    read_strokes(ctx, j, names, d);
    read_control(ctx, j, d);

    // Camera last: the framing sees the final geometry.
    if (j.contains("camera")) d.camera = parse_camera(ctx, j["camera"], d.scene, aspect, d);
    else if (procedural && !d.scene.cameras.empty()) d.camera = d.scene.cameras.front();
    else d.camera = parse_camera(ctx, json("auto"), d.scene, aspect, d);
    if (!procedural) d.scene.source = path;
    return d;
}

}  // namespace

SceneEdit parse_scene_edit(const std::string& text) {
    const std::size_t eq = text.find('=');
    if (text.empty() || text[0] != '/' || eq == std::string::npos || eq + 1 == text.size())
        throw Error("--scene-set expects /JSON/POINTER=VALUE, e.g. /layers/1/color=[0.3,0.5,0.2] or /foliage/T=60, got '" +
                    text.substr(0, 120) + "'");
    return {text.substr(0, eq), text.substr(eq + 1)};
}

std::vector<SceneKnob> scene_knobs(const std::string& path) { return knobs_of(read_json_file(path, "scene file")); }

SceneDesc load_scene(const std::string& spec, const LoadOptions& options) {
    SceneDesc d;
    const std::string no_edits = "scene '" + spec + "': --scene-set edits a scene file's art direction; a bare model or "
                                 "procedural scene has none (write a scene file naming it: docs/scenes.md)";
    if (spec.rfind(kProceduralPrefix, 0) == 0) {
        if (!options.edits.empty()) throw Error(no_edits);
        d.scene = make_procedural(spec.substr(std::string(kProceduralPrefix).size()));
        if (d.scene.lights.empty()) d.scene.lights.push_back(default_light());
        if (!d.scene.cameras.empty()) {
            d.camera = d.scene.cameras.front();
        } else {
            d.camera_auto = true;
            d.camera = frame_bounds(d.scene.world_bounds(), d.auto_aspect, d.auto_view_dir, d.auto_yfov);
        }
        return d;
    }
    std::error_code ec;
    if (!fs::exists(spec, ec)) throw Error("scene '" + spec + "': file not found");
    const std::string ext = lower(fs::path(spec).extension().string());
    if (ext == ".json") return load_scene_file(spec, options);
    if (!options.edits.empty()) throw Error(no_edits);
    if (ext == ".gltf" || ext == ".glb") {
        d.scene = load_gltf(spec, nullptr, options);
        d.scene.lights = {default_light()};
        d.camera_auto = true;
        d.camera = frame_bounds(d.scene.world_bounds(), d.auto_aspect, d.auto_view_dir, d.auto_yfov);
        return d;
    }
    throw Error("scene '" + spec + "': expected a .json scene file, a .gltf/.glb model or procedural:NAME");
}

}  // namespace aq::scene
