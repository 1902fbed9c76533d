// scenes/leaf_strokes.h — LD06 §4.4 hand-made strokes "duplicated over every leaf sharing a
// texture": a stroke drawn once in a material's texture space (UV polyline) is placed on every
// leaf — every connected group of triangles (shared vertex indices) — of the primitives using that
// material, through each triangle's UVs (docs/ld06.md "Strokes").
#pragma once

#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "scenes/scene.h"

namespace aq::scene {

//! A stroke in texture space (scene files: "strokes": [{"uv": [[u, v], ...], "material": NAME}]).
struct UvStroke {
    std::vector<glm::vec2> uv;  //!< TEXCOORD_0 space, >= 2 points
    std::string material;       //!< every leaf of this material gets a copy
    bool light_dependent = false;
};

//! World-space strokes (with the surface's normals, for the n·v fade) of every UvStroke on every
//! leaf, in order: stroke, instance, primitive, leaf (lowest triangle index), point. A point maps
//! through the first triangle of its leaf whose UV triangle contains it (barycentric, inclusive
//! edges); points outside every triangle split the stroke; runs of fewer than two points are
//! dropped. Throws aq::Error naming the limits when the copies exceed max_strokes strokes or
//! max_points points in all (nothing is allocated beyond them), or when the placement would test
//! more than *work_budget (point, triangle) pairs (checked before any work; the pairs tested are
//! subtracted from it), so a hostile file cannot make loading hang.
std::vector<Stroke> place_uv_strokes(const Scene& sc, const std::vector<UvStroke>& strokes, std::size_t max_strokes,
                                     std::size_t max_points, std::size_t* work_budget);

//! (point, triangle) pairs a scene file's texture-space strokes may test in all while loading.
inline constexpr std::size_t kMaxUvStrokeWork = 200'000'000;

}  // namespace aq::scene
