// core/compare.cpp
#include "core/compare.h"

#include <cmath>
#include <cstdio>
#include <limits>

#include "core/oiio.h"

namespace aq {

CompareStats compare_images(const ImageF& a, const ImageF& b, double threshold) {
    if (!a.same_size(b) || a.channels() != b.channels())
        throw Error("compare: images differ in size or channels (" + std::to_string(a.width()) + "x" +
                    std::to_string(a.height()) + "x" + std::to_string(a.channels()) + " vs " +
                    std::to_string(b.width()) + "x" + std::to_string(b.height()) + "x" +
                    std::to_string(b.channels()) + ")");
    const oiio_module::CompareResult r =
        oiio().compare(a.data(), b.data(), a.width(), a.height(), a.channels(), threshold);
    CompareStats s;
    s.threshold = threshold;
    s.mean_abs = r.meanerror;
    s.max_abs = r.maxerror;
    s.max_x = r.maxx;
    s.max_y = r.maxy;
    s.max_c = r.maxc;
    s.psnr = r.psnr;
    const double n = double(a.num_values());
    // OIIO counts pixels (not values) over the threshold; values are counted here for a
    // channel-exact fraction, with the non-finite values, which OIIO's mean would otherwise swallow.
    long long over = 0, nonfinite = 0;
    for (std::size_t i = 0; i < a.num_values(); ++i) {
        const float x = a.data()[i], y = b.data()[i];
        if (!std::isfinite(x) || !std::isfinite(y)) {
            ++nonfinite;
            continue;
        }
        if (std::fabs(double(x) - double(y)) > threshold) ++over;
    }
    s.frac_over = n > 0 ? double(over) / n : 0.0;
    s.nonfinite = nonfinite;
    if (s.max_abs == 0.0) s.psnr = std::numeric_limits<double>::infinity();
    return s;
}

ImageF diff_heatmap(const ImageF& a, const ImageF& b, double scale) {
    if (!a.same_size(b) || a.channels() != b.channels()) throw Error("diff: images differ in size or channels");
    ImageF out(a.width(), a.height(), 3);
    double mx = 0;
    std::vector<float> d(std::size_t(a.width()) * a.height());
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x) {
            double m = 0;
            for (int c = 0; c < a.channels(); ++c) {
                double e = std::fabs(double(a.at(x, y, c)) - double(b.at(x, y, c)));
                if (!std::isfinite(e)) e = 1e30;
                m = std::max(m, e);
            }
            d[std::size_t(y) * a.width() + x] = float(m);
            mx = std::max(mx, m);
        }
    const double s = scale > 0 ? scale : (mx > 0 ? mx : 1.0);
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x) {
            float t = float(std::min(1.0, d[std::size_t(y) * a.width() + x] / s));
            // black -> blue -> yellow -> red
            out.at(x, y, 0) = std::min(1.0f, 2.0f * t);
            out.at(x, y, 1) = t < 0.5f ? t : 2.0f * (1.0f - t);
            out.at(x, y, 2) = t > 0.0f && t < 0.5f ? 1.0f - 2.0f * t + 0.5f : 0.0f;
        }
    return out;
}

std::string format_stats(const CompareStats& s) {
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "mean_abs=%.6g max_abs=%.6g (at %d,%d ch%d) over_%.4g=%.4f%% psnr=%.2f dB nonfinite=%lld",
                  s.mean_abs, s.max_abs, s.max_x, s.max_y, s.max_c, s.threshold, 100.0 * s.frac_over,
                  s.psnr, s.nonfinite);
    return buf;
}

}  // namespace aq
