// stylize/passes/triangle_passes.h — the LD06 raster passes that draw the scene's triangles
// (raster/pass.h): depth, lighting, shadow intensity and intensity masks, registered by name so
// pipeline files can declare them beside the image stages (docs/ld06.md "Raster passes").
#pragma once

#include "stylize/stage.h"

namespace aq::stylize {

void register_triangle_passes(Registry& r);

}  // namespace aq::stylize
