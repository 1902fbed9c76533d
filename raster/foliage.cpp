// raster/foliage.cpp — see foliage.h.
#include "raster/foliage.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/hash.h"
#include "core/maths.h"
#include "raster/pass.h"
#include "scenes/scene_file.h"

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

const char* technique_name(FoliageTechnique t) {
    return t == FoliageTechnique::Surface ? "surface" : t == FoliageTechnique::Texture ? "texture" : "auto";
}

FoliageTechnique parse_technique(const std::string& s) {
    if (s == "auto") return FoliageTechnique::Auto;
    if (s == "surface") return FoliageTechnique::Surface;
    if (s == "texture") return FoliageTechnique::Texture;
    throw Error("foliage technique '" + s + "' is not one of auto, surface, texture");
}

scene::Texture derive_intensity_texture(const scene::Scene& sc, const scene::Material& m) {
    constexpr int kNoiseSize = 64, kNoiseCells = 4, kMaxSide = 256;
    const scene::Texture* base = nullptr;
    if (m.base_color_texture.texture >= 0 && m.base_color_texture.texture < int(sc.textures.size()))
        base = &sc.textures[std::size_t(m.base_color_texture.texture)];
    const ImageF* src = nullptr;
    ImageF level0;  // level 0 as floats, when it is small enough to be read
    if (base && !base->empty()) {
        if (std::max(base->width(), base->height()) <= kMaxSide) {
            if (base->codes.empty()) {
                src = &base->image;
            } else {
                level0 = base->level0();
                src = &level0;
            }
        }
        for (const ImageF& level : base->mips)  // (a computed level 1 is not stored: skipped)
            if (!level.empty() && (!src || std::max(src->width(), src->height()) > kMaxSide)) src = &level;
    }
    const int w = src ? src->width() : kNoiseSize, h = src ? src->height() : kNoiseSize;
    std::vector<float> v(std::size_t(w) * h);
    std::vector<char> used(v.size(), 1);
    // Value noise: hashed lattice values, bilinear, periodic over the texture (it repeats on a leaf).
    auto noise = [&](int x, int y) {
        auto lattice = [](int i, int j) {
            return float(hash32(std::uint32_t(i % kNoiseCells) * 0x9E3779B1u + std::uint32_t(j % kNoiseCells) * 0x85EBCA6Bu + 7u) >> 8) /
                   16777216.0f;
        };
        const float fx = (float(x) + 0.5f) / float(w) * kNoiseCells, fy = (float(y) + 0.5f) / float(h) * kNoiseCells;
        const int i = int(std::floor(fx)), j = int(std::floor(fy));
        const float tx = fx - float(i), ty = fy - float(j);
        return maths::bilerp(lattice(i, j), lattice(i + 1, j), lattice(i, j + 1), lattice(i + 1, j + 1), tx, ty);
    };
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            if (!src) {
                v[i] = noise(x, y);
                continue;
            }
            float t[4] = {0, 0, 0, 1};
            for (int c = 0; c < std::min(4, src->channels()); ++c) t[c] = src->at(x, y, c);
            const float alpha = t[3];
            used[i] = m.alpha_mode != scene::AlphaMode::Mask || alpha * m.base_color.a >= m.alpha_cutoff;
            v[i] = src->channels() >= 3 ? 0.2126f * t[0] + 0.7152f * t[1] + 0.0722f * t[2] : t[0];
        }
    auto terciles = [&](float& t1, float& t2) {
        std::vector<float> s;
        for (std::size_t i = 0; i < v.size(); ++i)
            if (used[i]) s.push_back(v[i]);
        if (s.empty()) return false;
        std::sort(s.begin(), s.end());
        t1 = s[s.size() / 3], t2 = s[(2 * s.size()) / 3];
        return t1 < t2;
    };
    float t1 = 0, t2 = 0;
    if (!terciles(t1, t2)) {  // a flat texture has no detail of its own: the noise pattern
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) v[std::size_t(y) * w + x] = noise(x, y);
        terciles(t1, t2);
    }
    scene::Texture out;
    out.name = "intensity detail derived from material '" + m.name + "'";
    out.image = ImageF(w, h, 4, 0.0f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float q = v[std::size_t(y) * w + x];
            out.image.at(x, y, q < t1 ? 0 : q < t2 ? 1 : 2) = 1.0f;
            out.image.at(x, y, 3) = used[std::size_t(y) * w + x] ? 1.0f : 0.0f;  // the texels the terciles count
        }
    scene::finish_texture(out);
    return out;
}

