// stylize/stages/gaussian_blur.h — stage "gaussian_blur": a plain separable Gaussian low-pass of a
// one-channel map. LD06 filters its depth maps with it before the blurred depth test (LD06 §2:
// "we apply a Gaussian low-pass filter to the depth map D") and its shadow map before eq. 5
// (§3.3); the watercolor layers of LD06 part 2 blur their intensity maps the same way.
// Delta form (blur.h): a constant map stays exactly constant. With `downsample` k > 1 the map is
// first reduced to (ceil(w / k), ceil(h / k)) by the mean of each k x k block (the pixels of the
// block inside the map), and the Gaussian (radius, sigma in those coarse pixels) runs on that: a
// wide low-pass at 1/k^2 of the cost (WC18's edge crowding map; readers resample it).
#pragma once

#include "core/exec.h"
#include "core/image.h"
#include "stylize/stage.h"

namespace aq::stylize {

//! Ours: LD06 does not give its kernel; 4 px at the 520 x 520 intermediate resolution.
inline constexpr int kGaussianBlurRadius = 8;
inline constexpr float kGaussianBlurSigma = 4.0f;

struct GaussianBlurParams {
    int radius = kGaussianBlurRadius;   //!< taps -radius..radius, [1, 64]
    float sigma = kGaussianBlurSigma;   //!< [0.1, 64]
    Border border = Border::Clamp;
    int downsample = 1;                 //!< k: block mean to ceil(w / k) x ceil(h / k) first, [1, 8]
};

//! dst = V(H(block_mean_k(src))), one channel, src's size divided by k (rounded up). src: one channel.
void gaussian_blur(ImageF& dst, const ImageF& src, const GaussianBlurParams& p, const Exec& ex = {});

void register_gaussian_blur(Registry& r);

}  // namespace aq::stylize
