// scenes/scene.cpp — scene-wide queries.
#include "scenes/scene.h"

#include <algorithm>
#include <cctype>
#include <cmath>

namespace aq::scene {

Bounds Scene::world_bounds() const {
    Bounds b;
    for (const Instance& inst : instances) {
        if (inst.mesh < 0 || inst.mesh >= int(meshes.size())) continue;
        for (const Primitive& p : meshes[inst.mesh].primitives)
            for (const glm::vec3& v : p.positions) {
                const glm::vec4 w = inst.world * glm::vec4(v, 1.0f);
                if (!std::isfinite(w.x) || !std::isfinite(w.y) || !std::isfinite(w.z)) continue;
                const glm::vec3 q(w);
                if (!b.valid) {
                    b.min = b.max = q;
                    b.valid = true;
                } else {
                    b.min = glm::min(b.min, q);
                    b.max = glm::max(b.max, q);
                }
            }
    }
    return b;
}

std::size_t Scene::triangle_count() const {
    std::size_t n = 0;
    for (const Instance& inst : instances)
        if (inst.mesh >= 0 && inst.mesh < int(meshes.size()))
            for (const Primitive& p : meshes[inst.mesh].primitives) n += p.indices.size() / 3;
    return n;
}

namespace {
bool names_foliage(std::string n) {
    for (char& c : n) c = char(std::tolower(static_cast<unsigned char>(c)));
    for (const char* w : {"foliage", "leaf", "leaves"})
        if (n.find(w) != std::string::npos) return true;
    return false;
}
}  // namespace

void FoliageSelection::add(std::vector<std::string>& list, const std::string& name) {
    const auto it = std::lower_bound(list.begin(), list.end(), name);
    if (it == list.end() || *it != name) list.insert(it, name);
}

bool is_foliage(const Scene& sc, const Instance& inst, const Primitive& prim) {
    const Material* m = prim.material >= 0 && prim.material < int(sc.materials.size()) ? &sc.materials[prim.material] : nullptr;
    if (sc.foliage.set) {
        auto listed = [](const std::vector<std::string>& v, const std::string& n) {
            return std::binary_search(v.begin(), v.end(), n);  // sorted: FoliageSelection
        };
        const Mesh* mesh = inst.mesh >= 0 && inst.mesh < int(sc.meshes.size()) ? &sc.meshes[std::size_t(inst.mesh)] : nullptr;
        return listed(sc.foliage.nodes, inst.name) || (mesh && listed(sc.foliage.meshes, mesh->name)) ||
               (m && listed(sc.foliage.materials, m->name));
    }
    if (m && (m->alpha_mode == AlphaMode::Mask || names_foliage(m->name))) return true;
    if (inst.mesh >= 0 && inst.mesh < int(sc.meshes.size()) && names_foliage(sc.meshes[inst.mesh].name)) return true;
    return names_foliage(inst.name);
}

}  // namespace aq::scene
