// scenes/scene.cpp — scene-wide queries.
#include "scenes/scene.h"

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

}  // namespace aq::scene
