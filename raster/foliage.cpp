// raster/foliage.cpp — see foliage.h.
#include "raster/foliage.h"

#include <cmath>
#include <cstdio>

namespace aq::raster {

namespace {
// The materials kept in the passes' scene lose their textures (the passes read a texture only
// for the alpha test of masked materials; a masked material keeps its texture).
scene::Material pass_material(const scene::Material& m) {
    scene::Material out = m;  // the intensity texture (LD06 §4.3) is kept: a pass reads it
    if (m.alpha_mode != scene::AlphaMode::Mask) {
        out.base_color_texture = {};
        out.normal_texture = {};
        for (auto& t : out.wc.control_texture) t = {};
    }
    return out;
}
}  // namespace

std::shared_ptr<const AbstractedScene> abstract_foliage(const scene::Scene& sc, const FoliageParams& p,
                                                        const Exec& ex, std::vector<std::string>* warnings) {
    auto out = std::make_shared<AbstractedScene>();
    scene::Scene& dst = out->scene;
    const scene::Bounds b = sc.world_bounds();
    if (!b.valid) throw Error("foliage abstraction: the scene has no finite geometry");
    out->height = b.max.y - b.min.y;
    bool keeps_masked = false;
    for (const scene::Material& m : sc.materials) {
        dst.materials.push_back(pass_material(m));
        keeps_masked = keeps_masked || m.alpha_mode == scene::AlphaMode::Mask || m.intensity_texture.texture >= 0;
    }
    if (keeps_masked) dst.textures = sc.textures;  // alpha tests and intensity textures need them
    dst.cameras = sc.cameras;
    dst.lights = sc.lights;
    dst.ambient = sc.ambient;
    dst.source = sc.source;
    dst.foliage = sc.foliage;
    dst.strokes = sc.strokes;
    std::vector<glm::vec3> points;
    int foliage_material = -1;
    std::uint32_t next_id = 1;
    for (const scene::Instance& inst : sc.instances) next_id = std::max(next_id, inst.object_id + 1);
    for (const scene::Instance& inst : sc.instances) {
        if (inst.mesh < 0 || inst.mesh >= int(sc.meshes.size())) continue;
        const scene::Mesh& mesh = sc.meshes[std::size_t(inst.mesh)];
        scene::Mesh kept;
        kept.name = mesh.name;
        for (const scene::Primitive& prim : mesh.primitives) {
            if (p.abstract && scene::is_foliage(sc, inst, prim)) {
                for (const glm::vec3& v : prim.positions) points.push_back(glm::vec3(inst.world * glm::vec4(v, 1.0f)));
                out->foliage_triangles += prim.indices.size() / 3;
                if (foliage_material < 0) {
                    foliage_material = prim.material;
                    out->foliage_object_id = inst.object_id;
                    out->foliage_material = prim.material;
                }
                continue;
            }
            kept.primitives.push_back(prim);
        }
        if (kept.primitives.empty()) continue;
        dst.meshes.push_back(std::move(kept));
        scene::Instance ki = inst;
        ki.mesh = int(dst.meshes.size()) - 1;
        dst.instances.push_back(ki);
    }
    out->foliage_points = points.size();
    if (!p.abstract) return out;
    if (points.empty()) {
        if (warnings) warnings->push_back("foliage abstraction: no foliage in the scene (docs/ld06.md \"Foliage\"); drawn as modelled");
        return out;
    }
    if (!(std::isfinite(p.radius) && p.radius > 0.0f)) throw Error("foliage abstraction: r must be finite and > 0");
    out->radius = p.relative ? p.radius * out->height : p.radius;
    ImplicitSurfaceParams ip;
    ip.threshold = p.threshold;
    ip.radius = out->radius;
    ip.cells_per_radius = p.cells_per_radius;
    if (!(out->radius > 0.0f && std::isfinite(out->radius)))
        throw Error("foliage abstraction: r = " + std::to_string(p.radius) + " x plant height " +
                    std::to_string(out->height) + " is not a usable radius");
    out->surface = build_implicit_surface(points, ip, ex);
    if (p.fit_threshold && out->surface.indices.empty()) {
        // The field does not depend on T and the surface is empty exactly when its maximum is not
        // above T: the first of T/2, T/4, ... (at most kFitThresholdSteps halvings) below the
        // maximum is found without building, then the surface is built once more at it.
        int k = 0;
        while (k < kFitThresholdSteps && !(out->surface.field_max > ip.threshold)) ip.threshold *= 0.5f, ++k;
        if (out->surface.field_max > ip.threshold) out->surface = build_implicit_surface(points, ip, ex);
        if (!out->surface.indices.empty() && warnings) {
            char msg[256];
            std::snprintf(msg, sizeof msg,
                          "foliage abstraction: the summed density of %zu foliage points never reaches T = %g at r = %g; "
                          "used T = %g (fit_threshold; set foliage.T in the scene file to choose)",
                          points.size(), double(p.threshold), double(out->radius), double(ip.threshold));
            warnings->push_back(msg);
        }
    }
    if (out->surface.indices.empty()) {
        char msg[256];
        std::snprintf(msg, sizeof msg,
                      "foliage abstraction: the implicit surface of %zu foliage points is empty at T = %g, r = %g "
                      "(the summed density never reaches T: lower T or raise r)",
                      points.size(), double(p.threshold), double(out->radius));
        throw Error(msg);
    }
    scene::Material m;
    m.name = "foliage (implicit surface)";
    if (foliage_material >= 0 && foliage_material < int(sc.materials.size()))
        m.base_color = sc.materials[std::size_t(foliage_material)].base_color;
    m.double_sided = true;
    dst.materials.push_back(m);
    scene::Primitive prim;
    prim.positions = out->surface.positions;
    prim.normals = out->surface.normals;
    prim.indices = out->surface.indices;
    prim.material = int(dst.materials.size()) - 1;
    const int prim_material = prim.material;
    scene::Mesh mesh;
    mesh.name = "foliage (implicit surface)";
    if (dst.foliage.set) scene::FoliageSelection::add(dst.foliage.meshes, mesh.name);  // still foliage for the passes
    mesh.primitives.push_back(std::move(prim));
    dst.meshes.push_back(std::move(mesh));
    scene::Instance inst;
    inst.mesh = int(dst.meshes.size()) - 1;
    inst.object_id = next_id;
    inst.name = "foliage (implicit surface)";
    dst.instances.push_back(inst);
    out->surface_object_id = inst.object_id;
    out->surface_material = prim_material;
    out->abstracted = true;
    return out;
}

scene::LayerTable abstracted_layer_table(const scene::Scene& source, const AbstractedScene& a) {
    scene::LayerTable t = scene::build_layer_table(source);
    if (a.abstracted) t.assign(a.surface_object_id, a.surface_material, t.of(a.foliage_object_id, a.foliage_material));
    return t;
}

}  // namespace aq::raster
