// stylize/scene_inputs.cpp — see scene_inputs.h.
#include "stylize/scene_inputs.h"

#include "stylize/pipeline.h"

namespace aq::stylize {

const scene::LayerTable& SceneInputs::layers() const {
    if (!layers_) layers_ = scene::build_layer_table(scene_);
    return *layers_;
}

int SceneInputs::foliage_layer() const {
    if (foliage_layer_) return *foliage_layer_;
    int layer = -1;
    for (const scene::Instance& inst : scene_.instances) {
        if (inst.mesh < 0 || inst.mesh >= int(scene_.meshes.size()) || layer >= 0) continue;
        for (const scene::Primitive& prim : scene_.meshes[std::size_t(inst.mesh)].primitives)
            if (layer < 0 && scene::is_foliage(scene_, inst, prim)) layer = layers().of(inst.object_id, prim.material);
    }
    foliage_layer_ = layer;
    return layer;
}

void apply_scene_inputs(Pipeline& p, const SceneInputs& in) {
    for (std::size_t i = 0; i < p.steps.size(); ++i) {
        const ResolvedStep r = resolve_step(p, i);
        if (!r.variant->scene_params) continue;
        const std::string id = p.steps[i].id.empty() ? p.steps[i].stage : p.steps[i].id;
        for (const SceneValue& v : r.variant->scene_params(r.params, in)) set_param_value(p, id, v.param, v.value, v.source);
    }
}

}  // namespace aq::stylize
