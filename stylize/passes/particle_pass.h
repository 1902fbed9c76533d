// stylize/passes/particle_pass.h — the LD06 particle pass (raster/particles.h) as registry entries.
#pragma once

#include "stylize/stage.h"

namespace aq::stylize {

void register_particle_pass(Registry& r);

}  // namespace aq::stylize
