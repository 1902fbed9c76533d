// core/json_file.cpp
#include "core/json_file.h"

#include <cstdio>

#include <cmath>
#include <vector>

#include "core/image.h"  // aq::Error
#include "core/input.h"

namespace aq {
using json = nlohmann::json;

void check_json_depth(const unsigned char* p, std::size_t n, const std::string& where) {
    int depth = 0;
    bool in_string = false;
    for (std::size_t i = 0; i < n; ++i) {
        const unsigned char c = p[i];
        if (in_string) {
            if (c == '\\') ++i;
            else if (c == '"') in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > kMaxJsonDepth)
                throw Error(where + ": JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
}

json parse_json(const std::string& text, const std::string& where) {
    check_json_depth(reinterpret_cast<const unsigned char*>(text.data()), text.size(), where);
    // The parser callback keeps the path of keys and array positions being read, so an error
    // (a number such as 1e400 that overflows a double, a syntax error) can name its key.
    struct Level {
        bool array = false;
        std::size_t index = 0;
        std::string key;
    };
    std::vector<Level> stack;
    auto cb = [&](int, json::parse_event_t ev, json& parsed) {
        switch (ev) {
            case json::parse_event_t::object_start: stack.push_back({false, 0, {}}); break;
            case json::parse_event_t::array_start: stack.push_back({true, 0, {}}); break;
            case json::parse_event_t::key:
                if (!stack.empty()) stack.back().key = parsed.is_string() ? parsed.get<std::string>() : "";
                break;
            case json::parse_event_t::object_end:
            case json::parse_event_t::array_end:
                if (!stack.empty()) stack.pop_back();
                if (!stack.empty() && stack.back().array) ++stack.back().index;
                break;
            case json::parse_event_t::value:
                if (!stack.empty() && stack.back().array) ++stack.back().index;
                break;
        }
        return true;
    };
    try {
        return json::parse(text, cb, true, false);
    } catch (const json::exception& e) {
        std::string path;
        for (const Level& l : stack) {
            if (l.array) path += "[" + std::to_string(l.index) + "]";
            else if (!l.key.empty()) path += (path.empty() ? "" : ".") + l.key;
        }
        std::string msg = e.what();
        if (const auto p = msg.find("] "); msg.rfind("[json.exception.", 0) == 0 && p != std::string::npos)
            msg = msg.substr(p + 2);
        throw Error(where + ": invalid JSON" + (path.empty() ? std::string() : " at key '" + path + "'") + ": " + msg);
    }
}

std::string exact_number_text(double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.17g", v);
    return b;
}

json read_json_file(const std::string& path, const std::string& what) {
    return parse_json(read_input_text(path, kMaxJsonFileBytes, what), what + " '" + path + "'");
}

std::string JsonReader::message(const std::string& key, const std::string& what) const {
    return where + ": key '" + key + "': " + what;
}

void JsonReader::bad(const std::string& key, const std::string& what) const { throw Error(message(key, what)); }

void JsonReader::check_keys(const json& j, const std::string& key, std::initializer_list<const char*> allowed) const {
    if (!j.is_object()) bad(key, std::string("expected an object, got ") + j.type_name());
    for (auto it = j.begin(); it != j.end(); ++it) {
        bool ok = false;
        for (const char* a : allowed) ok = ok || it.key() == a;
        if (!ok) {
            std::string list;
            for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
            bad(key.empty() ? it.key() : key + "." + it.key(), "unknown key (allowed: " + list + ")");
        }
    }
}

double JsonReader::number(const json& j, const std::string& key, double lo, double hi) const {
    if (!j.is_number()) bad(key, std::string("expected a number, got ") + j.type_name());
    const double d = j.get<double>();
    if (!std::isfinite(d) || d < lo || d > hi)
        bad(key, "value " + std::to_string(d) + " outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return d;
}

double JsonReader::number_or_flag(const json& j, const std::string& key) const {
    if (j.is_boolean()) return j.get<bool>() ? 1.0 : 0.0;
    if (!j.is_number()) bad(key, std::string("expected a number or true/false, got ") + j.type_name());
    const double d = j.get<double>();
    if (!std::isfinite(d)) bad(key, "not a finite number");
    return d;
}

int JsonReader::integer(const json& j, const std::string& key, long long lo, long long hi) const {
    if (!j.is_number_integer()) bad(key, std::string("expected an integer, got ") + j.type_name());
    // An unsigned value above LLONG_MAX would wrap to a negative one in get<long long>().
    if (j.is_number_unsigned() && (hi < 0 || j.get<unsigned long long>() > static_cast<unsigned long long>(hi)))
        bad(key, "value " + j.dump() + " outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    const long long v = j.get<long long>();
    if (v < lo || v > hi) bad(key, "value " + std::to_string(v) + " outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return int(v);
}

std::string JsonReader::string(const json& j, const std::string& key) const {
    if (!j.is_string()) bad(key, std::string("expected a string, got ") + j.type_name());
    return j.get<std::string>();
}

bool JsonReader::boolean(const json& j, const std::string& key) const {
    if (!j.is_boolean()) bad(key, std::string("expected a boolean, got ") + j.type_name());
    return j.get<bool>();
}

glm::vec3 JsonReader::vec3(const json& j, const std::string& key, double lo, double hi) const {
    if (!j.is_array() || j.size() != 3) bad(key, "expected an array of 3 numbers");
    return {float(number(j[0], key + "[0]", lo, hi)), float(number(j[1], key + "[1]", lo, hi)),
            float(number(j[2], key + "[2]", lo, hi))};
}

}  // namespace aq
