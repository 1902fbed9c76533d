// core/json_file.cpp
#include "core/json_file.h"

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

json read_json_file(const std::string& path, const std::string& what) {
    return parse_json(read_input_text(path, kMaxJsonFileBytes, what), what + " '" + path + "'");
}

}  // namespace aq
