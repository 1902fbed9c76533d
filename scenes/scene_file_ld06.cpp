// scenes/scene_file_ld06.cpp — the LD06 sections of a scene file (docs/scenes.md): the foliage
// selection and its parameters, the layers, the hand-made strokes. Selections name nodes, meshes
// and materials that must exist (a typo would silently select nothing).
#include <algorithm>
#include <cstring>

#include "scenes/layers.h"
#include "scenes/leaf_strokes.h"
#include "scenes/scene_file_reader.h"

namespace aq::scene::file {

SceneNames::SceneNames(const Scene& sc) {
    for (const Instance& inst : sc.instances) nodes.push_back(inst.name);
    for (const Mesh& m : sc.meshes) meshes.push_back(m.name);
    for (const Material& m : sc.materials) materials.push_back(m.name);
    for (auto* v : {&nodes, &meshes, &materials}) {
        std::sort(v->begin(), v->end());
        v->erase(std::unique(v->begin(), v->end()), v->end());
    }
}

void SceneNames::read(const Ctx& ctx, const json& f, const std::string& where, const char* key,
                      std::vector<std::string>& out, const std::vector<std::string>& have) const {
    if (!f.contains(key)) return;
    const std::string k = where + "." + key;
    if (!f[key].is_array()) ctx.bad(k, "expected an array of names");
    for (std::size_t i = 0; i < f[key].size(); ++i) {
        const std::string n = ctx.string(f[key][i], k + "[" + std::to_string(i) + "]");
        if (!std::binary_search(have.begin(), have.end(), n)) {
            std::string list;
            for (const std::string& h : have) list += (list.empty() ? "" : ", ") + ("'" + h + "'");
            const std::string singular = std::strcmp(key, "meshes") == 0 ? "mesh" : std::string(key).substr(0, std::strlen(key) - 1);
            ctx.bad(k + "[" + std::to_string(i) + "]",
                    "no " + singular + " is named '" + n + "' (have: " + (list.empty() ? "none" : list) + ")");
        }
        out.push_back(n);
    }
}

void read_foliage(const Ctx& ctx, const json& j, const SceneNames& names, SceneDesc& d) {
    if (!j.contains("foliage")) return;
    const json& f = j["foliage"];
    ctx.check_keys(f, "foliage", {"nodes", "meshes", "materials", "T", "radius", "relative", "cells_per_radius", "technique", "comment"});
    if (f.contains("technique")) {
        const json& t = f["technique"];
        if (!t.is_string() || (t != "auto" && t != "surface" && t != "texture"))
            ctx.bad("foliage.technique", "expected \"auto\", \"surface\" or \"texture\"");
        else d.foliage_technique = t.get<std::string>();
    }
    if (f.contains("T")) d.foliage_threshold = float(ctx.number(f["T"], "foliage.T", 1e-6, 1e6));
    if (f.contains("radius")) d.foliage_radius = float(ctx.number(f["radius"], "foliage.radius", 1e-6, 1e6));
    if (f.contains("relative")) {
        if (!f["relative"].is_boolean()) ctx.bad("foliage.relative", "expected true or false");
        d.foliage_relative = f["relative"].get<bool>();
    }
    if (f.contains("cells_per_radius")) d.foliage_cells_per_radius = ctx.integer(f["cells_per_radius"], "foliage.cells_per_radius", 1, 16);
    FoliageSelection& sel = d.scene.foliage;
    // Without names the default rule selects the foliage (the block only sets parameters).
    const bool selects = f.contains("nodes") || f.contains("meshes") || f.contains("materials");
    sel.set = selects;
    names.read(ctx, f, "foliage", "nodes", sel.nodes, names.nodes);
    names.read(ctx, f, "foliage", "meshes", sel.meshes, names.meshes);
    names.read(ctx, f, "foliage", "materials", sel.materials, names.materials);
    if (selects && sel.nodes.empty() && sel.meshes.empty() && sel.materials.empty())
        ctx.bad("foliage", "names no node, mesh or material");
    for (auto* v : {&sel.nodes, &sel.meshes, &sel.materials}) {  // sorted and unique (is_foliage searches them)
        std::sort(v->begin(), v->end());
        v->erase(std::unique(v->begin(), v->end()), v->end());
    }
}

// LD06 §3.1 layers: groups of primitives painted as one wash, with their colours (docs/ld06.md "Layers").
void read_layers(const Ctx& ctx, const json& j, const SceneNames& names, SceneDesc& d) {
    if (!j.contains("layers")) return;
    const json& ls = j["layers"];
    if (!ls.is_array()) ctx.bad("layers", "expected an array of {\"name\", \"nodes\", \"meshes\", \"materials\", \"color\", \"dark\", \"alpha\"}");
    if (ls.size() > kMaxLayerSpecs) ctx.bad("layers", "more than " + std::to_string(kMaxLayerSpecs) + " layers");
    for (std::size_t i = 0; i < ls.size(); ++i) {
        const std::string k = "layers[" + std::to_string(i) + "]";
        ctx.check_keys(ls[i], k, {"name", "nodes", "meshes", "materials", "color", "dark", "alpha", "comment"});
        LayerSpec l;
        l.name = ls[i].contains("name") ? ctx.string(ls[i]["name"], k + ".name") : "layer " + std::to_string(i);
        names.read(ctx, ls[i], k, "nodes", l.nodes, names.nodes);
        names.read(ctx, ls[i], k, "meshes", l.meshes, names.meshes);
        names.read(ctx, ls[i], k, "materials", l.materials, names.materials);
        if (l.nodes.empty() && l.meshes.empty() && l.materials.empty()) ctx.bad(k, "names no node, mesh or material");
        if (ls[i].contains("color")) l.color = ctx.vec3(ls[i]["color"], k + ".color", 0.0, 1.0);
        if (ls[i].contains("dark")) l.dark = ctx.vec3(ls[i]["dark"], k + ".dark", 0.0, 1.0);
        if (ls[i].contains("alpha")) l.alpha = float(ctx.number(ls[i]["alpha"], k + ".alpha", 0.0, 1.0));
        d.scene.layers.push_back(std::move(l));
    }
}

// LD06 §4.4 hand-made strokes: polylines in world coordinates ("scale" does not apply), or in a
// material's texture space copied onto every leaf of that material (scenes/leaf_strokes.h), in
// file order.
void read_strokes(const Ctx& ctx, const json& j, const SceneNames& names, SceneDesc& d) {
    if (!j.contains("strokes")) return;
    const json& st = j["strokes"];
    if (!st.is_array())
        ctx.bad("strokes", "expected an array of {\"points\": [[x, y, z], ...], \"normals\", \"hatching\"} or "
                           "{\"uv\": [[u, v], ...], \"material\": NAME, \"hatching\"}");
    if (st.size() > kMaxSceneStrokes) ctx.bad("strokes", "more than " + std::to_string(kMaxSceneStrokes) + " strokes");
    std::size_t vertices = 0, uv_work = kMaxUvStrokeWork;
    for (std::size_t i = 0; i < st.size(); ++i) {
        const std::string k = "strokes[" + std::to_string(i) + "]";
        ctx.check_keys(st[i], k, {"points", "normals", "uv", "material", "hatching", "comment"});
        bool hatching = false;
        if (st[i].contains("hatching")) {
            if (!st[i]["hatching"].is_boolean()) ctx.bad(k + ".hatching", "expected true or false");
            hatching = st[i]["hatching"].get<bool>();
        }
        if (st[i].contains("uv")) {
            if (st[i].contains("points") || st[i].contains("normals"))
                ctx.bad(k, "a stroke has either \"points\" (world) or \"uv\" (texture space), not both");
            if (!st[i]["uv"].is_array() || st[i]["uv"].size() < 2)
                ctx.bad(k + ".uv", "expected an array of at least two [u, v] points");
            if (!st[i].contains("material")) ctx.bad(k + ".material", "a texture-space stroke names the material whose leaves it is copied onto");
            UvStroke us;
            us.material = ctx.string(st[i]["material"], k + ".material");
            if (!std::binary_search(names.materials.begin(), names.materials.end(), us.material))
                ctx.bad(k + ".material", "no material is named '" + us.material + "'");
            us.light_dependent = hatching;
            for (std::size_t q = 0; q < st[i]["uv"].size(); ++q) {
                const std::string kq = k + ".uv[" + std::to_string(q) + "]";
                const json& uv = st[i]["uv"][q];
                if (!uv.is_array() || uv.size() != 2) ctx.bad(kq, "expected [u, v]");
                us.uv.push_back({float(ctx.number(uv[0], kq + "[0]", -1e6, 1e6)), float(ctx.number(uv[1], kq + "[1]", -1e6, 1e6))});
            }
            std::vector<Stroke> placed;
            try {
                placed = place_uv_strokes(d.scene, {us}, kMaxSceneStrokes - d.scene.strokes.size(),
                                          kMaxSceneStrokeVertices - vertices, &uv_work);
            } catch (const Error& e) {
                ctx.bad(k, e.what());
            }
            if (placed.empty()) ctx.bad(k, "lands on no leaf of material '" + us.material + "' (no triangle's UVs contain its points)");
            for (Stroke& ps : placed) {
                vertices += ps.points.size();
                d.scene.strokes.push_back(std::move(ps));
            }
            continue;
        }
        if (!st[i].contains("points") || !st[i]["points"].is_array() || st[i]["points"].size() < 2)
            ctx.bad(k + ".points", "expected an array of at least two [x, y, z] points");
        Stroke s;
        vertices += st[i]["points"].size();
        if (vertices > kMaxSceneStrokeVertices || d.scene.strokes.size() >= kMaxSceneStrokes)
            ctx.bad(k + ".points", "more than " + std::to_string(kMaxSceneStrokeVertices) + " stroke points or " +
                                       std::to_string(kMaxSceneStrokes) + " strokes in all");
        for (std::size_t q = 0; q < st[i]["points"].size(); ++q)
            s.points.push_back(ctx.vec3(st[i]["points"][q], k + ".points[" + std::to_string(q) + "]"));
        if (st[i].contains("normals")) {
            const json& n = st[i]["normals"];
            if (!n.is_array() || n.size() != s.points.size()) ctx.bad(k + ".normals", "expected one [x, y, z] per point");
            for (std::size_t q = 0; q < n.size(); ++q)
                s.normals.push_back(ctx.vec3(n[q], k + ".normals[" + std::to_string(q) + "]"));
        }
        s.light_dependent = hatching;
        d.scene.strokes.push_back(std::move(s));
    }
}

}  // namespace aq::scene::file