float crown_silhouette_ratio(const scene::Scene& source, const scene::Scene& abstracted, const Exec& ex) {
    const scene::Bounds b = source.world_bounds();
    long leaves = 0, crown = 0;
    for (int k = 0; k < kCrownViews; ++k) {
        const float az = 6.28318530718f * float(k) / float(kCrownViews);
        const scene::Camera cam = scene::frame_bounds(b, 1.0f, {std::sin(az), -0.3f, -std::cos(az)});
        TrianglePass p;
        p.draw = DrawSet::Foliage;
        p.value = PassValue::Coverage;
        for (const scene::Scene* sc : {&source, &abstracted}) {
            ImageF m;
            render_triangle_pass(m, make_pass_scene(*sc, cam, kCrownViewSize, kCrownViewSize), p, ex);
            long n = 0;
            for (std::size_t i = 0; i < std::size_t(m.width()) * m.height(); ++i) n += m.data()[i] > 0.5f;
            (sc == &source ? leaves : crown) += n;
        }
    }
    return leaves > 0 ? float(double(crown) / double(leaves)) : 0.0f;
}

namespace {

//! The foliage of sc (when p.abstract): its vertices in world space (the constraint points), the
//! square roots of its triangles' areas (leaf sizes) and its materials; out's foliage counts, first
//! object and material, and the leaf share of the plant's height.
struct FoliageGather {
    std::vector<glm::vec3> points;
    std::vector<int> materials;
};
FoliageGather gather_foliage(const scene::Scene& sc, const FoliageParams& p, AbstractedScene& out) {
    FoliageGather g;
    std::vector<float> leaf;
    for (const scene::Instance& inst : sc.instances) {
        if (!p.abstract || inst.mesh < 0 || inst.mesh >= int(sc.meshes.size())) continue;
        for (const scene::Primitive& prim : sc.meshes[std::size_t(inst.mesh)].primitives) {
            if (!scene::is_foliage(sc, inst, prim)) continue;
            const std::size_t first = g.points.size();
            for (const glm::vec3& v : prim.positions) g.points.push_back(glm::vec3(inst.world * glm::vec4(v, 1.0f)));
            for (std::size_t t = 0; t + 2 < prim.indices.size(); t += 3) {
                const glm::vec3 a = g.points[first + prim.indices[t]], e1 = g.points[first + prim.indices[t + 1]] - a,
                                e2 = g.points[first + prim.indices[t + 2]] - a;
                const float area = 0.5f * glm::length(glm::cross(e1, e2));
                if (std::isfinite(area)) leaf.push_back(std::sqrt(area));
            }
            out.foliage_triangles += prim.indices.size() / 3;
            if (out.foliage_material < 0) {
                out.foliage_object_id = inst.object_id;
                out.foliage_material = prim.material;
            }
            if (std::find(g.materials.begin(), g.materials.end(), prim.material) == g.materials.end())
                g.materials.push_back(prim.material);
        }
    }
    out.foliage_points = g.points.size();
    if (!leaf.empty() && out.height > 0.0f) {
        std::nth_element(leaf.begin(), leaf.begin() + std::ptrdiff_t(leaf.size() / 2), leaf.end());
        out.leaf_share = leaf[leaf.size() / 2] / out.height;
    }
    return g;
}

//! The implicit surface around the foliage points (LD06 §4.1) into out.surface. Returns false, with
//! a warning, when it encloses too few of them (a plant never loses its foliage: the caller paints
//! the modelled leaves instead).
bool build_foliage_surface(const std::vector<glm::vec3>& points, const FoliageParams& p, const Exec& ex, AbstractedScene& out,
                           std::vector<std::string>* warnings) {
    if (!(std::isfinite(p.radius) && p.radius > 0.0f)) throw Error("foliage abstraction: r must be finite and > 0");
    out.radius = p.relative ? p.radius * out.height : p.radius;
    if (!(out.radius > 0.0f && std::isfinite(out.radius)))
        throw Error("foliage abstraction: r = " + std::to_string(p.radius) + " x plant height " + std::to_string(out.height) +
                    " is not a usable radius");
    ImplicitSurfaceParams ip;
    ip.threshold = p.threshold;
    ip.radius = out.radius;
    ip.cells_per_radius = p.cells_per_radius;
    ip.fit_inside = p.fit ? kFitInside : 0.0f;
    out.surface = build_implicit_surface(points, ip, ex);
    out.threshold = out.surface.threshold;
    if (!out.surface.indices.empty() && out.surface.inside_fraction >= kMinSurfaceInside) return true;
    if (warnings) {
        char msg[320];
        std::snprintf(msg, sizeof msg,
                      "foliage abstraction: the implicit surface at T = %g, r = %g encloses %.0f %% of the %zu foliage "
                      "vertices; painted from the modelled leaves instead (technique texture, docs/ld06.md)",
                      double(out.threshold), double(out.radius), 100.0 * double(out.surface.inside_fraction), points.size());
        warnings->push_back(msg);
    }
    out.surface = {};
    return false;
}

//! The textures the kept materials still name (pass_material dropped the rest, e.g. bark maps),
//! copied once each and renumbered: alpha tests and intensity textures need them.
void copy_named_textures(const scene::Scene& sc, scene::Scene& dst) {
    std::vector<int> index(sc.textures.size(), -1);
    for (scene::Material& m : dst.materials) {
        std::vector<scene::TextureRef*> refs = {&m.base_color_texture, &m.normal_texture, &m.intensity_texture};
        for (scene::TextureRef& c : m.wc.control_texture) refs.push_back(&c);
        for (scene::TextureRef* r : refs) {
            if (r->texture < 0 || r->texture >= int(sc.textures.size())) continue;
            int& k = index[std::size_t(r->texture)];
            if (k < 0) {
                k = int(dst.textures.size());
                dst.textures.push_back(sc.textures[std::size_t(r->texture)]);
            }
            r->texture = k;
        }
    }
}

//! The implicit surface as one more mesh, material and instance of the abstracted scene (still
//! foliage for the passes).
void add_surface_instance(const scene::Scene& sc, std::uint32_t object_id, AbstractedScene& out) {
    scene::Scene& dst = out.scene;
    scene::Material m;
    m.name = "foliage (implicit surface)";
    if (out.foliage_material >= 0 && out.foliage_material < int(sc.materials.size()))
        m.base_color = sc.materials[std::size_t(out.foliage_material)].base_color;
    m.double_sided = true;
    dst.materials.push_back(m);
    scene::Primitive prim;
    prim.positions = out.surface.positions;
    prim.normals = out.surface.normals;
    prim.indices = out.surface.indices;
    prim.material = int(dst.materials.size()) - 1;
    const int prim_material = prim.material;
    scene::Mesh mesh;
    mesh.name = "foliage (implicit surface)";
    if (dst.foliage.set) scene::FoliageSelection::add(dst.foliage.meshes, mesh.name);  // still foliage for the passes
    mesh.primitives.push_back(std::move(prim));
    dst.meshes.push_back(std::move(mesh));
    scene::Instance inst;
    inst.mesh = int(dst.meshes.size()) - 1;
    inst.object_id = object_id;
    inst.name = "foliage (implicit surface)";
    dst.instances.push_back(inst);
    out.surface_object_id = inst.object_id;
    out.surface_material = prim_material;
    out.abstracted = true;
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
    dst.cameras = sc.cameras;
    dst.lights = sc.lights;
    dst.ambient = sc.ambient;
    dst.source = sc.source;
    dst.foliage = sc.foliage;
    dst.strokes = sc.strokes;
    std::uint32_t next_id = 1;
    for (const scene::Instance& inst : sc.instances) next_id = std::max(next_id, inst.object_id + 1);
    const FoliageGather g = gather_foliage(sc, p, *out);
    if (p.abstract && g.points.empty() && warnings)
        warnings->push_back("foliage abstraction: no foliage in the scene (docs/ld06.md \"Foliage\"); drawn as modelled");
    // Which technique (docs/ld06.md "Choosing the technique").
    bool texture = p.technique == FoliageTechnique::Texture;
    if (p.technique == FoliageTechnique::Auto)
        texture = out->leaf_share >= kTextureLeafShare || out->foliage_triangles < kTextureMaxTriangles;
    if (!g.points.empty() && !texture && !build_foliage_surface(g.points, p, ex, *out, warnings)) texture = true;
    const bool surface = !g.points.empty() && !texture;
    out->texture_technique = !g.points.empty() && texture;
    // Every instance, without its foliage where the surface replaces it.
    for (const scene::Instance& inst : sc.instances) {
        if (inst.mesh < 0 || inst.mesh >= int(sc.meshes.size())) continue;
        const scene::Mesh& mesh = sc.meshes[std::size_t(inst.mesh)];
        scene::Mesh kept;
        kept.name = mesh.name;
        for (const scene::Primitive& prim : mesh.primitives)
            if (!(surface && scene::is_foliage(sc, inst, prim))) kept.primitives.push_back(prim);
        if (kept.primitives.empty()) continue;
        dst.meshes.push_back(std::move(kept));
        scene::Instance ki = inst;
        ki.mesh = int(dst.meshes.size()) - 1;
        dst.instances.push_back(ki);
    }
    if (keeps_masked || out->texture_technique) copy_named_textures(sc, dst);
    if (out->texture_technique) {
        for (const int mi : g.materials) {
            if (mi < 0 || mi >= int(dst.materials.size()) || dst.materials[std::size_t(mi)].intensity_texture.texture >= 0) continue;
            scene::Material& m = dst.materials[std::size_t(mi)];
            dst.textures.push_back(derive_intensity_texture(sc, sc.materials[std::size_t(mi)]));
            m.intensity_texture.texture = int(dst.textures.size()) - 1;
            if (m.base_color_texture.texture >= 0) m.intensity_texture.sampler = m.base_color_texture.sampler;
        }
        return out;
    }
    if (!surface) return out;
    add_surface_instance(sc, next_id, *out);
    if (p.technique == FoliageTechnique::Auto) {
        // A sparse crown (light, conifer): the surface would paint its envelope, far more than the
        // leaves; the texture technique paints the leaves (docs/ld06.md "Choosing the technique").
        out->crown_ratio = crown_silhouette_ratio(sc, dst, ex);
        if (out->crown_ratio > kMaxCrownRatio) {
            FoliageParams tp = p;
            tp.technique = FoliageTechnique::Texture;
            auto t = std::const_pointer_cast<AbstractedScene>(abstract_foliage(sc, tp, ex, warnings));
            t->crown_ratio = out->crown_ratio;
            return t;
        }
    }
    return out;
}

scene::LayerTable abstracted_layer_table(const scene::Scene& source, const AbstractedScene& a) {
    scene::LayerTable t = scene::build_layer_table(source);
    if (a.abstracted) t.assign(a.surface_object_id, a.surface_material, t.of(a.foliage_object_id, a.foliage_material));
    return t;
}

}  // namespace aq::raster
