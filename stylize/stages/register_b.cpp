// stylize/stages/register_b.cpp — registers stage group B (edge darkening, gaps & overlaps,
// pigment application, substrate distortion and lighting), in pipeline order (spec §4.6-4.10).
// The first variant of each stage is its default.
#include "stylize/stage.h"
#include "stylize/stages/edge_darken.h"
#include "stylize/stages/gaps_overlaps.h"
#include "stylize/stages/pigment_apply.h"
#include "stylize/stages/substrate.h"

namespace aq::stylize {
void register_stages_b(Registry& r) {
    register_edge_darken(r);
    register_gaps_overlaps(r);
    register_pigment_apply(r);
    register_substrate(r);
}
}  // namespace aq::stylize
