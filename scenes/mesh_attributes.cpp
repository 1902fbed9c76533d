// scenes/mesh_attributes.cpp — the vertex attributes a model may lack (normals weighted by face
// area, tangents from the UVs), and strips and fans as triangle lists (declared in
// scenes/gltf_loader.h).
#include <cmath>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>
#include <tiny_gltf.h>  // the primitive modes

#include "scenes/gltf_loader.h"

namespace aq::scene {

std::vector<glm::vec3> compute_normals(const std::vector<glm::vec3>& p, const std::vector<std::uint32_t>& idx) {
    std::vector<glm::vec3> n(p.size(), glm::vec3(0.0f));
    for (std::size_t t = 0; t + 2 < idx.size(); t += 3) {
        const std::uint32_t a = idx[t], b = idx[t + 1], c = idx[t + 2];
        if (a >= p.size() || b >= p.size() || c >= p.size()) continue;
        // The cross product's length is twice the area: summing it weights faces by area.
        const glm::vec3 fn = glm::cross(p[b] - p[a], p[c] - p[a]);
        if (!std::isfinite(fn.x) || !std::isfinite(fn.y) || !std::isfinite(fn.z)) continue;
        n[a] += fn;
        n[b] += fn;
        n[c] += fn;
    }
    for (glm::vec3& v : n) {
        const float len = glm::length(v);
        v = (len > 0.0f && std::isfinite(len)) ? v / len : glm::vec3(0.0f, 0.0f, 1.0f);
    }
    return n;
}

namespace {
glm::vec3 any_perpendicular(const glm::vec3& n) {
    const glm::vec3 a = std::abs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    const glm::vec3 t = glm::cross(a, n);
    const float len = glm::length(t);
    return len > 0.0f ? t / len : glm::vec3(1, 0, 0);
}
}  // namespace

std::vector<glm::vec4> compute_tangents(const std::vector<glm::vec3>& p, const std::vector<glm::vec3>& nrm,
                                        const std::vector<glm::vec2>& uv, const std::vector<std::uint32_t>& idx) {
    const std::size_t n = p.size();
    std::vector<glm::vec3> tan(n, glm::vec3(0.0f)), bit(n, glm::vec3(0.0f));
    if (uv.size() == n) {
        for (std::size_t t = 0; t + 2 < idx.size(); t += 3) {
            const std::uint32_t a = idx[t], b = idx[t + 1], c = idx[t + 2];
            if (a >= n || b >= n || c >= n) continue;
            const glm::vec3 e1 = p[b] - p[a], e2 = p[c] - p[a];
            const glm::vec2 d1 = uv[b] - uv[a], d2 = uv[c] - uv[a];
            const float det = d1.x * d2.y - d2.x * d1.y;
            if (det == 0.0f || !std::isfinite(det)) continue;
            // Unnormalised by |det| on purpose: weights each face by its area in position space
            // and keeps the sign for the handedness.
            const float r = 1.0f / det;
            const glm::vec3 sdir = (e1 * d2.y - e2 * d1.y) * r;
            const glm::vec3 tdir = (e2 * d1.x - e1 * d2.x) * r;
            if (!std::isfinite(sdir.x + sdir.y + sdir.z + tdir.x + tdir.y + tdir.z)) continue;
            for (std::uint32_t v : {a, b, c}) {
                tan[v] += sdir;
                bit[v] += tdir;
            }
        }
    }
    std::vector<glm::vec4> out(n);
    for (std::size_t i = 0; i < n; ++i) {
        const glm::vec3 N = i < nrm.size() ? nrm[i] : glm::vec3(0, 0, 1);
        glm::vec3 T = tan[i] - N * glm::dot(N, tan[i]);  // Gram-Schmidt
        const float len = glm::length(T);
        if (!(len > 1e-20f) || !std::isfinite(len)) {
            out[i] = glm::vec4(any_perpendicular(N), 1.0f);
            continue;
        }
        T /= len;
        const float w = glm::dot(glm::cross(N, T), bit[i]) < 0.0f ? -1.0f : 1.0f;
        out[i] = glm::vec4(T, w);
    }
    return out;
}

std::vector<std::uint32_t> to_triangle_list(int mode, const std::vector<std::uint32_t>& v) {
    std::vector<std::uint32_t> out;
    const std::size_t n = v.size();
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        out.assign(v.begin(), v.begin() + std::ptrdiff_t(n - n % 3));
    } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        if (n >= 3) out.reserve((n - 2) * 3);
        for (std::size_t i = 0; i + 2 < n; ++i) {
            // glTF 2.0 §3.7.2.1: odd triangles swap their first two vertices to keep the winding.
            if (i % 2 == 0) out.insert(out.end(), {v[i], v[i + 1], v[i + 2]});
            else out.insert(out.end(), {v[i + 1], v[i], v[i + 2]});
        }
    } else if (mode == TINYGLTF_MODE_TRIANGLE_FAN) {
        if (n >= 3) out.reserve((n - 2) * 3);
        for (std::size_t i = 1; i + 1 < n; ++i) out.insert(out.end(), {v[0], v[i], v[i + 1]});
    } else {
        throw Error("to_triangle_list: mode " + std::to_string(mode) + " is not a triangle mode");
    }
    return out;
}

}  // namespace aq::scene
