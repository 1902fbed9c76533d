// scenes/scene_archive.h — every field of the scene types, for the content cache (core/archive.h).
//
// One `fields` function per struct lists its members in declaration order; the trivially
// copyable members (glm values, enums, TextureRef, WatercolorMaterial, Light) are their bytes.
// A member added to one of these structs must be added here: the size checks below stop the
// build until it is (their values are the x86-64 libstdc++ sizes of the structs as archived).
#pragma once

#include "core/archive.h"
#include "core/input.h"
#include "scenes/scene_file.h"

namespace aq {

template <class Ar>
void fields(Ar& ar, DecodeBudget& b) {
    ar(b.bytes_left, b.what);
}
template <class Ar>
void fields(Ar& ar, InputRecord& r) {
    ar(r.path, r.bytes, r.sha256);
}

namespace scene {

static_assert(sizeof(Texture) == 4248 && sizeof(TextureCodes) == 4128 && sizeof(Material) == 392 &&
                  sizeof(WatercolorMaterial) == 232 && sizeof(Primitive) == 296 && sizeof(Mesh) == 56 &&
                  sizeof(Instance) == 104 && sizeof(Camera) == 128 && sizeof(FoliageSelection) == 80 &&
                  sizeof(Stroke) == 56 && sizeof(LayerSpec) == 144 && sizeof(Scene) == 384 && sizeof(SceneDesc) == 800,
              "a scene type changed: archive its new members in scenes/scene_archive.h, then update these sizes");
static_assert(archive::kRaw<TextureRef> && archive::kRaw<WatercolorMaterial> && archive::kRaw<Light> && archive::kRaw<Sampler>);

template <class Ar>
void fields(Ar& ar, TextureCodes& c) {
    ar(c.width, c.height, c.codes, c.lut);
}
template <class Ar>
void fields(Ar& ar, Texture& t) {
    ar(t.name, t.image, t.srgb, t.codes, t.mips, t.level1_computed);
}
template <class Ar>
void fields(Ar& ar, Material& m) {
    ar(m.name, m.base_color, m.base_color_texture, m.normal_texture, m.alpha_mode, m.alpha_cutoff, m.double_sided,
       m.linear_color, m.wc, m.intensity_texture);
}
template <class Ar>
void fields(Ar& ar, Primitive& p) {
    ar(p.positions, p.normals, p.tangents, p.uv0, p.colors, p.control, p.indices, p.material, p.attributes);
}
template <class Ar>
void fields(Ar& ar, Mesh& m) {
    ar(m.name, m.primitives);
}
template <class Ar>
void fields(Ar& ar, Instance& i) {
    ar(i.mesh, i.world, i.object_id, i.name);
}
template <class Ar>
void fields(Ar& ar, Camera& c) {
    ar(c.name, c.view, c.orthographic, c.yfov, c.xmag, c.ymag, c.znear, c.zfar, c.aspect);
}
template <class Ar>
void fields(Ar& ar, FoliageSelection& f) {
    ar(f.set, f.nodes, f.meshes, f.materials);
}
template <class Ar>
void fields(Ar& ar, Stroke& s) {
    ar(s.points, s.normals, s.light_dependent);
}
template <class Ar>
void fields(Ar& ar, LayerSpec& l) {
    ar(l.name, l.nodes, l.meshes, l.materials, l.color, l.dark, l.alpha);
}
template <class Ar>
void fields(Ar& ar, Scene& s) {
    ar(s.meshes, s.instances, s.materials, s.textures, s.cameras, s.lights, s.ambient, s.warnings, s.source, s.foliage,
       s.strokes, s.layers, s.decode_budget);
}
template <class Ar>
void fields(Ar& ar, SceneDesc& d) {
    ar(d.scene, d.camera, d.style, d.style_set, d.style_variant, d.width, d.height, d.fps, d.paper, d.substrate_color,
       d.substrate_color_set, d.camera_auto, d.auto_view_dir, d.auto_yfov, d.auto_aspect, d.control_rules,
       d.foliage_threshold, d.foliage_radius, d.foliage_relative, d.foliage_cells_per_radius, d.foliage_technique);
}

}  // namespace scene
}  // namespace aq
