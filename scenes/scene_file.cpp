// scenes/scene_file.cpp — JSON scene files (the LD06 sections in scene_file_ld06.cpp), control
// mapping rules and automatic framing.
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

constexpr std::size_t kVerticesPerTask = 4096;  //!< grain of the per-vertex control rules
namespace fs = std::filesystem;
using namespace file;  // Ctx, the LD06 sections (scenes/scene_file_reader.h)



std::string lower(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

bool ends_with(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// --- control targets ---------------------------------------------------------------------------

bool parse_wc18_target(const std::string& s, int* target, int* channel) {
    const auto dot = s.find('.');
    if (dot == std::string::npos) return false;
    const int t = detail::parse_control_target(s.substr(0, dot));
    if (t < 0) return false;
    const std::string c = s.substr(dot + 1);
    int ch = -1;
    if (c == "r") ch = 0;
    else if (c == "g") ch = 1;
    else if (c == "b") ch = 2;
    else
        for (int k = 0; k < 3; ++k)
            if (c == control::kChannelNames[t][k]) ch = k;
    if (ch < 0) return false;
    *target = t;
    *channel = ch;
    return true;
}

int parse_wc17_channel(const std::string& s) {
    if (s == "R" || s == "distortion") return 0;
    if (s == "G" || s == "granulation") return 1;
    if (s == "B" || s == "edge_bleeding") return 2;
    if (s == "A" || s == "turbulence") return 3;
    return -1;
}

int component_index(const std::string& c) {
    if (c == "r" || c == "x") return 0;
    if (c == "g" || c == "y") return 1;
    if (c == "b" || c == "z") return 2;
    if (c == "a" || c == "w") return 3;
    return -1;
}

bool rule_matches(const ControlRule& r, const Scene& s, int material) {
    if (r.materials.empty()) return true;
    for (const std::string& m : r.materials) {
        if (m == std::to_string(material)) return true;
        if (material >= 0 && material < int(s.materials.size()) && s.materials[std::size_t(material)].name == m) return true;
    }
    return false;
}

// Rule value at vertex i; returns false if the source attribute is absent.
const std::vector<glm::vec4>* find_attribute(const Primitive& p, const std::string& name,
                                             std::vector<glm::vec4>& scratch) {
    if (name == "COLOR_0") return p.colors.empty() ? nullptr : &p.colors;
    if (name == "TEXCOORD_0") {
        if (p.uv0.empty()) return nullptr;
        scratch.resize(p.uv0.size());
        for (std::size_t i = 0; i < p.uv0.size(); ++i) scratch[i] = glm::vec4(p.uv0[i], 0.0f, 0.0f);
        return &scratch;
    }
    if (name == "NORMAL") {
        scratch.resize(p.normals.size());
        for (std::size_t i = 0; i < p.normals.size(); ++i) scratch[i] = glm::vec4(p.normals[i], 0.0f);
        return &scratch;
    }
    if (name == "POSITION") {
        scratch.resize(p.positions.size());
        for (std::size_t i = 0; i < p.positions.size(); ++i) scratch[i] = glm::vec4(p.positions[i], 1.0f);
        return &scratch;
    }
    auto it = p.attributes.find(name);
    return it == p.attributes.end() ? nullptr : &it->second;
}

}  // namespace

void map_wc17_control(const glm::vec4& c0, std::array<glm::vec4, kNumControlTargets>& out) {
    const glm::vec4 c = glm::clamp(c0, glm::vec4(0.0f), glm::vec4(1.0f));
    out[kCtrlSubstrate].r = c.r;             // paper distortion
    out[kCtrlPigment].g = c.g;               // + granulation
    out[kCtrlEdge].r = c.b;                  // edge darkening ...
    out[kCtrlAbstraction].b = c.b;           // ... and bleeding share B (WC17 §3.1)
    out[kCtrlPigment].b = 1.0f - 2.0f * c.a; // A < 0.5 turbulence (accumulate), > 0.5 fading (dilute)
}

void apply_control_rules(Scene& scene, const std::vector<ControlRule>& rules, ControlLayout layout,
                         const std::string& where, const std::function<bool(const Primitive&)>& only) {
    // Texture rules: one Texture per (file, scale, bias); bound to the matching materials.
    std::map<std::tuple<std::string, float, float>, int> tex_cache;
    for (const ControlRule& r : rules) {
        if (r.source != ControlRule::Source::Texture) continue;
        if (layout != ControlLayout::WC18) throw Error(where + ": control textures need the wc18 control layout");
        if (r.target < 0 || r.target >= kNumControlTargets) throw Error(where + ": texture rule without a target");
        const auto key = std::make_tuple(r.file, r.scale, r.bias);
        int ti;
        if (auto it = tex_cache.find(key); it != tex_cache.end()) {
            ti = it->second;
        } else {
            // The rasterizer decodes a control texel t as 2t - 1 (raster/material.cpp); store the
            // mapped value v = file*scale + bias as (v + 1) / 2 so it decodes to exactly v.
            Texture t = read_texture(r.file, &scene.decode_budget, {TexelMap::Kind::Control, r.scale, r.bias});
            finish_texture(t);
            scene.textures.push_back(std::move(t));
            ti = int(scene.textures.size()) - 1;
            tex_cache[key] = ti;
        }
        for (std::size_t m = 0; m < scene.materials.size(); ++m)
            if (rule_matches(r, scene, int(m))) scene.materials[m].wc.control_texture[std::size_t(r.target)].texture = ti;
    }

    std::set<std::pair<std::size_t, std::size_t>> warned;  // (rule, mesh)
    std::vector<glm::vec4> scratch;
    for (std::size_t mi = 0; mi < scene.meshes.size(); ++mi) {
        // Object-space size of the mesh for bounds-relative noise: diagonal of its finite positions.
        float inv_diag = 1.0f;
        {
            glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
            bool any = false;
            for (const Primitive& p : scene.meshes[mi].primitives)
                for (const glm::vec3& v : p.positions)
                    if (std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z)) {
                        lo = glm::min(lo, v), hi = glm::max(hi, v), any = true;
                    }
            const float diag = any ? glm::length(hi - lo) : 0.0f;
            if (diag > 0.0f && std::isfinite(diag)) inv_diag = 1.0f / diag;
        }
        for (Primitive& p : scene.meshes[mi].primitives) {
            if (only && !only(p)) continue;
            const std::size_t n = p.positions.size();
            // Per-vertex values of the active rules, per destination channel.
            // Destination key: WC18 -> target*4 + channel; WC17 -> channel (0..3).
            std::map<int, std::vector<float>> sums;
            for (std::size_t ri = 0; ri < rules.size(); ++ri) {
                const ControlRule& r = rules[ri];
                if (r.source == ControlRule::Source::Texture || !rule_matches(r, scene, p.material)) continue;
                const int dest = layout == ControlLayout::WC18 ? r.target * 4 + r.channel : r.channel;
                if (layout == ControlLayout::WC18 && (r.target < 0 || r.target >= kNumControlTargets || r.channel < 0 || r.channel > 2))
                    throw Error(where + ": rule " + std::to_string(ri) + " has no valid WC18 destination");
                if (layout == ControlLayout::WC17 && (r.channel < 0 || r.channel > 3))
                    throw Error(where + ": rule " + std::to_string(ri) + " has no valid WC17 channel");
                const std::vector<glm::vec4>* attr = nullptr;
                if (r.source == ControlRule::Source::Attribute) {
                    attr = find_attribute(p, r.attribute, scratch);
                    if (!attr || attr->size() != n) {
                        if (warned.insert({ri, mi}).second)
                            scene.warnings.push_back(where + ": rule " + std::to_string(ri) + ": mesh '" + scene.meshes[mi].name +
                                                     "' has no " + r.attribute + "; the rule adds nothing there");
                        continue;
                    }
                }
                std::vector<float>& acc = sums[dest];
                acc.resize(n, 0.0f);
                // Each vertex on its own (rules stay in order per vertex): the same bytes for any
                // thread count. Parallel because noise rules on large meshes cost ~170 ms on one
                // core for 871k triangles (docs/performance.md, one-shot profile).
                // Noise is evaluated eight vertices at a time (noise_field_n), a chunk per task.
                const float noise_scale = r.noise.bounds_relative ? inv_diag : 1.0f;
                oneapi::tbb::parallel_for(oneapi::tbb::blocked_range<std::size_t>(0, n, kVerticesPerTask),
                                          [&](const oneapi::tbb::blocked_range<std::size_t>& range) {
                    constexpr std::size_t kChunk = 256;  // noise values on the stack (1 KiB)
                    std::array<float, kChunk> noise;
                    for (std::size_t c0 = range.begin(); c0 < range.end(); c0 += kChunk) {
                        const std::size_t c1 = std::min(range.end(), c0 + kChunk);
                        if (r.source == ControlRule::Source::Noise)
                            noise_field_n(r.noise, p.positions.data() + c0, c1 - c0, noise_scale, noise.data());
                        for (std::size_t i = c0; i < c1; ++i) {
                            float v = 0.0f;
                            switch (r.source) {
                                case ControlRule::Source::Attribute: v = (*attr)[i][r.component] * r.scale + r.bias; break;
                                case ControlRule::Source::Noise: v = noise[i - c0] * r.scale + r.bias; break;
                                case ControlRule::Source::Constant: v = r.value * r.scale + r.bias; break;
                                case ControlRule::Source::Texture: break;
                            }
                            acc[i] += std::isfinite(v) ? v : 0.0f;
                        }
                    }
                });
            }
            if (sums.empty()) continue;
            auto ensure = [&](int t) {
                if (p.control[std::size_t(t)].size() != n) p.control[std::size_t(t)].assign(n, glm::vec4(0.0f));
            };
            if (layout == ControlLayout::WC18) {
                for (auto& [dest, acc] : sums) {
                    const int t = dest / 4, c = dest % 4;
                    ensure(t);
                    for (std::size_t i = 0; i < n; ++i) p.control[std::size_t(t)][i][c] = std::clamp(acc[i], -1.0f, 1.0f);
                }
            } else {
                for (int t = 0; t < kNumControlTargets; ++t) ensure(t);
                for (std::size_t i = 0; i < n; ++i) {
                    glm::vec4 c(0.0f, 0.0f, 0.0f, 0.5f);  // WC17 neutral
                    for (auto& [dest, acc] : sums) c[dest] = acc[i];
                    std::array<glm::vec4, kNumControlTargets> w{};
                    for (int t = 0; t < kNumControlTargets; ++t) w[std::size_t(t)] = p.control[std::size_t(t)][i];
                    map_wc17_control(c, w);
                    for (int t = 0; t < kNumControlTargets; ++t) p.control[std::size_t(t)][i] = w[std::size_t(t)];
                }
            }
        }
    }
}

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

