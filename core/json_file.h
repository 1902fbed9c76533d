// core/json_file.h — the one JSON reading helper: bounded file read (core/input.h), a nesting-depth
// check before the recursive parser runs, and parse errors that name the file and the key.
#pragma once

#include <cstddef>
#include <string>

#include <nlohmann/json.hpp>

namespace aq {

inline constexpr int kMaxJsonDepth = 256;  //!< nesting levels; deeper input is refused before parsing

//! Throws aq::Error("WHERE: JSON nested deeper than ...") when brackets nest beyond kMaxJsonDepth
//! (strings and escapes are skipped). Linear, no allocation: runs before the recursive parser.
void check_json_depth(const unsigned char* p, std::size_t n, const std::string& where);

//! Parses text as JSON. Errors become aq::Error "WHERE: invalid JSON at key 'a.b[2]': ..." (the
//! key being read when the parser stopped: a number out of range such as 1e400, a syntax error).
nlohmann::json parse_json(const std::string& text, const std::string& where);

//! read_input_text(path, kMaxJsonFileBytes, what) + parse_json; `what` names the kind of file
//! ("scene file", "style file").
nlohmann::json read_json_file(const std::string& path, const std::string& what);

}  // namespace aq
