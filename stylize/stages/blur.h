// stylize/stages/blur.h — separable 1-D convolution shared by the blur stages (spec §4.4), in the
// "delta" form that keeps constant images exactly constant:
//   out = s + sum_{a=-r..r, ascending} w[a + r] * (src(x + a) - s)
// which equals sum_a w[a] * src(x + a) for normalised w. H pass then V pass. The reference
// traversal evaluates it per pixel through the border rule; the fast one per row with padded rows
// (H) or row pointers (V), channels interleaved and innermost so the loop vectorises; the per
// value operation sequence is identical, so the results are bit-identical.
#pragma once

#include <vector>

#include "core/exec.h"
#include "core/image.h"

namespace aq::stylize {

//! dst = V(H(src)); w has 2r + 1 normalised weights; any channel count; dst same size as src.
void separable_blur(ImageF& dst, const ImageF& src, const std::vector<float>& w, Border border,
                    const Exec& ex = {});

}  // namespace aq::stylize
