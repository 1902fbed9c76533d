// stylize/passes/register.cpp — the one list of built-in raster passes (builtin_pass_registry),
// in the order an LD06 frame runs them (../shared/spec/ld06.md). The first variant a pass
// registers is its default.
#include "stylize/passes/particle_pass.h"
#include "stylize/passes/stroke_pass.h"
#include "stylize/passes/triangle_passes.h"
#include "stylize/stage.h"

namespace aq::stylize {

void register_builtin_passes(Registry& r) {
    register_triangle_passes(r);
    register_particle_pass(r);
    register_stroke_pass(r);
}

}  // namespace aq::stylize