ControlRule parse_rule(const Ctx& ctx, const json& j, const std::string& key, ControlLayout layout) {
    ctx.check_keys(j, key, {"target", "source", "scale", "bias", "value", "noise", "file", "materials", "comment"});
    ControlRule r;
    if (!j.contains("source")) ctx.bad(key + ".source", "missing");
    if (!j.contains("target")) ctx.bad(key + ".target", "missing");
    const std::string src = ctx.string(j["source"], key + ".source");
    if (src == "noise") r.source = ControlRule::Source::Noise;
    else if (src == "texture") r.source = ControlRule::Source::Texture;
    else if (src == "constant") r.source = ControlRule::Source::Constant;
    else {
        const auto dot = src.rfind('.');
        const int comp = dot == std::string::npos ? -1 : component_index(src.substr(dot + 1));
        const std::string attr = dot == std::string::npos ? "" : src.substr(0, dot);
        const bool known_attr = attr.rfind("COLOR_", 0) == 0 || attr.rfind("TEXCOORD_", 0) == 0 ||
                                attr.rfind("_", 0) == 0 || attr == "NORMAL" || attr == "POSITION";
        if (comp < 0 || !known_attr)
            ctx.bad(key + ".source", "'" + src + "' is not noise, texture, constant or ATTRIBUTE.channel (e.g. COLOR_0.r, TEXCOORD_1.x)");
        r.source = ControlRule::Source::Attribute;
        r.attribute = attr;
        r.component = comp;
    }
    const std::string tgt = ctx.string(j["target"], key + ".target");
    if (r.source == ControlRule::Source::Texture) {
        if (layout != ControlLayout::WC18) ctx.bad(key + ".source", "control textures need the wc18 control_layout");
        r.target = detail::parse_control_target(tgt);
        r.channel = -1;
        if (r.target < 0) ctx.bad(key + ".target", "'" + tgt + "': a texture rule targets a whole target (pigment, substrate, edge, abstraction)");
        r.scale = 2.0f;
        r.bias = -1.0f;
        if (!j.contains("file")) ctx.bad(key + ".file", "missing (texture rules need a file)");
        r.file = ctx.file(j["file"], key + ".file");
    } else if (layout == ControlLayout::WC18) {
        if (!parse_wc18_target(tgt, &r.target, &r.channel))
            ctx.bad(key + ".target", "'" + tgt + "' is not TARGET.CHANNEL (pigment|substrate|edge|abstraction . r|g|b or the channel names of docs/scenes.md)");
        if (j.contains("file")) ctx.bad(key + ".file", "only texture rules take a file");
    } else {
        r.channel = parse_wc17_channel(tgt);
        if (r.channel < 0) ctx.bad(key + ".target", "'" + tgt + "' is not a WC17 channel (R, G, B, A or distortion, granulation, edge_bleeding, turbulence)");
        if (j.contains("file")) ctx.bad(key + ".file", "only texture rules take a file");
    }
    if (j.contains("scale")) r.scale = float(ctx.number(j["scale"], key + ".scale", -1e6, 1e6));
    if (j.contains("bias")) r.bias = float(ctx.number(j["bias"], key + ".bias", -1e6, 1e6));
    if (j.contains("value")) {
        if (r.source != ControlRule::Source::Constant) ctx.bad(key + ".value", "only constant rules take a value");
        r.value = float(ctx.number(j["value"], key + ".value", -1e6, 1e6));
    } else if (r.source == ControlRule::Source::Constant) {
        ctx.bad(key + ".value", "missing (constant rules need a value)");
    }
    if (j.contains("noise")) {
        if (r.source != ControlRule::Source::Noise) ctx.bad(key + ".noise", "only noise rules take noise parameters");
        const json& n = j["noise"];
        const std::string nk = key + ".noise";
        ctx.check_keys(n, nk, {"frequency", "amplitude", "offset", "seed", "octaves", "space"});
        if (n.contains("space")) {
            const std::string sp = ctx.string(n["space"], nk + ".space");
            if (sp == "bounds") r.noise.bounds_relative = true;
            else if (sp != "object") ctx.bad(nk + ".space", "'" + sp + "': expected \"object\" or \"bounds\"");
        }
        if (n.contains("frequency")) r.noise.frequency = float(ctx.number(n["frequency"], nk + ".frequency", 1e-6, 1e6));
        if (n.contains("amplitude")) r.noise.amplitude = float(ctx.number(n["amplitude"], nk + ".amplitude", -1e6, 1e6));
        if (n.contains("offset")) r.noise.offset = float(ctx.number(n["offset"], nk + ".offset", -1e6, 1e6));
        if (n.contains("seed")) r.noise.seed = std::uint32_t(ctx.integer(n["seed"], nk + ".seed", 0, 2147483647));
        if (n.contains("octaves")) r.noise.octaves = ctx.integer(n["octaves"], nk + ".octaves", 1, 8);
    }
    if (j.contains("materials")) {
        const json& m = j["materials"];
        if (!m.is_array()) ctx.bad(key + ".materials", "expected an array of material names or indices");
        for (std::size_t i = 0; i < m.size(); ++i) {
            const std::string mk = key + ".materials[" + std::to_string(i) + "]";
            if (m[i].is_string()) r.materials.push_back(m[i].get<std::string>());
            else r.materials.push_back(std::to_string(ctx.integer(m[i], mk, 0, 1 << 30)));
        }
    }
    return r;
}

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

