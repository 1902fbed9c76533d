// scenes/gltf_reader.h — what the files of the glTF reader share (gltf_loader.cpp: the file, its
// container and the node tree; gltf_meshes.cpp: buffer views, accessors and primitives;
// gltf_materials.cpp: materials and textures). Private to scenes/.
#pragma once

#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <tiny_gltf.h>

#include "core/io.h"
#include "scenes/gltf_loader.h"

namespace aq::scene::gltf {

inline int component_size(int ct) {
    switch (ct) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
        default: return 0;
    }
}

inline int num_components(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR: return 1;
        case TINYGLTF_TYPE_VEC2: return 2;
        case TINYGLTF_TYPE_VEC3: return 3;
        case TINYGLTF_TYPE_VEC4: return 4;
        case TINYGLTF_TYPE_MAT2: return 4;
        case TINYGLTF_TYPE_MAT3: return 9;
        case TINYGLTF_TYPE_MAT4: return 16;
        default: return 0;
    }
}

inline const char* type_name(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR: return "SCALAR";
        case TINYGLTF_TYPE_VEC2: return "VEC2";
        case TINYGLTF_TYPE_VEC3: return "VEC3";
        case TINYGLTF_TYPE_VEC4: return "VEC4";
        default: return "MAT";
    }
}

//! A validated accessor: every element i lies in [base + i*stride, base + i*stride + elem).
struct AccessorView {
    const unsigned char* base = nullptr;  //!< nullptr: no bufferView, all zeros (glTF rule)
    std::size_t count = 0, stride = 0;
    int comp_type = 0, ncomp = 0;
    bool normalized = false;

    float component(std::size_t i, int c) const {
        if (!base) return 0.0f;
        const unsigned char* p = base + i * stride + std::size_t(c) * component_size(comp_type);
        switch (comp_type) {
            case TINYGLTF_COMPONENT_TYPE_FLOAT: {
                float f;
                std::memcpy(&f, p, 4);
                return f;
            }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
                const float v = float(p[0]);
                return normalized ? v / 255.0f : v;
            }
            case TINYGLTF_COMPONENT_TYPE_BYTE: {
                const float v = float(std::int8_t(p[0]));
                return normalized ? std::max(v / 127.0f, -1.0f) : v;
            }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                std::uint16_t u;
                std::memcpy(&u, p, 2);
                return normalized ? float(u) / 65535.0f : float(u);
            }
            case TINYGLTF_COMPONENT_TYPE_SHORT: {
                std::int16_t s;
                std::memcpy(&s, p, 2);
                return normalized ? std::max(float(s) / 32767.0f, -1.0f) : float(s);
            }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
                std::uint32_t u;
                std::memcpy(&u, p, 4);
                return float(u);
            }
            default: return 0.0f;
        }
    }
    std::uint32_t index(std::size_t i) const {
        if (!base) return 0;
        const unsigned char* p = base + i * stride;
        switch (comp_type) {
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return p[0];
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                std::uint16_t u;
                std::memcpy(&u, p, 2);
                return u;
            }
            default: {
                std::uint32_t u;
                std::memcpy(&u, p, 4);
                return u;
            }
        }
    }
};

inline glm::mat4 checked_mat4(const std::vector<double>& m) {
    glm::mat4 r;
    for (int i = 0; i < 16; ++i) glm::value_ptr(r)[i] = float(m[std::size_t(i)]);
    return r;
}

inline bool finite(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

class Loader {
public:
    Loader(const std::string& path, const tinygltf::Model& m, std::size_t texture_budget)
        : path_(path), m_(m), texture_budget_(render_decode_budget(texture_budget)) {}

    Scene run();
    std::vector<std::string> warnings;

private:
    [[noreturn]] void fail(const std::string& msg) const { throw Error("glTF '" + path_ + "': " + msg); }
    void warn(const std::string& msg) { warnings.push_back("glTF '" + path_ + "': " + msg); }

    AccessorView accessor(int index, const std::string& what);
    std::pair<const unsigned char*, std::size_t> buffer_view_bytes(int index, const std::string& what) const;
    Material convert_material(int index);
    TextureRef texture_ref(int tex_index, int texcoord, bool srgb, const std::string& what);
    //! A texture texture_ref will decode: its image's bytes, and the slot of scene_.textures it fills.
    struct PendingTexture {
        std::string label, what, fallback;
        const unsigned char* bytes;
        std::size_t size;
        bool srgb;
        int slot;
    };
    void decode_one(const PendingTexture& p, DecodeBudget* budget, Texture& out);
    void decode_textures();
    void convert_meshes();
    bool convert_primitive(const tinygltf::Primitive& gp, const std::string& where, Primitive& out);
    //! The primitive's triangle list from its indices (or 0..n-1), every index checked against n.
    void primitive_indices(const tinygltf::Primitive& gp, const std::string& where, int mode, std::size_t n, Primitive& out);
    //! Attribute `name` of the primitive when present (count n, one of `types`; integer colours
    //! normalised), else an empty view.
    AccessorView primitive_attribute(const tinygltf::Primitive& gp, const std::string& where, const std::string& name,
                                     std::initializer_list<int> types, bool colour, std::size_t n);
    //! NORMAL (else computed), TEXCOORD_0, COLOR_0 and the further attributes the scene file's
    //! control mapping may read (COLOR_n, TEXCOORD_n, _CUSTOM).
    void primitive_attributes(const tinygltf::Primitive& gp, const std::string& where, std::size_t n, Primitive& out);
    //! The primitive's material (the default one appended when it has none) and, where its
    //! material needs them, tangents (TANGENT, else computed).
    void primitive_material(const tinygltf::Primitive& gp, const std::string& where, std::size_t n, Primitive& out);
    void traverse(int node, const glm::mat4& parent, int depth);
    void add_camera(const tinygltf::Camera& gc, const glm::mat4& world, const std::string& node_name);

    std::string path_;
    const tinygltf::Model& m_;
    Scene scene_;
    std::map<std::pair<int, bool>, int> texture_cache_;  //!< (image, srgb) -> scene texture or -1
    std::vector<bool> material_needs_tangents_;
    bool need_default_material_ = false;
    std::size_t total_triangles_ = 0, instanced_triangles_ = 0, nonfinite_positions_ = 0;
    std::vector<char> node_state_;  //!< 0 unvisited, 1 on the current path, 2 done
    std::uint32_t next_object_id_ = 1;
    std::vector<std::size_t> infinite_cameras_;
    DecodeBudget texture_budget_;
    std::vector<PendingTexture> pending_;
    std::size_t accessor_bytes_ = 0, implicit_accessor_bytes_ = 0;
};

}  // namespace aq::scene::gltf
