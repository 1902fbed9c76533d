// scenes/material_params.h — watercolor material parameters from JSON (glTF material `extras`
// and scene-file material overrides). Internal to aq_scenes: it exposes nlohmann::json.
//
// Keys (docs/scenes.md "Material parameters"): dilute, cangiante, diffuse_factor, dilute_area,
// shade_wrap, shade_color [r,g,b], specular, specular_power, control {pigment|substrate|edge|
// abstraction: [r,g,b(,a)]}; and, in scene files, base_color [r,g,b,a], double_sided, alpha_mode,
// alpha_cutoff.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "scenes/scene.h"

namespace aq::scene::detail {

//! Name of a control target as used in JSON: "pigment", "substrate", "edge", "abstraction".
const char* control_target_name(int target);
//! Parses "pigment" ... "abstraction" (or "ctrl.pigment"...); -1 if unknown.
int parse_control_target(const std::string& s);

//! Applies the WatercolorMaterial keys of `j` onto `wc`. Messages read
//! "<where>: key '<key_prefix><key>': <problem>".
//! strict (scene files): an unknown key, a wrong type or an out-of-range value throws aq::Error.
//! Lenient (glTF extras, which other tools also use): unknown keys are ignored, bad values are
//! skipped with a warning.
void apply_watercolor_json(WatercolorMaterial& wc, const nlohmann::json& j, const std::string& where,
                           const std::string& key_prefix, bool strict, std::vector<std::string>* warnings,
                           const std::vector<std::string>& extra_allowed_keys = {});

//! Applies base_color, double_sided, alpha_mode, alpha_cutoff and every watercolor key (strict).
//! Keys listed in extra_allowed_keys are skipped (the caller handles them).
void apply_material_json(Material& m, const nlohmann::json& j, const std::string& where,
                         const std::string& key_prefix,
                         const std::vector<std::string>& extra_allowed_keys = {});


//! JSON type name for messages.
std::string json_type_name(const nlohmann::json& j);

}  // namespace aq::scene::detail
