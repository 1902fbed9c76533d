// stylize/schedule/plan.h — the schedule of a compiled pipeline: which consecutive steps run as one
// (a registered Fusion), which compute over their dead input's image (in place), and which run
// band by band (row groups; bands.h). Decided once, when the pipeline compiles; run_pipeline
// follows the plan under RunOptions::fuse, in_place and row_groups. Every choice keeps the bytes
// of step by step (docs/stylize.md "Row groups").
#pragma once

#include "stylize/pipeline.h"

namespace aq::stylize::schedule {

//! Fills c.fused_with_next, c.in_place and c.row_groups (in that order: a fused step is neither in
//! place nor in a row group; an in-place step with a row halo runs alone) from c.steps,
//! c.last_read, c.produced and c.output.
void plan(CompiledPipeline& c);

}  // namespace aq::stylize::schedule