std::vector<ControlRule> parse_control_rules(const std::string& text, const std::string& where, ControlLayout layout) {
    json j;
    try {
        j = json::parse(text);
    } catch (const json::exception& e) {
        throw Error(where + ": malformed JSON (" + e.what() + ")");
    }
    Ctx ctx{{where}, fs::path()};
    if (!j.is_array()) ctx.bad("", "expected an array of control rules");
    std::vector<ControlRule> rules;
    for (std::size_t i = 0; i < j.size(); ++i) {
        const std::string k = "[" + std::to_string(i) + "]";
        if (j[i].is_object() && j[i].contains("source") && j[i]["source"].is_string()) {
            const std::string src = j[i]["source"].get<std::string>();
            if (src != "noise" && src != "constant")
                ctx.bad(k + ".source", "'" + src + "': default control takes noise and constant rules only");
        }
        if (j[i].is_object() && j[i].contains("materials")) ctx.bad(k + ".materials", "not allowed in default control");
        rules.push_back(parse_rule(ctx, j[i], k, layout));
    }
    return rules;
}

bool has_painted_control(const Scene& scene, const Primitive& p) {
    for (const auto& c : p.control)
        if (!c.empty()) return true;
    if (p.material >= 0 && std::size_t(p.material) < scene.materials.size()) {
        const WatercolorMaterial& wc = scene.materials[std::size_t(p.material)].wc;
        for (int k = 0; k < kNumControlTargets; ++k) {
            const glm::vec4& c = wc.control[std::size_t(k)];
            if (c.x != 0.0f || c.y != 0.0f || c.z != 0.0f) return true;
            if (wc.control_texture[std::size_t(k)].texture >= 0) return true;
        }
    }
    return false;
}

std::size_t apply_default_control(Scene& scene, const std::vector<ControlRule>& rules, const std::string& where) {
    if (rules.empty()) return 0;
    std::vector<const Primitive*> todo;
    for (const Mesh& m : scene.meshes)
        for (const Primitive& p : m.primitives)
            if (!has_painted_control(scene, p)) todo.push_back(&p);
    if (todo.empty()) return 0;
    auto selected = [&](const Primitive& p) { return std::find(todo.begin(), todo.end(), &p) != todo.end(); };
    apply_control_rules(scene, rules, ControlLayout::WC18, where, selected);
    return todo.size();
}

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
