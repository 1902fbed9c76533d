// stylize/passes/stroke_pass.h — the LD06 stroke pass (raster/strokes.h) as registry entries.
#pragma once

#include "stylize/stage.h"

namespace aq::stylize {

void register_stroke_pass(Registry& r);

}  // namespace aq::stylize
