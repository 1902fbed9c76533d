// scenes/leaf_strokes.cpp — see leaf_strokes.h.
#include "scenes/leaf_strokes.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/image.h"  // aq::Error

namespace aq::scene {

namespace {

// Leaves of a primitive: connected components of its triangles over shared vertex indices
// (union-find; each component listed by its triangles in index order, components by their first).
std::vector<std::vector<std::uint32_t>> leaves_of(const Primitive& p) {
    const std::size_t nv = p.positions.size(), nt = p.indices.size() / 3;
    std::vector<std::uint32_t> parent(nv);
    std::iota(parent.begin(), parent.end(), 0u);
    auto find = [&](std::uint32_t v) {
        while (parent[v] != v) v = parent[v] = parent[parent[v]];
        return v;
    };
    for (std::size_t t = 0; t < nt; ++t) {
        const std::uint32_t a = find(p.indices[3 * t]);
        for (int k = 1; k < 3; ++k) {
            const std::uint32_t b = find(p.indices[3 * t + std::size_t(k)]);
            if (a != b) parent[std::max(a, b)] = std::min(a, b);
        }
    }
    std::vector<std::vector<std::uint32_t>> out;
    std::vector<std::int64_t> slot(nv, -1);
    for (std::size_t t = 0; t < nt; ++t) {
        const std::uint32_t r = find(p.indices[3 * t]);
        if (slot[r] < 0) {
            slot[r] = std::int64_t(out.size());
            out.emplace_back();
        }
        out[std::size_t(slot[r])].push_back(std::uint32_t(t));
    }
    return out;
}

// Barycentric coordinates of q in the UV triangle (a, b, c); false when outside or degenerate.
bool inside_uv(glm::vec2 q, glm::vec2 a, glm::vec2 b, glm::vec2 c, float* w1, float* w2) {
    const glm::vec2 e1 = b - a, e2 = c - a, d = q - a;
    const float det = e1.x * e2.y - e1.y * e2.x;
    if (!(std::abs(det) > 0.0f)) return false;
    const float u = (d.x * e2.y - d.y * e2.x) / det, v = (e1.x * d.y - e1.y * d.x) / det;
    constexpr float kEps = 1e-6f;
    if (u < -kEps || v < -kEps || u + v > 1.0f + kEps) return false;
    *w1 = u;
    *w2 = v;
    return true;
}

}  // namespace

std::vector<Stroke> place_uv_strokes(const Scene& sc, const std::vector<UvStroke>& strokes, std::size_t max_strokes,
                                     std::size_t max_points, std::size_t* work_budget) {
    // Work bound first: every point may be tested against every triangle of its material.
    std::size_t work = 0;
    for (const UvStroke& us : strokes)
        for (const Instance& inst : sc.instances) {
            if (inst.mesh < 0 || inst.mesh >= int(sc.meshes.size())) continue;
            for (const Primitive& p : sc.meshes[std::size_t(inst.mesh)].primitives)
                if (p.material >= 0 && p.material < int(sc.materials.size()) && sc.materials[std::size_t(p.material)].name == us.material) {
                    const std::size_t tris = p.indices.size() / 3, pts = us.uv.size();
                    if (tris && pts > (*work_budget - std::min(work, *work_budget)) / tris) work = *work_budget + 1;
                    else work += tris * pts;
                    if (work > *work_budget)
                        throw Error("strokes: placing the texture-space strokes would test more than " + std::to_string(kMaxUvStrokeWork) +
                                    " (point, triangle) pairs (docs/limits.md); draw fewer or shorter strokes");
                }
        }
    *work_budget -= work;
    std::vector<Stroke> out;
    std::size_t points = 0;
    auto limit = [&](std::size_t more_points) {
        if (out.size() + 1 > max_strokes || points + more_points > max_points)
            throw Error("strokes: copying the texture-space strokes onto every leaf gives more than " +
                        std::to_string(max_strokes) + " strokes or " + std::to_string(max_points) +
                        " points (docs/limits.md); draw fewer strokes or select fewer leaves by material");
    };
    for (const UvStroke& us : strokes)
        for (const Instance& inst : sc.instances) {
            if (inst.mesh < 0 || inst.mesh >= int(sc.meshes.size())) continue;
            const glm::mat3 nmat = glm::transpose(glm::inverse(glm::mat3(inst.world)));
            for (const Primitive& p : sc.meshes[std::size_t(inst.mesh)].primitives) {
                if (p.material < 0 || p.material >= int(sc.materials.size()) ||
                    sc.materials[std::size_t(p.material)].name != us.material || p.uv0.size() != p.positions.size())
                    continue;
                for (const std::vector<std::uint32_t>& leaf : leaves_of(p)) {
                    Stroke s;
                    s.light_dependent = us.light_dependent;
                    auto flush = [&] {
                        if (s.points.size() >= 2) {
                            limit(s.points.size());
                            points += s.points.size();
                            out.push_back(s);
                        }
                        s.points.clear();
                        s.normals.clear();
                    };
                    for (const glm::vec2 q : us.uv) {
                        bool found = false;
                        for (const std::uint32_t t : leaf) {
                            const std::uint32_t i0 = p.indices[3 * t], i1 = p.indices[3 * t + 1], i2 = p.indices[3 * t + 2];
                            float w1, w2;
                            if (!inside_uv(q, p.uv0[i0], p.uv0[i1], p.uv0[i2], &w1, &w2)) continue;
                            const float w0 = 1.0f - w1 - w2;
                            const glm::vec3 pos = w0 * p.positions[i0] + w1 * p.positions[i1] + w2 * p.positions[i2];
                            const glm::vec3 n = w0 * p.normals[i0] + w1 * p.normals[i1] + w2 * p.normals[i2];
                            s.points.push_back(glm::vec3(inst.world * glm::vec4(pos, 1.0f)));
                            const glm::vec3 wn = nmat * n;
                            const float l = glm::length(wn);
                            s.normals.push_back(l > 0.0f ? wn / l : glm::vec3(0, 0, 1));
                            found = true;
                            break;
                        }
                        if (!found) flush();
                    }
                    flush();
                }
            }
        }
    return out;
}

}  // namespace aq::scene
