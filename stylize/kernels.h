// stylize/kernels.h — the shared maths (core/maths.h, core/fastmath.h) under the names the stages use.
#pragma once

#include "core/fastmath.h"
#include "core/maths.h"

namespace aq::stylize {

using maths::gaussian_weights;
using maths::half_size;
using maths::kLumaB;
using maths::kLumaG;
using maths::kLumaR;
using maths::length3;
using maths::lerp;
using maths::luminance;
using maths::mix;
using maths::pow_c;
using maths::pow_c8;
using maths::pow_c_many;
using maths::sample_bilinear;
using maths::sample_resampled;
using maths::sat;
using maths::smoothstep;
using maths::texel_coord;
#ifdef __AVX2__
using maths::sat8;
using maths::smoothstep8;
#endif

}  // namespace aq::stylize
