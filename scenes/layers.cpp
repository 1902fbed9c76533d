// scenes/layers.cpp — see layers.h.
#include "scenes/layers.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/color.h"

namespace aq::scene {

glm::vec3 material_display_color(const Scene& sc, int material) {
    if (material < 0 || material >= int(sc.materials.size())) return glm::vec3(1.0f);
    const Material& m = sc.materials[std::size_t(material)];
    glm::vec3 c(m.base_color);
    const int ti = m.base_color_texture.texture;
    if (ti >= 0 && ti < int(sc.textures.size()) && !sc.textures[std::size_t(ti)].empty()) {
        const Texture& tex = sc.textures[std::size_t(ti)];
        const int w = tex.width();
        const std::size_t n = std::size_t(w) * std::size_t(tex.height());
        const std::size_t step = std::max<std::size_t>(1, n / kLayerColorSamples);
        // A float image of fewer than 4 channels has no alpha to mask with; grey counts as R, G, B.
        const int nc = tex.codes.empty() ? tex.image.channels() : 4;
        const bool masked = m.alpha_mode == AlphaMode::Mask && nc >= 4;
        double sum[3] = {0, 0, 0};
        std::size_t count = 0;
        for (std::size_t i = 0; i < n; i += step) {
            glm::vec4 px = tex.texel0(int(i % std::size_t(w)), int(i / std::size_t(w)));
            if (nc == 2) px.z = px.y;  // channel min(k, nc - 1) of a 2-channel image
            if (masked && !(px[3] >= m.alpha_cutoff)) continue;
            bool finite = true;
            for (int k = 0; k < 3; ++k) finite = finite && std::isfinite(px[k]);
            if (!finite) continue;
            for (int k = 0; k < 3; ++k) sum[k] += double(px[k]);
            ++count;
        }
        if (count > 0)
            for (int k = 0; k < 3; ++k) c[k] *= float(sum[k] / double(count));
    }
    for (int k = 0; k < 3; ++k) {
        float v = std::isfinite(c[k]) ? std::clamp(c[k], 0.0f, 1.0f) : 0.5f;
        c[k] = m.linear_color ? linear_to_srgb(v) : v;
    }
    return c;
}

LayerTable build_layer_table(const Scene& sc) {
    LayerTable t;
    std::vector<int> first_material(sc.layers.size(), -1);
    for (const LayerSpec& s : sc.layers) {
        Layer l;
        l.name = s.name;
        t.layers.push_back(l);
    }
    // Name -> the first group naming it, per kind (a primitive joins the first group naming its
    // node, mesh or material): one lookup per primitive whatever the number of groups and names.
    std::map<std::string, int> by_node, by_mesh, by_material;
    for (std::size_t g = sc.layers.size(); g-- > 0;) {
        for (const std::string& n : sc.layers[g].nodes) by_node[n] = int(g);
        for (const std::string& n : sc.layers[g].meshes) by_mesh[n] = int(g);
        for (const std::string& n : sc.layers[g].materials) by_material[n] = int(g);
    }
    auto group_of = [](const std::map<std::string, int>& m, const std::string& n) {
        const auto it = m.find(n);
        return it == m.end() ? std::numeric_limits<int>::max() : it->second;
    };
    std::map<int, int> material_layer;  // the per-material layers of unassigned primitives
    for (const Instance& inst : sc.instances) {
        if (inst.mesh < 0 || inst.mesh >= int(sc.meshes.size())) continue;
        const Mesh& mesh = sc.meshes[std::size_t(inst.mesh)];
        for (const Primitive& prim : mesh.primitives) {
            const std::string& mat_name =
                prim.material >= 0 && prim.material < int(sc.materials.size()) ? sc.materials[std::size_t(prim.material)].name
                                                                               : std::string();
            int layer = -1;
            if (!sc.layers.empty()) {
                const int g = std::min({group_of(by_node, inst.name), group_of(by_mesh, mesh.name),
                                        mat_name.empty() ? std::numeric_limits<int>::max() : group_of(by_material, mat_name)});
                if (g != std::numeric_limits<int>::max()) {
                    layer = g;
                    if (first_material[std::size_t(g)] < 0) first_material[std::size_t(g)] = prim.material;
                }
            }
            if (layer < 0) {
                auto [it, fresh] = material_layer.emplace(prim.material, int(t.layers.size()));
                if (fresh) {
                    Layer l;
                    l.name = mat_name.empty() ? "material " + std::to_string(prim.material) : mat_name;
                    l.color = material_display_color(sc, prim.material);
                    l.dark = l.color * kLayerDarkTone;
                    t.layers.push_back(l);
                }
                layer = it->second;
            }
            t.assign(inst.object_id, prim.material, layer);
        }
    }
    for (std::size_t g = 0; g < sc.layers.size(); ++g) {
        const LayerSpec& s = sc.layers[g];
        Layer& l = t.layers[g];
        l.color = s.color ? *s.color : material_display_color(sc, first_material[g]);
        l.dark = s.dark ? *s.dark : l.color * kLayerDarkTone;
        l.alpha = s.alpha ? *s.alpha : 1.0f;
    }
    return t;
}

}  // namespace aq::scene
