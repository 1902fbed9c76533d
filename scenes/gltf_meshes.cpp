// scenes/gltf_meshes.cpp — the glTF reader's buffer views, accessors (every range checked,
// overflow-safe, before a byte is read) and primitives (scenes/gltf_reader.h).
#include "scenes/gltf_reader.h"

#include <algorithm>
#include <atomic>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <string_view>

#include <glm/gtc/quaternion.hpp>
#include <tbb/parallel_for.h>
#include <glm/gtc/type_ptr.hpp>
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "core/color.h"
#include "core/input.h"
#include "core/io.h"
#include "core/json_file.h"
#include "core/unorm8.h"
#include "scenes/material_params.h"


namespace aq::scene::gltf {

std::pair<const unsigned char*, std::size_t> Loader::buffer_view_bytes(int index,
                                                                     const std::string& what) const {
    if (index < 0 || std::size_t(index) >= m_.bufferViews.size())
        fail(what + ": bufferView " + std::to_string(index) + " does not exist (the file has " +
             std::to_string(m_.bufferViews.size()) + ")");
    const tinygltf::BufferView& bv = m_.bufferViews[std::size_t(index)];
    if (bv.buffer < 0 || std::size_t(bv.buffer) >= m_.buffers.size())
        fail(what + ": bufferView " + std::to_string(index) + " refers to buffer " +
             std::to_string(bv.buffer) + " which does not exist (the file has " +
             std::to_string(m_.buffers.size()) + ")");
    const std::vector<unsigned char>& data = m_.buffers[std::size_t(bv.buffer)].data;
    if (bv.byteOffset > data.size() || bv.byteLength > data.size() - bv.byteOffset)
        fail(what + ": bufferView " + std::to_string(index) + " [offset " + std::to_string(bv.byteOffset) +
             ", length " + std::to_string(bv.byteLength) + "] exceeds buffer " + std::to_string(bv.buffer) +
             " of " + std::to_string(data.size()) + " bytes");
    return {data.data() + bv.byteOffset, bv.byteLength};
}

AccessorView Loader::accessor(int index, const std::string& what) {
    if (index < 0 || std::size_t(index) >= m_.accessors.size())
        fail(what + ": accessor " + std::to_string(index) + " does not exist (the file has " +
             std::to_string(m_.accessors.size()) + ")");
    const tinygltf::Accessor& a = m_.accessors[std::size_t(index)];
    const std::string name = what + ": accessor " + std::to_string(index);
    if (a.sparse.isSparse) fail(name + " is sparse; sparse accessors are not supported");
    const int csize = component_size(a.componentType);
    if (csize == 0) fail(name + " has invalid componentType " + std::to_string(a.componentType));
    const int nc = num_components(a.type);
    if (nc == 0) fail(name + " has an invalid type");
    if (a.count > kMaxVertices)
        fail(name + " has count " + std::to_string(a.count) + ", above the limit of " +
             std::to_string(kMaxVertices));
    AccessorView v;
    v.count = a.count;
    v.comp_type = a.componentType;
    v.ncomp = nc;
    v.normalized = a.normalized;
    const std::size_t elem = std::size_t(csize) * std::size_t(nc);
    v.stride = elem;
    const std::size_t data_bytes = a.count * elem;  // count <= kMaxVertices: no overflow
    accessor_bytes_ += data_bytes;
    if (accessor_bytes_ > kMaxAccessorBytes)
        fail(name + ": the accessors read so far hold " + std::to_string(accessor_bytes_) +
             " bytes, above the limit of " + std::to_string(kMaxAccessorBytes) + " per file (docs/limits.md)");
    if (a.bufferView == -1) {  // no bufferView: zeros (glTF 2.0 §3.6.2.2)
        implicit_accessor_bytes_ += data_bytes;
        if (implicit_accessor_bytes_ > kMaxImplicitAccessorBytes)
            fail(name + " has no bufferView (implicit zeros) and count " + std::to_string(a.count) +
                 ": implicit accessor data above " + std::to_string(kMaxImplicitAccessorBytes) +
                 " bytes per file is refused (docs/limits.md)");
        return v;
    }
    const auto [bytes, length] = buffer_view_bytes(a.bufferView, name);
    const tinygltf::BufferView& bv = m_.bufferViews[std::size_t(a.bufferView)];
    if (bv.byteStride != 0) {
        if (bv.byteStride < elem || bv.byteStride > 252)
            fail(name + ": byteStride " + std::to_string(bv.byteStride) + " of bufferView " +
                 std::to_string(a.bufferView) + " is invalid for " + std::to_string(elem) +
                 "-byte elements (allowed: element size..252)");
        v.stride = bv.byteStride;
    }
    if (a.count > 0) {
        // offset + (count-1)*stride + elem <= length, without overflow.
        if (a.byteOffset > length || length - a.byteOffset < elem ||
            (a.count - 1) > (length - a.byteOffset - elem) / v.stride)
            fail(name + " (offset " + std::to_string(a.byteOffset) + ", count " + std::to_string(a.count) +
                 ", stride " + std::to_string(v.stride) + ") exceeds bufferView " +
                 std::to_string(a.bufferView) + " of " + std::to_string(length) + " bytes");
    }
    v.base = bytes + a.byteOffset;
    return v;
}



bool Loader::convert_primitive(const tinygltf::Primitive& gp, const std::string& where, Primitive& out) {
    const int mode = gp.mode < 0 ? TINYGLTF_MODE_TRIANGLES : gp.mode;
    if (mode == TINYGLTF_MODE_POINTS || mode == TINYGLTF_MODE_LINE || mode == TINYGLTF_MODE_LINE_LOOP ||
        mode == TINYGLTF_MODE_LINE_STRIP) {
        warn(where + ": points/lines primitive (mode " + std::to_string(mode) + ") skipped");
        return false;
    }
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN)
        fail(where + ": invalid primitive mode " + std::to_string(mode));
    if (!gp.targets.empty()) warn(where + ": morph targets ignored");

