// stylize/scene_inputs.h — what of the scene being rendered a stage may take as parameter values
// (StageVariant::scene_params; docs/stylize.md "Scene inputs"). The render job builds one
// SceneInputs and apply_scene_inputs fills every step whose variant declares such values, so the
// job names no stage: the automatic depth range of adjust and the LD06 layer colours of color_ramp
// are declarations of those stages.
#pragma once

#include <optional>
#include <utility>

#include "scenes/layers.h"
#include "scenes/scene.h"

namespace aq::stylize {

struct Pipeline;

class SceneInputs {
public:
    //! `framed_depth_range`: the clip range (near, far) of a camera the scene file asked to be
    //! framed automatically, which hugs the scene's bounding sphere; empty for a placed camera.
    //! `sc` must outlive this object.
    SceneInputs(const scene::Scene& sc, std::optional<std::pair<float, float>> framed_depth_range)
        : scene_(sc), framed_depth_range_(framed_depth_range) {}
    const std::optional<std::pair<float, float>>& framed_depth_range() const { return framed_depth_range_; }
    //! The scene's layers (scene::build_layer_table), built on first use.
    const scene::LayerTable& layers() const;
    //! The layer of the first foliage primitive in instance order, or -1.
    int foliage_layer() const;

private:
    const scene::Scene& scene_;
    std::optional<std::pair<float, float>> framed_depth_range_;
    mutable std::optional<scene::LayerTable> layers_;
    mutable std::optional<int> foliage_layer_;
};

//! Sets, on every step whose variant has StageVariant::scene_params, the values it takes from
//! `in` (set_param_value, so each is range-checked and an error names where it came from). The
//! render job calls it before the scene file's style values and --set, which override it.
void apply_scene_inputs(Pipeline& p, const SceneInputs& in);

}  // namespace aq::stylize
