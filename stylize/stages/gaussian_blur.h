// stylize/stages/gaussian_blur.h — stage "gaussian_blur": a plain separable Gaussian low-pass of a
// one-channel map. LD06 filters its depth maps with it before the blurred depth test (LD06 §2:
// "we apply a Gaussian low-pass filter to the depth map D") and its shadow map before eq. 5
// (§3.3); the watercolor layers of LD06 part 2 blur their intensity maps the same way.
// Delta form (blur.h): a constant map stays exactly constant.
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
};

//! dst = V(H(src)), same size, one channel. src: one channel.
void gaussian_blur(ImageF& dst, const ImageF& src, const GaussianBlurParams& p, const Exec& ex = {});

void register_gaussian_blur(Registry& r);

}  // namespace aq::stylize
