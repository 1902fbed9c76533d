// core/compare.h — image comparison metrics (OpenImageIO ImageBufAlgo::compare) and diff heatmaps.
#pragma once

#include <string>

#include "core/image.h"

namespace aq {

struct CompareStats {
    double mean_abs = 0;        //!< mean absolute error over all values
    double max_abs = 0;         //!< largest absolute error
    int max_x = 0, max_y = 0, max_c = 0;  //!< where the largest error is
    double frac_over = 0;       //!< fraction of values with |a-b| > threshold
    double psnr = 0;            //!< dB, peak 1.0 (inf when identical)
    double threshold = 1.0 / 255.0;
    long long nonfinite = 0;    //!< NaN/Inf values met in either image
};

//! Compares two same-sized images channel by channel. Throws aq::Error on size mismatch.
CompareStats compare_images(const ImageF& a, const ImageF& b, double threshold = 1.0 / 255.0);

//! Per-pixel max |a-b| over channels, scaled so `scale` maps to full red, as an RGB heatmap.
ImageF diff_heatmap(const ImageF& a, const ImageF& b, double scale = 0.0 /*0 = auto (max)*/);

std::string format_stats(const CompareStats& s);

}  // namespace aq
