// stylize/stages/blur.h — separable 1-D convolution shared by the blur stages (spec §4.4), in the
// "delta" form that keeps constant images exactly constant:
//   out = s + sum_{a=-r..r, ascending} w[a + r] * (src(x + a) - s)
// which equals sum_a w[a] * src(x + a) for normalised w. H pass then V pass. The reference
// traversal evaluates it per pixel through the border rule; the fast one per row with padded rows
// (H) or row pointers (V), channels interleaved and innermost so the loop vectorises; the per
// value operation sequence is identical, so the results are bit-identical.
#pragma once

#include <cstddef>
#include <vector>

#include "core/exec.h"
#include "core/image.h"
#include "stylize/stages/toolkit.h"

namespace aq::stylize {

//! The delta-form tap sum of every blur here, for n values: o[i] = acc with acc = s[i], then
//! acc = acc + wt[a] * (d[a][i] - s[i]) for a = 0..taps-1 in order (the reference loops'
//! operations), eight values at a time with the accumulator in registers across the taps.
//! d[a] points at tap a's values aligned with s (a shifted row, or another row).
inline void accumulate_taps(float* __restrict o, const float* __restrict s, const float* const* __restrict d, const float* wt, int taps, std::size_t n) {
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        const toolkit::v8f e0 = toolkit::load8(s + i);
        toolkit::v8f acc = e0;
        for (int a = 0; a < taps; ++a) acc = acc + wt[a] * (toolkit::load8(d[a] + i) - e0);
        toolkit::store8(o + i, acc);
    }
    for (; i < n; ++i) {
        const float e0 = s[i];
        float acc = e0;
        for (int a = 0; a < taps; ++a) acc = acc + wt[a] * (d[a][i] - e0);
        o[i] = acc;
    }
}

//! dst = V(H(src)); w has 2r + 1 normalised weights; any channel count; dst same size as src.
void separable_blur(ImageF& dst, const ImageF& src, const std::vector<float>& w, Border border,
                    const Exec& ex = {});

}  // namespace aq::stylize
