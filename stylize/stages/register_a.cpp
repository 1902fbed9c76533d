// stylize/stages/register_a.cpp — registers stage group A (adjust, edges, pigment density, blurs,
// bleeding blend). Each stage file provides a register_<stage>(Registry&) declared in its header.
#include "stylize/stage.h"
#include "stylize/stages/adjust.h"
#include "stylize/stages/bleed.h"
#include "stylize/stages/bleed_blend.h"
#include "stylize/stages/edge_blur.h"
#include "stylize/stages/edge_detect.h"
#include "stylize/stages/extend_edges.h"
#include "stylize/stages/pigment_density.h"

namespace aq::stylize {
void register_stages_a(Registry& r) {
    register_adjust(r);
    register_edge_detect(r);
    register_pigment_density(r);
    register_bleed(r);
    register_edge_blur(r);
    register_extend_edges(r);
    register_bleed_blend(r);
}
}  // namespace aq::stylize
