// tests/scenes/gltf_builder.h — writes small glTF / GLB files for loader tests (valid ones with
// chosen component types, and hostile ones with broken ranges, strides, counts, hierarchies).
#pragma once

#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace aq::test {

inline std::string base64(const std::vector<unsigned char>& in) {
    static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    std::size_t i = 0;
    for (; i + 2 < in.size(); i += 3) {
        const std::uint32_t v = std::uint32_t(in[i]) << 16 | std::uint32_t(in[i + 1]) << 8 | in[i + 2];
        out += k[v >> 18 & 63];
        out += k[v >> 12 & 63];
        out += k[v >> 6 & 63];
        out += k[v & 63];
    }
    if (i + 1 == in.size()) {
        const std::uint32_t v = std::uint32_t(in[i]) << 16;
        out += k[v >> 18 & 63];
        out += k[v >> 12 & 63];
        out += "==";
    } else if (i + 2 == in.size()) {
        const std::uint32_t v = std::uint32_t(in[i]) << 16 | std::uint32_t(in[i + 1]) << 8;
        out += k[v >> 18 & 63];
        out += k[v >> 12 & 63];
        out += k[v >> 6 & 63];
        out += '=';
    }
    return out;
}

inline void write_bytes(const std::string& path, const std::vector<unsigned char>& b) {
    std::ofstream f(path, std::ios::binary);
    f.write(reinterpret_cast<const char*>(b.data()), std::streamsize(b.size()));
}

inline std::vector<unsigned char> read_bytes(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return std::vector<unsigned char>((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

//! Builds one buffer and the JSON around it. Mesh/node/scene JSON is edited directly via `j`.
struct GltfBuilder {
    nlohmann::json j = {{"asset", {{"version", "2.0"}}}, {"buffers", nlohmann::json::array()},
                        {"bufferViews", nlohmann::json::array()}, {"accessors", nlohmann::json::array()}};
    std::vector<unsigned char> bin;

    int add_view(const void* data, std::size_t bytes, int stride = 0) {
        while (bin.size() % 4) bin.push_back(0);
        const std::size_t off = bin.size();
        const auto* p = static_cast<const unsigned char*>(data);
        bin.insert(bin.end(), p, p + bytes);
        nlohmann::json v = {{"buffer", 0}, {"byteOffset", off}, {"byteLength", bytes}};
        if (stride) v["byteStride"] = stride;
        j["bufferViews"].push_back(v);
        return int(j["bufferViews"].size()) - 1;
    }
    int add_accessor(int view, int component_type, std::size_t count, const std::string& type, bool normalized = false,
                     std::size_t byte_offset = 0) {
        nlohmann::json a = {{"componentType", component_type}, {"count", count}, {"type", type}};
        if (view >= 0) a["bufferView"] = view;
        if (byte_offset) a["byteOffset"] = byte_offset;
        if (normalized) a["normalized"] = true;
        j["accessors"].push_back(a);
        return int(j["accessors"].size()) - 1;
    }
    template <class T>
    int add(const std::vector<T>& data, int component_type, const std::string& type, std::size_t count,
            bool normalized = false) {
        const int v = add_view(data.data(), data.size() * sizeof(T));
        return add_accessor(v, component_type, count, type, normalized);
    }
    //! One mesh with one primitive, one node, one scene.
    void single_primitive(const nlohmann::json& primitive) {
        j["meshes"] = nlohmann::json::array({{{"primitives", nlohmann::json::array({primitive})}}});
        j["nodes"] = nlohmann::json::array({{{"mesh", 0}}});
        j["scenes"] = nlohmann::json::array({{{"nodes", {0}}}});
        j["scene"] = 0;
    }
    void finish_buffer() {
        while (bin.size() % 4) bin.push_back(0);
        j["buffers"] = nlohmann::json::array({{{"byteLength", bin.size()}}});
    }
    //! .gltf with the buffer as a base64 data URI.
    std::string write_gltf(const std::string& path) {
        finish_buffer();
        j["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(bin);
        std::ofstream(path) << j.dump();
        return path;
    }
    std::vector<unsigned char> glb_bytes() {
        finish_buffer();
        std::string js = j.dump();
        while (js.size() % 4) js += ' ';
        std::vector<unsigned char> out;
        auto u32 = [&](std::uint32_t v) {
            for (int i = 0; i < 4; ++i) out.push_back(static_cast<unsigned char>(v >> (8 * i)));
        };
        const std::uint32_t total = std::uint32_t(12 + 8 + js.size() + 8 + bin.size());
        out.reserve(total);  // also keeps GCC 12's -Wstringop-overflow false positive on the empty vector away
        for (const char c : {'g', 'l', 'T', 'F'}) out.push_back(static_cast<unsigned char>(c));
        u32(2);
        u32(total);
        u32(std::uint32_t(js.size()));
        u32(0x4E4F534Au);
        out.insert(out.end(), js.begin(), js.end());
        u32(std::uint32_t(bin.size()));
        u32(0x004E4942u);
        out.insert(out.end(), bin.begin(), bin.end());
        return out;
    }
    std::string write_glb(const std::string& path) {
        write_bytes(path, glb_bytes());
        return path;
    }
};

constexpr int kFloat = 5126, kUByte = 5121, kUShort = 5123, kUInt = 5125;

//! A unit quad in the XY plane (4 vertices, 2 CCW triangles) as float positions.
inline std::vector<float> quad_positions() { return {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}; }
inline std::vector<std::uint16_t> quad_indices() { return {0, 1, 2, 0, 2, 3}; }

}  // namespace aq::test
