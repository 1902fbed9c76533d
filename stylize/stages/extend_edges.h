// stylize/stages/extend_edges.h — stage "extend_edges", variant mnpr: the extended edges that
// gaps & overlaps marches along (WC18 §3.2; MNPR quadSeparable edgeBlur, "GAPS AND OVERLAPS
// GRADIENT"; spec §4.4).
#pragma once

#include <vector>

#include "core/exec.h"
#include "core/image.h"
#include "stylize/kernels.h"
#include "stylize/stage.h"

namespace aq::stylize {

//! Kernel width: WC18 uses m = 5 ("a linear filtering kernel (m = 5)"), MNPR gGapsOverlapsKernel 3.
inline constexpr int kGapsOverlapsWidthPaper = 5;
inline constexpr int kGapsOverlapsWidthMnpr = 3;

struct ExtendEdgesParams {
    int width = kGapsOverlapsWidthMnpr;  //!< W [1, 32]: taps |l| < W, weights 1 - |l|/W, normalised
    Border border = Border::Clamp;
};

//! The gamma of one blurred edge value b (MNPR's two powers as one): b^((1/b)(2/W)) for b > 0,
//! else 0 (b <= 0 or NaN).
inline float extend_edges_gamma(float b, float two_over_w) {
    return b > 0.0f ? pow_c(b, (1.0f / b) * two_over_w) : 0.0f;
}

//! b = V(H(edges)) with the linear kernel, then (MNPR) b = b^(1/b) ("get rid of weak gradients")
//! and b = b^(2/W) ("adjust gamma depending on kernel size"), evaluated as the single power
//! b^((1/b)(2/W)) (equal but for rounding); b <= 0 or NaN gives 0.
//! edges: 1 channel; dst: 1 channel, same size.
void extend_edges(ImageF& dst, const ImageF& edges, const ExtendEdgesParams& p, const Exec& ex = {});

//! Normalised linear weights for taps -(W-1)..(W-1).
std::vector<float> linear_weights(int width);

//! The gamma's fast schedule (extend_edges.schedule.cpp): extend_edges_gamma(v, g) of every value of
//! the blurred edges d, in place, for Traversal::Fast.
void extend_edges_gamma_fast(ImageF& d, float g, const Exec& ex);

void register_extend_edges(Registry& r);

}  // namespace aq::stylize
