// stylize/stages/stroke_ink.schedule.cpp — the fast schedule of stroke_ink/over (stroke_ink.h
// stroke_ink_fast): the ink row resampled once (RowResampler; the ink itself at the same size),
// then the row glazed in registers (glaze_of: glaze_px's values); in place, uninked pixels are not
// written. The registry-wide traversal test compares it with the reference.
#include "stylize/stages/stroke_ink.h"

#include <algorithm>
#include <cstring>
#include <vector>

#include "stylize/stages/toolkit.h"
#include "stylize/stages/wash.h"

namespace aq::stylize {

using namespace toolkit;

void stroke_ink_fast(ImageF& dst, const ImageF& color, const ImageF& ink, bool in_place, const StrokeInkParams& p,
                     const Exec& ex) {
    const int w = color.width(), h = color.height();
    const float* c = color.data();
    float* o = dst.data();
    // Fast: the ink row resampled once (RowResampler; the ink itself at the same size), then the
    // row glazed in registers (glaze_of: glaze_px's values); in place, uninked pixels untouched.
    const ResampleAxis ax(w, ink.width()), ay(h, ink.height());
    const v4f col = {p.color.r, p.color.g, p.color.b, 0.0f};
    constexpr int kGroup = 8;
    for_each_row_block(ex, h, [&](int y0, int y1) {
        RowResampler<1> up(ink.data(), ink.width(), w, ax, ay);
        std::vector<float> buf(static_cast<std::size_t>(w));
        for (int y = y0; y < y1; ++y) {
            const float* cov = up.row_or_source(y, buf.data());
            const float* src = c + std::size_t(y) * w * 4;
            float* out = o + std::size_t(y) * w * 4;
            for (int x0 = 0; x0 < w; x0 += kGroup) {
                const int x1 = std::min(w, x0 + kGroup);
                if (in_place && x1 - x0 == kGroup) {  // skip 8 uninked pixels at once (sat(v) == 0 iff v <= 0)
#ifdef __AVX2__
                    const __m256 v = _mm256_mul_ps(_mm256_set1_ps(p.alpha), _mm256_loadu_ps(cov + x0));
                    if (_mm256_movemask_ps(_mm256_cmp_ps(v, _mm256_setzero_ps(), _CMP_LE_OQ)) == 0xFF) continue;
#else
                    bool none = true;
                    for (int l = 0; l < kGroup; ++l) none &= p.alpha * cov[x0 + l] <= 0.0f;
                    if (none) continue;
#endif
                }
                for (int x = x0; x < x1; ++x) {
                    const float k = ink_opacity(p.alpha, cov[x]);
                    if (in_place && k == 0.0f) continue;
                    v4f d;
                    std::memcpy(&d, src + std::size_t(x) * 4, sizeof d);
                    if (k != 0.0f) {
                        const float a = d[3];
                        d = glaze_of<false>(d, col, k);
                        d[3] = a;
                    }
                    std::memcpy(out + std::size_t(x) * 4, &d, sizeof d);
                }
            }
        }
    });
}

}  // namespace aq::stylize
