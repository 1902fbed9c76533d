// scenes/scene_file_reader.h — what the files of the scene-file reader share (scene_file.cpp:
// the file and its general sections; scene_file_ld06.cpp: foliage, layers, strokes;
// control_rules.cpp: the control mapping rules). Private to scenes/.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/json_file.h"
#include "scenes/scene_file.h"

namespace aq::scene::file {

using nlohmann::json;

//! Strict JSON access with key paths, and paths relative to the scene file.
struct Ctx : JsonReader {
    std::filesystem::path base;  //!< folder of the scene file

    //! Path relative to the scene file; must exist.
    std::string file(const json& j, const std::string& key) const {
        const std::string rel = string(j, key);
        if (rel.empty()) bad(key, "empty path");
        std::filesystem::path p(rel);
        if (p.is_relative()) p = base / p;
        p = p.lexically_normal();
        std::error_code ec;
        if (!std::filesystem::is_regular_file(p, ec)) bad(key, "file '" + p.string() + "' not found");
        return p.string();
    }
};

//! The scene's node, mesh and material names, sorted and unique: a selection's lookup is a binary
//! search (a file may name many thousands).
struct SceneNames {
    std::vector<std::string> nodes, meshes, materials;
    explicit SceneNames(const Scene& sc);
    //! Appends f[key] (an array of names, each in `have`) to out; absent key: nothing. An unknown
    //! name is an error listing the names there are.
    void read(const Ctx& ctx, const json& f, const std::string& where, const char* key, std::vector<std::string>& out,
              const std::vector<std::string>& have) const;
};

//! One control rule of a "control" section or default-control file at `key` (control_rules.cpp).
ControlRule parse_rule(const Ctx& ctx, const json& j, const std::string& key, ControlLayout layout);

//! The sections "foliage", "layers" and "strokes" (absent: nothing), in this order.
void read_foliage(const Ctx& ctx, const json& j, const SceneNames& names, SceneDesc& d);
void read_layers(const Ctx& ctx, const json& j, const SceneNames& names, SceneDesc& d);
void read_strokes(const Ctx& ctx, const json& j, const SceneNames& names, SceneDesc& d);

}  // namespace aq::scene::file
