// raster/foliage.h — LD06 §4.1: a plant whose foliage is replaced by the implicit surface of its
// leaf vertices (raster/implicit_surface.h), the scene the LD06 raster passes draw. Trunk and
// branches stay as modelled. docs/ld06.md "Implicit surface".
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/cache.h"
#include "core/exec.h"
#include "raster/implicit_surface.h"
#include "scenes/layers.h"
#include "scenes/scene.h"

namespace aq::raster {

//! How LD06 paints a plant's foliage: the implicit surface with particles (§4.1-4.2), or the
//! modelled leaves with intensity-texture detail (§4.3). Auto decides from the geometry.
enum class FoliageTechnique { Auto = 0, Surface = 1, Texture = 2 };

//! "auto" | "surface" | "texture"; parse throws aq::Error naming the known values.
const char* technique_name(FoliageTechnique t);
FoliageTechnique parse_technique(const std::string& s);

struct FoliageParams {
    bool abstract = true;               //!< false: passes draw the modelled leaves
    float threshold = kLd06Threshold;   //!< T of eq. 7
    //! r of eq. 6; a fraction of the plant height h when `relative` (LD06: "the parameters scale
    //! with the tree height"), else world units.
    float radius = kLd06RadiusPerHeight;
    bool relative = true;
    int cells_per_radius = 2;
    //! Fit T to the plant (ImplicitSurfaceParams::fit_inside = kFitInside) instead of using
    //! `threshold`: the surface encloses that share of the foliage's vertices whatever its density.
    bool fit = false;
    //! Surface by default (what a pipeline's "foliage" block asked for before techniques existed);
    //! the ld06 preset says "auto".
    FoliageTechnique technique = FoliageTechnique::Surface;
};

//! Share of the foliage vertices a fitted surface encloses (docs/ld06.md "Fitting the
//! abstraction": the painted crown then covers >= 85 % of the modelled foliage's silhouette).
inline constexpr float kFitInside = 0.9f;
//! Auto technique: LD06 §4.3's intensity textures ("small plants or plants with few large
//! leaves") when the median leaf (square root of a foliage triangle's area) is at least this
//! share of the plant height, or the foliage has fewer than kTextureMaxTriangles triangles.
inline constexpr float kTextureLeafShare = 0.045f;
inline constexpr std::size_t kTextureMaxTriangles = 500;
//! A surface enclosing less than this share of the foliage's vertices (a scene file's fixed T far
//! above the plant's density) is replaced by the texture technique, with a warning.
inline constexpr float kMinSurfaceInside = 0.5f;
//! Auto technique, sparse crowns: the implicit surface's silhouette over the modelled foliage's,
//! summed over kCrownViews views around the plant (kCrownViewSize² coverage passes); above
//! kMaxCrownRatio the crown is too sparse for the surface and gets the texture technique.
inline constexpr int kCrownViews = 4, kCrownViewSize = 128;
inline constexpr float kMaxCrownRatio = 1.0f;

//! The scene LD06 passes draw, with what the abstraction measured.
struct AbstractedScene {
    scene::Scene scene;        //!< trunk as modelled + one foliage instance holding the surface
    ImplicitSurface surface;   //!< world space (empty when nothing was abstracted)
    float height = 0;          //!< h: the world bounds' extent along +Y (glTF's up axis)
    float radius = 0;          //!< r used, world units
    std::size_t foliage_points = 0, foliage_triangles = 0;
    float leaf_share = 0;      //!< median foliage triangle's sqrt(area) / h (the technique rule)
    float threshold = 0;       //!< T used (fitted or given)
    float crown_ratio = 0;     //!< auto technique: crown_silhouette_ratio of the surface (0: not measured)
    bool abstracted = false;   //!< false: no foliage, or abstraction off (scene is a plain copy)
    //! Texture: foliage drawn as modelled, every foliage material with an intensity texture
    //! (its own, else one derived from its base colour: derive_intensity_texture); the particle
    //! pass then renders that detail (PassScene::foliage_detail).
    bool texture_technique = false;
    //! The surface's draw (object_id, material) and the first foliage primitive it replaces in the
    //! source scene: the surface belongs to that primitive's LD06 layer (scenes/layers.h).
    std::uint32_t surface_object_id = 0, foliage_object_id = 0;
    int surface_material = -1, foliage_material = -1;
};

//! LD06 §4.3 detail maps made from a leaf material when it has none: the base colour texture's
//! luminance (else a value-noise pattern of 4 x 4 cells) over the texels that pass the alpha test,
//! split at its terciles into dark (R), medium (G) and bright (B): each texel is 1 in exactly one
//! channel; alpha is 1 where the texel passes the material's alpha test (the terciles' texels), 0
//! elsewhere. 64 x 64 texels without a base texture; else the first mip level of at most 256 px.
scene::Texture derive_intensity_texture(const scene::Scene& sc, const scene::Material& m);

//! The foliage's silhouette in `abstracted` (its implicit surface) over its silhouette as modelled
//! in `source`, coverage pixels summed over kCrownViews views from around and slightly above the
//! plant (frame_bounds, kCrownViewSize² px). 0 when `source` has no foliage to see.
float crown_silhouette_ratio(const scene::Scene& source, const scene::Scene& abstracted, const Exec& ex = {});

//! Splits `sc` into trunk and foliage (scene::is_foliage), builds the implicit surface of the
//! foliage vertices (in world space) and returns the trunk plus the surface as a foliage instance
//! (material "foliage (implicit surface)": opaque, double-sided, the first foliage material's base
//! colour). No foliage: the scene unchanged and a warning. An empty surface (T above the field)
//! is an error naming T and r. Throws aq::Error for invalid parameters or grid limits.
std::shared_ptr<const AbstractedScene> abstract_foliage(const scene::Scene& sc, const FoliageParams& p,
                                                        const Exec& ex = {},
                                                        std::vector<std::string>* warnings = nullptr);

//! Every parameter of `p` as text (floats exact, "%a"): the parameters' part of a cache key.
std::string foliage_params_key(const FoliageParams& p);

//! abstract_foliage through the content cache (core/cache.h): the entry keyed by `scene_key` (what
//! the scene's content and every change made to it since loading hash to, scenes/scene_cache.h)
//! and the parameters; `store` null or `scene_key` empty: abstract_foliage. The same result and
//! warnings either way; `notes` receives why an entry was not used or stored.
std::shared_ptr<const AbstractedScene> abstract_foliage_cached(const scene::Scene& sc, const FoliageParams& p, const Exec& ex,
                                                               std::vector<std::string>* warnings, const cache::Store* store,
                                                               const std::string& scene_key, std::vector<std::string>* notes);

//! The layers of the scene an AbstractedScene draws: scene::build_layer_table of the source scene,
//! with the implicit surface in the layer of the foliage it replaces.
scene::LayerTable abstracted_layer_table(const scene::Scene& source, const AbstractedScene& a);

}  // namespace aq::raster