    auto attr = gp.attributes.find("POSITION");
    if (attr == gp.attributes.end()) fail(where + ": no POSITION attribute");
    const AccessorView pos = accessor(attr->second, where + " POSITION");
    if (pos.ncomp != 3 || m_.accessors[std::size_t(attr->second)].type != TINYGLTF_TYPE_VEC3)
        fail(where + " POSITION: expected VEC3");
    const std::size_t n = pos.count;

    primitive_indices(gp, where, mode, n, out);
    out.positions.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        out.positions[i] = {pos.component(i, 0), pos.component(i, 1), pos.component(i, 2)};
        if (!std::isfinite(out.positions[i].x) || !std::isfinite(out.positions[i].y) ||
            !std::isfinite(out.positions[i].z))
            ++nonfinite_positions_;
    }

    primitive_attributes(gp, where, n, out);
    primitive_material(gp, where, n, out);
    return true;
}

void Loader::primitive_indices(const tinygltf::Primitive& gp, const std::string& where, int mode, std::size_t n, Primitive& out) {
    // Index count and triangle count are known before anything is allocated.
    std::size_t nidx = n;
    AccessorView iv;
    if (gp.indices >= 0) {
        iv = accessor(gp.indices, where + " indices");
        if (m_.accessors[std::size_t(gp.indices)].type != TINYGLTF_TYPE_SCALAR ||
            (iv.comp_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
             iv.comp_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
             iv.comp_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
            fail(where + " indices: expected SCALAR unsigned byte/short/int");
        nidx = iv.count;
    } else if (gp.indices != -1) {
        fail(where + ": invalid indices accessor " + std::to_string(gp.indices));
    }
    const std::size_t ntri = mode == TINYGLTF_MODE_TRIANGLES ? nidx / 3 : (nidx >= 3 ? nidx - 2 : 0);
    if (ntri > kMaxTriangles - total_triangles_)
        fail(where + ": more than " + std::to_string(kMaxTriangles) + " triangles in the file (limit)");
    total_triangles_ += ntri;

    std::vector<std::uint32_t> idx(nidx);
    if (gp.indices >= 0) {
        for (std::size_t i = 0; i < nidx; ++i) {
            idx[i] = iv.index(i);
            if (idx[i] >= n)
                fail(where + " indices: index " + std::to_string(idx[i]) + " at position " + std::to_string(i) +
                     " is out of range (" + std::to_string(n) + " vertices)");
        }
    } else {
        std::iota(idx.begin(), idx.end(), 0u);
    }
    if (mode == TINYGLTF_MODE_TRIANGLES && nidx % 3 != 0)
        warn(where + ": " + std::to_string(nidx % 3) + " trailing indices do not form a triangle, ignored");
    out.indices = to_triangle_list(mode, idx);
    idx.clear();
    idx.shrink_to_fit();

}

AccessorView Loader::primitive_attribute(const tinygltf::Primitive& gp, const std::string& where, const std::string& name,
                                         std::initializer_list<int> types, bool colour, std::size_t n) {
    auto it = gp.attributes.find(name);
    if (it == gp.attributes.end()) return {};
    AccessorView v = accessor(it->second, where + " " + name);
    const int t = m_.accessors[std::size_t(it->second)].type;
    if (std::find(types.begin(), types.end(), t) == types.end()) fail(where + " " + name + ": unexpected type " + type_name(t));
    if (v.count != n)
        fail(where + " " + name + ": count " + std::to_string(v.count) + " differs from POSITION count " + std::to_string(n));
    // Integer colours are normalised by definition (glTF 2.0 §3.7.2.1), whatever the flag says.
    if (colour && v.comp_type != TINYGLTF_COMPONENT_TYPE_FLOAT) v.normalized = true;
    return v;
}

void Loader::primitive_attributes(const tinygltf::Primitive& gp, const std::string& where, std::size_t n, Primitive& out) {
    auto read_attr = [&](const std::string& name, std::initializer_list<int> types, bool colour) {
        return primitive_attribute(gp, where, name, types, colour, n);
    };
    if (AccessorView v = read_attr("NORMAL", {TINYGLTF_TYPE_VEC3}, false); v.count) {
        out.normals.resize(n);
        for (std::size_t i = 0; i < n; ++i) out.normals[i] = {v.component(i, 0), v.component(i, 1), v.component(i, 2)};
    } else {
        out.normals = compute_normals(out.positions, out.indices);
    }
    if (AccessorView v = read_attr("TEXCOORD_0", {TINYGLTF_TYPE_VEC2}, false); v.count) {
        out.uv0.resize(n);
        for (std::size_t i = 0; i < n; ++i) out.uv0[i] = {v.component(i, 0), v.component(i, 1)};
    }
    if (AccessorView v = read_attr("COLOR_0", {TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4}, true); v.count) {
        out.colors.resize(n);
        for (std::size_t i = 0; i < n; ++i)
            out.colors[i] = {v.component(i, 0), v.component(i, 1), v.component(i, 2), v.ncomp == 4 ? v.component(i, 3) : 1.0f};
    }
    // Further attributes the scene file's control mapping may read (COLOR_n, TEXCOORD_n, _CUSTOM).
    for (const auto& [name, acc] : gp.attributes) {
        (void)acc;
        const bool colour = name.rfind("COLOR_", 0) == 0;
        if (!(colour && name != "COLOR_0") && !(name.rfind("TEXCOORD_", 0) == 0 && name != "TEXCOORD_0") &&
            !(name.rfind("_", 0) == 0))
            continue;
        AccessorView v = read_attr(name, {TINYGLTF_TYPE_SCALAR, TINYGLTF_TYPE_VEC2, TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4}, colour);
        auto& dst = out.attributes[name];
        dst.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            glm::vec4 c(0.0f, 0.0f, 0.0f, colour ? 1.0f : 0.0f);
            for (int k = 0; k < v.ncomp; ++k) c[k] = v.component(i, k);
            dst[i] = c;
        }
    }

}

void Loader::primitive_material(const tinygltf::Primitive& gp, const std::string& where, std::size_t n, Primitive& out) {
    if (gp.material >= 0) {
        if (std::size_t(gp.material) >= m_.materials.size())
            fail(where + ": material " + std::to_string(gp.material) + " does not exist (the file has " +
                 std::to_string(m_.materials.size()) + ")");
        out.material = gp.material;
    } else {
        if (gp.material != -1) fail(where + ": invalid material index " + std::to_string(gp.material));
        out.material = int(m_.materials.size());  // the default material, appended after the file's
        need_default_material_ = true;
    }
    if (out.material < int(material_needs_tangents_.size()) && material_needs_tangents_[std::size_t(out.material)]) {
        if (AccessorView v = primitive_attribute(gp, where, "TANGENT", {TINYGLTF_TYPE_VEC4}, false, n); v.count) {
            out.tangents.resize(n);
            for (std::size_t i = 0; i < n; ++i)
                out.tangents[i] = {v.component(i, 0), v.component(i, 1), v.component(i, 2), v.component(i, 3)};
        } else {
            if (out.uv0.empty())
                warn(where + ": normal-mapped material without TEXCOORD_0; tangents are arbitrary");
            out.tangents = compute_tangents(out.positions, out.normals, out.uv0, out.indices);
        }
    }
}

void Loader::convert_meshes() {
    // Pre-pass over the counts alone, so that a file whose primitives add up to absurd sizes is
    // refused before anything is allocated (each accessor is fully validated later).
    std::size_t vertices = 0, triangles = 0;
    for (const tinygltf::Mesh& gm : m_.meshes)
        for (const tinygltf::Primitive& gp : gm.primitives) {
            const int mode = gp.mode < 0 ? TINYGLTF_MODE_TRIANGLES : gp.mode;
            if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) continue;
            auto it = gp.attributes.find("POSITION");
            if (it == gp.attributes.end() || it->second < 0 || std::size_t(it->second) >= m_.accessors.size()) continue;
            const std::size_t n = std::min(m_.accessors[std::size_t(it->second)].count, kMaxVertices + 1);
            std::size_t nidx = n;
            if (gp.indices >= 0 && std::size_t(gp.indices) < m_.accessors.size())
                nidx = std::min(m_.accessors[std::size_t(gp.indices)].count, kMaxVertices + 1);
            vertices += n;
            triangles += mode == TINYGLTF_MODE_TRIANGLES ? nidx / 3 : (nidx >= 3 ? nidx - 2 : 0);
            if (vertices > kMaxVertices)
                fail("the triangle primitives hold more than " + std::to_string(kMaxVertices) + " vertices in total (limit)");
            if (triangles > kMaxTriangles)
                fail("more than " + std::to_string(kMaxTriangles) + " triangles in the file (limit)");
        }
    for (std::size_t mi = 0; mi < m_.meshes.size(); ++mi) {
        const tinygltf::Mesh& gm = m_.meshes[mi];
        Mesh mesh;
        mesh.name = gm.name.empty() ? "mesh_" + std::to_string(mi) : gm.name;
        for (std::size_t pi = 0; pi < gm.primitives.size(); ++pi) {
            Primitive p;
            const std::string where = "mesh " + std::to_string(mi) + " primitive " + std::to_string(pi);
            if (convert_primitive(gm.primitives[pi], where, p)) mesh.primitives.push_back(std::move(p));
        }
        scene_.meshes.push_back(std::move(mesh));
    }
}

}  // namespace aq::scene::gltf
