// scenes/material_params.cpp — watercolor material parameters from JSON (see the header).
#include "scenes/material_params.h"

#include "core/json_file.h"

#include <algorithm>
#include <cmath>

namespace aq::scene::detail {

using nlohmann::json;

const char* control_target_name(int target) {
    return target >= 0 && target < control::kNumTargets ? control::kShortNames[target] : "?";
}

int parse_control_target(const std::string& s0) {
    std::string s = s0;
    if (s.rfind("ctrl.", 0) == 0) s = s.substr(5);
    for (int t = 0; t < kNumControlTargets; ++t)
        if (s == control_target_name(t)) return t;
    return -1;
}

std::string json_type_name(const json& j) { return j.type_name(); }



namespace {

struct Range {
    const char* key;
    float WatercolorMaterial::*field;
    float lo, hi;
};

// Ranges of the per-material reflectance parameters (WC17 eq. 3-5; MNPR defaults in scene.h).
const Range kRanges[] = {
    {"dilute", &WatercolorMaterial::dilute, 0.0f, 1.0f},
    {"cangiante", &WatercolorMaterial::cangiante, 0.0f, 1.0f},
    {"diffuse_factor", &WatercolorMaterial::diffuse_factor, 0.0f, 1.0f},
    {"dilute_area", &WatercolorMaterial::dilute_area, 0.01f, 1.0f},  // divides in eq. 3
    {"shade_wrap", &WatercolorMaterial::shade_wrap, 0.0f, 1.0f},
    {"specular", &WatercolorMaterial::specular, 0.0f, 1.0f},
    {"specular_power", &WatercolorMaterial::specular_power, 1.0f, 1024.0f},
};

struct Reporter {
    std::string where;
    std::string prefix;
    bool strict;
    std::vector<std::string>* warnings;
    // Returns normally only in lenient mode.
    void bad(const std::string& key, const std::string& what) const {
        std::string path = prefix + key;
        if (!path.empty() && path.back() == '.') path.pop_back();
        const JsonReader reader{where};
        if (strict) reader.bad(path, what);
        const std::string msg = reader.message(path, what);
        if (warnings) warnings->push_back(msg + " (ignored)");
    }
};

bool read_number(const json& v, const Reporter& r, const std::string& key, float lo, float hi,
                 float* out) {
    if (!v.is_number()) {
        r.bad(key, std::string("expected a number, got ") + v.type_name());
        return false;
    }
    const double d = v.get<double>();
    if (!std::isfinite(d) || d < lo || d > hi) {
        r.bad(key, "value " + std::to_string(d) + " outside [" + std::to_string(lo) + ", " +
                       std::to_string(hi) + "]");
        return false;
    }
    *out = float(d);
    return true;
}

bool read_vec(const json& v, const Reporter& r, const std::string& key, std::size_t nmin,
              std::size_t nmax, float lo, float hi, float* out) {
    if (!v.is_array() || v.size() < nmin || v.size() > nmax) {
        r.bad(key, "expected an array of " + std::to_string(nmin) +
                       (nmax != nmin ? ".." + std::to_string(nmax) : std::string()) + " numbers");
        return false;
    }
    float tmp[4];
    for (std::size_t i = 0; i < v.size(); ++i)
        if (!read_number(v[i], r, key + "[" + std::to_string(i) + "]", lo, hi, &tmp[i])) return false;
    std::copy(tmp, tmp + v.size(), out);
    return true;
}

}  // namespace

void apply_watercolor_json(WatercolorMaterial& wc, const json& j, const std::string& where,
                           const std::string& key_prefix, bool strict, std::vector<std::string>* warnings,
                           const std::vector<std::string>& extra_allowed_keys) {
    const Reporter r{where, key_prefix, strict, warnings};
    if (!j.is_object()) {
        r.bad("", std::string("expected an object, got ") + j.type_name());
        return;
    }
    for (auto it = j.begin(); it != j.end(); ++it) {
        const std::string& key = it.key();
        const json& v = it.value();
        if (std::find(extra_allowed_keys.begin(), extra_allowed_keys.end(), key) !=
            extra_allowed_keys.end())
            continue;
        bool known = false;
        for (const Range& rg : kRanges)
            if (key == rg.key) {
                known = true;
                read_number(v, r, key, rg.lo, rg.hi, &(wc.*rg.field));
            }
        if (known) continue;
        if (key == "shade_color") {
            float c[3];
            if (read_vec(v, r, key, 3, 3, 0.0f, 1.0f, c)) wc.shade_color = {c[0], c[1], c[2]};
        } else if (key == "control") {
            if (!v.is_object()) {
                r.bad(key, std::string("expected an object of control targets, got ") + v.type_name());
                continue;
            }
            for (auto ct = v.begin(); ct != v.end(); ++ct) {
                const int t = parse_control_target(ct.key());
                const std::string sub = key + "." + ct.key();
                if (t < 0) {
                    r.bad(sub, "unknown control target (pigment, substrate, edge, abstraction)");
                    continue;
                }
                float c[4] = {0, 0, 0, 0};
                if (read_vec(ct.value(), r, sub, 3, 4, -1.0f, 1.0f, c))
                    wc.control[t] = {c[0], c[1], c[2], c[3]};
            }
        } else if (strict) {
            r.bad(key, "unknown key");
        }
    }
}

void apply_material_json(Material& m, const json& j, const std::string& where,
                         const std::string& key_prefix, const std::vector<std::string>& extra_allowed_keys) {
    const Reporter r{where, key_prefix, true, nullptr};
    if (!j.is_object()) r.bad("", std::string("expected an object, got ") + j.type_name());
    std::vector<std::string> skip = extra_allowed_keys;
    for (const char* k : {"base_color", "double_sided", "alpha_mode", "alpha_cutoff"}) skip.push_back(k);
    apply_watercolor_json(m.wc, j, where, key_prefix, true, nullptr, skip);
    if (j.contains("base_color")) {
        float c[4] = {1, 1, 1, 1};
        if (read_vec(j["base_color"], r, "base_color", 3, 4, 0.0f, 1.0f, c))
            m.base_color = {c[0], c[1], c[2], j["base_color"].size() == 4 ? c[3] : 1.0f};
    }
    if (j.contains("double_sided")) {
        if (!j["double_sided"].is_boolean()) r.bad("double_sided", "expected a boolean");
        m.double_sided = j["double_sided"].get<bool>();
    }
    if (j.contains("alpha_mode")) {
        const json& v = j["alpha_mode"];
        const std::string s = v.is_string() ? v.get<std::string>() : std::string();
        if (s == "OPAQUE") m.alpha_mode = AlphaMode::Opaque;
        else if (s == "MASK") m.alpha_mode = AlphaMode::Mask;
        else if (s == "BLEND") m.alpha_mode = AlphaMode::Blend;
        else r.bad("alpha_mode", "expected \"OPAQUE\", \"MASK\" or \"BLEND\"");
    }
    if (j.contains("alpha_cutoff")) read_number(j["alpha_cutoff"], r, "alpha_cutoff", 0.0f, 1.0f, &m.alpha_cutoff);
}

}  // namespace aq::scene::detail
