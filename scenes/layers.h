// scenes/layers.h — LD06 §3.1 watercolor layers: which primitives form one layer ("objects having
// the same identifier", the ID layers) and the colour ramp each layer is painted with. Built once
// per render from the scene; the raster pass "layer_id" writes a layer's index, the stage
// "color_ramp" receives its colours as parameters (docs/ld06.md "Layers").
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "scenes/scene.h"

namespace aq::scene {

//! Ours: LD06's object ramp runs "from the object colour to a slightly darker tone"; the dark end
//! is the colour times this factor unless the scene file gives one.
inline constexpr float kLayerDarkTone = 0.55f;
//! At most this many "layers" entries in a scene file (each may name many primitives).
inline constexpr std::size_t kMaxLayerSpecs = 1024;
//! Texels averaged for a material's default layer colour (a regular subsample beyond it).
inline constexpr std::size_t kLayerColorSamples = 1u << 16;

struct Layer {
    std::string name;
    glm::vec3 color{0.5f}, dark{0.5f * kLayerDarkTone};  //!< display values in [0, 1]
    float alpha = 1.0f;
};

class LayerTable {
public:
    std::vector<Layer> layers;
    //! Index of the layer of a draw (instance object_id, material index), or -1.
    int of(std::uint32_t object_id, int material) const {
        const auto it = map_.find({object_id, material});
        return it == map_.end() ? -1 : it->second;
    }
    void assign(std::uint32_t object_id, int material, int layer) { map_[{object_id, material}] = layer; }

private:
    std::map<std::pair<std::uint32_t, int>, int> map_;
};

//! The mean colour of a material as a display value: base colour factor times the mean of its base
//! colour texture (texels passing the alpha test for MASK materials; at most kLayerColorSamples
//! texels, a regular subsample), encoded to sRGB when the material's colours are linear (glTF).
glm::vec3 material_display_color(const Scene& sc, int material);

//! Layers of a scene: the scene file's groups first (Scene::layers, in file order; a primitive
//! belongs to the first group naming its node, mesh or material), then one layer per material of
//! every primitive left, in first-use order (instances, then primitives). A group without a colour
//! takes its first member's material colour; dark defaults to kLayerDarkTone x colour.
LayerTable build_layer_table(const Scene& sc);

}  // namespace aq::scene
