// scenes/control_rules.cpp — control mapping rules (docs/scenes.md "Control"): parsed from a scene
// file's "control" section (parse_rule, for scene_file.cpp) or a default-control file, and applied
// to the scene's materials and vertices.
#include "scenes/scene_file.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <string>

#include <nlohmann/json.hpp>
#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include "core/json_file.h"
#include "scenes/material_params.h"
#include "scenes/noise.h"
#include "scenes/scene_file_reader.h"

namespace aq::scene {
namespace {

constexpr std::size_t kVerticesPerTask = 4096;  //!< grain of the per-vertex control rules
namespace fs = std::filesystem;
using namespace file;  // Ctx (scenes/scene_file_reader.h)

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

namespace file {

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

}  // namespace file

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

}  // namespace aq::scene
