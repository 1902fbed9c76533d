// stylize/stages/extend_edges.schedule.cpp — the fast schedule of extend_edges' gamma
// (extend_edges.h extend_edges_gamma_fast): per chunk of a row block, the positive values packed
// (or, mostly positive, all of them) and their powers taken in one vectorised pow_c_many, the
// deterministic pow_c of core/fastmath.h: extend_edges_gamma's values (the registry-wide traversal
// test compares the schedules). The power loops vectorise only with -fno-trapping-math (FP
// exception flags only, no value changes).
#pragma GCC optimize("no-trapping-math")
#include "stylize/stages/extend_edges.h"

#include <algorithm>
#include <cstddef>

#include "stylize/stages/toolkit.h"

namespace aq::stylize {

void extend_edges_gamma_fast(ImageF& d_img, float g, const Exec& ex) {
    float* d = d_img.data();
    const int w = d_img.width();
    toolkit::for_each_row_block(ex, d_img.height(), [&](int y0, int y1) {
        // b > 0: (b^(1/b))^(2/W) = b^((1/b) (2/W)), taken as one power (MNPR takes two; the
        // results differ by rounding only, and where b^(1/b) alone would underflow: values below
        // 1e-30, checked against the two-power GLSL twin by tests/reference); b <= 0 (and NaN) -> 0.
        // The positive values of a chunk are packed and only they take the power (vectorised).
        constexpr std::size_t kChunk = 256;
        float bs[kChunk], t[kChunk];
        int idx[kChunk];
        const std::size_t end = std::size_t(y1) * w;
        for (std::size_t i0 = std::size_t(y0) * w; i0 < end; i0 += kChunk) {
            const std::size_t n = std::min(kChunk, end - i0);
            float* di = d + i0;
            // No positive value (the background's zeros): only the clamp below.
            if (!toolkit::any_above(di, n, 0.0f)) {
                for (std::size_t j = 0; j < n; ++j) di[j] = di[j] > 0.0f ? di[j] : 0.0f;
                continue;
            }
            int m = 0;
            for (std::size_t j = 0; j < n; ++j) m += di[j] > 0.0f;
            if (std::size_t(4 * m) >= n) {
                // Mostly positive (inside a model's edges): every value takes the power, without
                // packing, and the non-positive ones are replaced by 0 — a positive value's power
                // is the same operations either way.
                for (std::size_t j = 0; j < n; ++j) bs[j] = di[j] > 0.0f ? di[j] : 1.0f;
                for (std::size_t j = 0; j < n; ++j) t[j] = (1.0f / bs[j]) * g;
                pow_c_many(bs, t, t, n);
                for (std::size_t j = 0; j < n; ++j) di[j] = di[j] > 0.0f ? t[j] : 0.0f;
                continue;
            }
            m = 0;
            for (std::size_t j = 0; j < n; ++j) {
                idx[m] = int(j);
                m += di[j] > 0.0f;
            }
            for (int q = 0; q < m; ++q) bs[q] = di[idx[q]];
            for (int q = 0; q < m; ++q) t[q] = (1.0f / bs[q]) * g;
            pow_c_many(bs, t, t, std::size_t(m));
            for (std::size_t j = 0; j < n; ++j) di[j] = di[j] > 0.0f ? di[j] : 0.0f;  // <= 0, NaN -> 0
            for (int q = 0; q < m; ++q) di[idx[q]] = t[q];
        }
    });
}

}  // namespace aq::stylize
