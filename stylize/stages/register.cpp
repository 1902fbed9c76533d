// stylize/stages/register.cpp — the one list of built-in stages, in pipeline order (the order of
// stylize/presets/mnpr.json; spec §4.1-4.10). Each stage file provides register_<stage>(Registry&)
// declared in its header; the first variant a stage registers is its default.
#include "stylize/stage.h"
#include "stylize/stages/adjust.h"
#include "stylize/stages/bleed.h"
#include "stylize/stages/bleed_blend.h"
#include "stylize/stages/color_ramp.h"
#include "stylize/stages/edge_blur.h"
#include "stylize/stages/edge_darken.h"
#include "stylize/stages/edge_detect.h"
#include "stylize/stages/extend_edges.h"
#include "stylize/stages/gaps_overlaps.h"
#include "stylize/stages/gaussian_blur.h"
#include "stylize/stages/glaze.h"
#include "stylize/stages/id_layers.h"
#include "stylize/stages/layer_wash.h"
#include "stylize/stages/pigment_apply.h"
#include "stylize/stages/pigment_density.h"
#include "stylize/stages/shadow_layer.h"
#include "stylize/stages/stroke_ink.h"
#include "stylize/stages/substrate_distort.h"
#include "stylize/stages/substrate_light.h"

namespace aq::stylize {

void register_builtin_stages(Registry& r) {
    register_adjust(r);
    register_edge_detect(r);
    register_pigment_density(r);
    register_bleed(r);
    register_edge_blur(r);
    register_extend_edges(r);
    register_bleed_blend(r);
    register_edge_darken(r);
    register_gaps_overlaps(r);
    register_pigment_apply(r);
    register_substrate_distort(r);
    register_substrate_light(r);
    // LD06 (docs/ld06.md), in the order of stylize/presets/ld06.json
    register_gaussian_blur(r);
    register_id_layers(r);
    register_layer_wash(r);
    register_color_ramp(r);
    register_glaze(r);
    register_shadow_layer(r);
    register_stroke_ink(r);
}

}  // namespace aq::stylize
