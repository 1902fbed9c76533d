// raster/foliage.h — LD06 §4.1: a plant whose foliage is replaced by the implicit surface of its
// leaf vertices (raster/implicit_surface.h), the scene the LD06 raster passes draw. Trunk and
// branches stay as modelled. docs/ld06.md "Implicit surface".
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/exec.h"
#include "raster/implicit_surface.h"
#include "scenes/layers.h"
#include "scenes/scene.h"

namespace aq::raster {

struct FoliageParams {
    bool abstract = true;               //!< false: passes draw the modelled leaves
    float threshold = kLd06Threshold;   //!< T of eq. 7
    //! r of eq. 6; a fraction of the plant height h when `relative` (LD06: "the parameters scale
    //! with the tree height"), else world units.
    float radius = kLd06RadiusPerHeight;
    bool relative = true;
    int cells_per_radius = 2;
    //! When the summed density never reaches T (sparse foliage, e.g. a bare glTF bush under the
    //! ld06 preset's dense-tree T): halve T until the surface is not empty (at most
    //! kFitThresholdSteps times) and report the T used as a warning, instead of failing.
    bool fit_threshold = false;
};

inline constexpr int kFitThresholdSteps = 12;

//! The scene LD06 passes draw, with what the abstraction measured.
struct AbstractedScene {
    scene::Scene scene;        //!< trunk as modelled + one foliage instance holding the surface
    ImplicitSurface surface;   //!< world space (empty when nothing was abstracted)
    float height = 0;          //!< h: the world bounds' extent along +Y (glTF's up axis)
    float radius = 0;          //!< r used, world units
    std::size_t foliage_points = 0, foliage_triangles = 0;
    bool abstracted = false;   //!< false: no foliage, or abstraction off (scene is a plain copy)
    //! The surface's draw (object_id, material) and the first foliage primitive it replaces in the
    //! source scene: the surface belongs to that primitive's LD06 layer (scenes/layers.h).
    std::uint32_t surface_object_id = 0, foliage_object_id = 0;
    int surface_material = -1, foliage_material = -1;
};

//! Splits `sc` into trunk and foliage (scene::is_foliage), builds the implicit surface of the
//! foliage vertices (in world space) and returns the trunk plus the surface as a foliage instance
//! (material "foliage (implicit surface)": opaque, double-sided, the first foliage material's base
//! colour). No foliage: the scene unchanged and a warning. An empty surface (T above the field)
//! is an error naming T and r. Throws aq::Error for invalid parameters or grid limits.
std::shared_ptr<const AbstractedScene> abstract_foliage(const scene::Scene& sc, const FoliageParams& p,
                                                        const Exec& ex = {},
                                                        std::vector<std::string>* warnings = nullptr);

//! The layers of the scene an AbstractedScene draws: scene::build_layer_table of the source scene,
//! with the implicit surface in the layer of the foliage it replaces.
scene::LayerTable abstracted_layer_table(const scene::Scene& source, const AbstractedScene& a);

}  // namespace aq::raster
