// stylize/stages/edge_detect.h — stage "edge_detect", variant rgbd_sobel (WC18 §3; spec §4.2).
#pragma once

#include "core/exec.h"
#include "core/image.h"
#include "core/lanes.h"
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

//! The Sobel maths of one pixel, once: the squared horizontal and vertical responses summed over
//! (r, g, b, depth * wd). tap(row, col, c) is channel c of the neighbour at row 0..2 (top to
//! bottom), column 0..2 (left to right). Differences of opposite taps, so a flat neighbourhood
//! gives exactly 0 (MNPR sums the six weighted taps left to right, which leaves rounding residue
//! ~1e-8 on flat colour).
template <class Tap>
inline void sobel_squares(Tap&& tap, float wd, float& hs, float& vs) {
    hs = 0.0f, vs = 0.0f;
    for (int c = 0; c < 4; ++c) {
        float hk = (tap(0, 0, c) - tap(2, 0, c)) + 2.0f * (tap(0, 1, c) - tap(2, 1, c)) + (tap(0, 2, c) - tap(2, 2, c));
        float vk = (tap(0, 0, c) - tap(0, 2, c)) + 2.0f * (tap(1, 0, c) - tap(1, 2, c)) + (tap(2, 0, c) - tap(2, 2, c));
        if (c == 3) {
            hk *= wd;
            vk *= wd;
        }
        hs += hk * hk;
        vs += vk * vk;
    }
}

//! The edge value from the squared sums, over lanes (one value, or eight in simd::v8f):
//! min(1, |(|H|, |V|)|), NaN staying NaN.
template <class F>
inline F sobel_magnitude(F hs, F vs) {
    const F lh = lanes::root(hs), lv = lanes::root(vs);
    const F m = lanes::root(lh * lh + lv * lv);
    return lanes::min_of(m, lanes::splat<F>(1.0f));
}

//! The fast schedule (edge_detect.schedule.cpp), which the stage runs for Traversal::Fast after its
//! checks, with edges allocated: the reference's bytes.
void edge_detect_rgbd_sobel_fast(ImageF& edges, const ImageF& color, const ImageF& depth, const EdgeDetectParams& p,
                                 const Exec& ex);

void register_edge_detect(Registry& r);

}  // namespace aq::stylize
