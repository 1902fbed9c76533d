// stylize/stages/layer_wash.h — stage "layer_wash": LD06 §3.1 watercolor layer shading
// (reconstructed, ../shared/spec/ld06.md §4): up to four intensity maps (one layer each) are
// Gaussian-blurred at their own resolution (which also gives §4.3's automatic level of detail:
// shapes smaller than the kernel fade), then shaped by a smoothstep, edge-darkened and granulated
// by the paper at the output resolution (the maps are resampled bilinearly, so borders are smooth
// at 720 px from 520 px intermediates). Output: the pigment amount of each layer (stylize/stages/wash.h).
// Variants: the edge term multiplicative (default) or additive.
#pragma once

#include "core/exec.h"
#include "core/image.h"
#include "stylize/stage.h"
#include "stylize/stages/gaussian_blur.h"
#include "stylize/stages/toolkit.h"
#include "stylize/stages/wash.h"

namespace aq::stylize {

struct LayerWashParams {
    int radius = kGaussianBlurRadius;  //!< blur radius, pixels of the intensity maps, [0, 64] (0 = no blur)
    float sigma = kGaussianBlurSigma;  //!< [0.1, 64]
    WashShape shape;
};

//! dst (4 channels, out_w x out_h): channel k = wash_amount of layers[k] (0 where layers[k] is
//! null). layers: one channel each, all of one size; paper: the prepared paper (height in channel
//! 2) of size out_w x out_h, or null (flat).
//! paper_spread: paper_height_spread(*paper) when the caller knows it (a pipeline run computes it
//! once), negative: computed here when needed.
void layer_wash(ImageF& dst, const ImageF* const layers[4], const ImageF* paper, int out_w, int out_h,
                const LayerWashParams& p, const Exec& ex = {}, float paper_spread = -1.0f);

//! The blur both layer_wash and shadow_layer apply to an intensity map (radius 0: a copy).
void wash_blur(ImageF& dst, const ImageF& src, int radius, float sigma, const Exec& ex);

//! The fast schedule (layer_wash.schedule.cpp), which layer_wash runs for Traversal::Fast after its
//! checks: first is the first present layer, hp the paper height plane at the output size (a
//! constant flat plane without a paper). The reference's bytes.
void layer_wash_fast(ImageF& dst, const ImageF* const layers[4], int first, const ImageF* paper, const toolkit::Plane& hp,
                     int out_w, int out_h, const LayerWashParams& p, const Exec& ex, float paper_spread);

void register_layer_wash(Registry& r);

}  // namespace aq::stylize
