// core/json_file.h — the one JSON reading helper: bounded file read (core/input.h), a nesting-depth
// check before the recursive parser runs, and parse errors that name the file and the key.
#pragma once

#include <cstddef>
#include <initializer_list>
#include <string>

#include <glm/glm.hpp>

#include <nlohmann/json.hpp>

namespace aq {

inline constexpr int kMaxJsonDepth = 256;  //!< nesting levels; deeper input is refused before parsing

//! Throws aq::Error("WHERE: JSON nested deeper than ...") when brackets nest beyond kMaxJsonDepth
//! (strings and escapes are skipped). Linear, no allocation: runs before the recursive parser.
void check_json_depth(const unsigned char* p, std::size_t n, const std::string& where);

//! The shortest-to-write exact text of a double ("%.17g"): what a JSON or command-line reader
//! reads back as the same double (the live page's and the Python module's render arguments).
std::string exact_number_text(double v);

//! Parses text as JSON. Errors become aq::Error "WHERE: invalid JSON at key 'a.b[2]': ..." (the
//! key being read when the parser stopped: a number out of range such as 1e400, a syntax error).
nlohmann::json parse_json(const std::string& text, const std::string& where);

//! read_input_text(path, kMaxJsonFileBytes, what) + parse_json; `what` names the kind of file
//! ("scene file", "style file").
nlohmann::json read_json_file(const std::string& path, const std::string& what);

//! Strict typed access to parsed JSON with key paths in every error (scene files, style/pipeline
//! files): each accessor checks the type (and range) and throws aq::Error
//! "WHERE: key 'a.b[2]': what" otherwise. The one reader of the project's JSON formats; glTF
//! `extras` use a lenient form of the same messages (scenes/material_params.cpp: warnings instead
//! of errors, because third-party models must still load).
struct JsonReader {
    std::string where;  //!< e.g. "scene file 'x.json'" or a style file's path

    //! "WHERE: key 'KEY': WHAT", the form of every error (and lenient warning) about a JSON value.
    std::string message(const std::string& key, const std::string& what) const;
    [[noreturn]] void bad(const std::string& key, const std::string& what) const;
    //! j must be an object whose keys are all in `allowed`.
    void check_keys(const nlohmann::json& j, const std::string& key, std::initializer_list<const char*> allowed) const;
    //! A finite number in [lo, hi].
    double number(const nlohmann::json& j, const std::string& key, double lo, double hi) const;
    //! A number or true/false (as 1/0), finite, unranged (the caller checks its own range).
    double number_or_flag(const nlohmann::json& j, const std::string& key) const;
    int integer(const nlohmann::json& j, const std::string& key, long long lo, long long hi) const;
    std::string string(const nlohmann::json& j, const std::string& key) const;
    bool boolean(const nlohmann::json& j, const std::string& key) const;
    //! An array of 3 numbers, each in [lo, hi].
    glm::vec3 vec3(const nlohmann::json& j, const std::string& key, double lo = -1e9, double hi = 1e9) const;
};

}  // namespace aq
