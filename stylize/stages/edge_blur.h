// stylize/stages/edge_blur.h — stage "edge_blur": the blurred input of edge darkening (spec §4.4).
//   wc17  WC17 §3.3: "convolving the equivalent of a 5x5 Gaussian kernel (sigma = 1)" of the colour
//         image, at half resolution (bilinear downsample, kernels.h texel_coord convention);
//         the DoG edge darkening (WC17 eq. 8) upsamples it the same way.
//   wc18  WC18 §3.1: Gaussian blur of the Sobel edges with a per-pixel width painted in
//         ctrl.edge.g (MNPR quadSeparable edgeBlur): K = max(1, int(W + lerp(0, 3W, ctrl))),
//         sigma = K / 2, taps |o| < K, weights normalised; W = 3 (MNPR gEdgeDarkeningKernel).
#pragma once

#include <cstddef>
#include <vector>

#include "core/exec.h"
#include "core/image.h"
#include "core/simd.h"
#include "stylize/stage.h"

namespace aq::stylize {

inline constexpr int kEdgeBlurWc17Radius = 2;       //!< 5x5 kernel (WC17 §3.3)
inline constexpr float kEdgeBlurWc17Sigma = 1.0f;   //!< sigma = 1 (WC17 §3.3)
inline constexpr int kEdgeBlurWidth = 3;            //!< MNPR gEdgeDarkeningKernel (WC18 W)

struct EdgeBlurWc17Params {
    int radius = kEdgeBlurWc17Radius;    //!< [1, 16]
    float sigma = kEdgeBlurWc17Sigma;    //!< [0.1, 16]
    bool half_res = true;                //!< WC17 intermediates are half resolution
    Border border = Border::Clamp;
};

struct EdgeBlurWc18Params {
    int width = kEdgeBlurWidth;  //!< W [1, 16]; painted width ctrl.edge.g in [-1, 1] scales K up to 4W
    Border border = Border::Clamp;
};

//! dst: 4 channels, half (ceil) or full size. color: 4 channels.
void edge_blur_wc17(ImageF& dst, const ImageF& color, const EdgeBlurWc17Params& p, const Exec& ex = {});

//! Per-pixel kernel size K(x, y) from ctrl.edge.g at the output pixel in both passes (as MNPR).
//! K is computed with NaN/overflow guards (NaN control -> K = 1, K <= 4W).
//! dst = V(H(edges)): 1 channel, same size. edges: 1 channel; ctrl_edge: 4 channels.
void edge_blur_wc18(ImageF& dst, const ImageF& edges, const ImageF& ctrl_edge, const EdgeBlurWc18Params& p,
                    const Exec& ex = {});

//! K of WC18/MNPR for width W and painted control c (guarded).
int edge_blur_kernel_size(int width, float ctrl);
//! edge_blur_kernel_size of eight control values: its operations lane by lane, the same K.
simd::v8i edge_blur_kernel_size8(int width, simd::v8f ctrl);
//! K of the pixels [i0, i0 + n) from ctrl.edge.g (channel of the 4-channel control), eight at a time.
void edge_blur_kernel_sizes(const ImageF& ctrl, int width, std::size_t i0, std::size_t n, int* k);

//! wc18's weights: w[K][o], o = 0..K-1, for K = 1..4W.
using EdgeBlurWeights = std::vector<std::vector<float>>;
//! wc18's fast schedule (edge_blur.schedule.cpp), which the variant runs for Traversal::Fast after
//! its checks, with tmp and dst allocated to the edges' size: the reference's bytes. K is
//! recomputed per row where needed: cheaper than a full-size table (8 MB at 1080p, faulted in and
//! filled every frame).
void edge_blur_wc18_fast(ImageF& dst, ImageF& tmp, const ImageF& edges, const ImageF& ctrl, const EdgeBlurWeights& tab,
                         const EdgeBlurWc18Params& p, const Exec& ex);

void register_edge_blur(Registry& r);

}  // namespace aq::stylize
