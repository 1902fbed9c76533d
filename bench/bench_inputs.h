// bench/bench_inputs.h — inputs shared by the C++ stage benchmarks (bench/stylize_bench.cpp) and
// their GLSL twins (bench/reference_bench.cpp), so both sides process the same data; and what the
// frame-loop benchmarks share.
#pragma once

#include "core/image.h"

namespace aq::bench {

//! The paper of the single-stage benchmarks at w x h: the WC18 preset's paper (the rough 2k scan
//! the WC presets use), prepared once per size. With the flat paper, the stages that read it
//! (substrate distortion and lighting, pigment application) ran their identity paths (zero
//! offsets, constant height) and the benchmarks timed little more than a copy; every stage/* figure
//! in docs/performance.md is with this paper.
const ImageF& stage_paper(int w, int h);

//! Frames a frame-loop benchmark runs before it is timed (pipeline/*, profile/*, BM_Ld06Frame/*):
//! two, because with steps in place (stylize::RunOptions::in_place) the images a frame recycles
//! settle only in its second run — the first has none to recycle, so the second still allocates
//! some anew, and one warm-up left their first-touch page clearing in the timed frames.
inline constexpr int kWarmUpFrames = 2;

}  // namespace aq::bench
