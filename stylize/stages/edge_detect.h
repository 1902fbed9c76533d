// stylize/stages/edge_detect.h — stage "edge_detect", variant rgbd_sobel (WC18 §3; spec §4.2).
#pragma once

#include "core/exec.h"
#include "core/image.h"
#include "stylize/stage.h"

namespace aq::stylize {

//! WC18 §3 weights the depth channel "by a parameter"; MNPR uses 5.
inline constexpr float kSobelDepthWeight = 5.0f;

struct EdgeDetectParams {
    float depth_weight = kSobelDepthWeight;  //!< wD, multiplies the depth gradient [0, 1000]
    Border border = Border::Clamp;           //!< neighbourhood reads outside the image
};

//! edges(x,y) = min(1, sqrt(|H|^2 + |V|^2)) with H, V the 3x3 Sobel responses of the 4-vector
//! (r, g, b, depth) and the depth components multiplied by wD (MNPR quadEdgeDetection sobelRGBD:
//! length(vec2(length(H), length(V)))). color: 4 channels (alpha unused); depth: 1 channel,
//! normalised; edges: 1 channel, same size. NaN inputs give NaN edges, never a crash.
void edge_detect_rgbd_sobel(ImageF& edges, const ImageF& color, const ImageF& depth,
                            const EdgeDetectParams& p, const Exec& ex = {});

void register_edge_detect(Registry& r);

}  // namespace aq::stylize
