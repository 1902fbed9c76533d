// stylize/stages/glaze.schedule.cpp — the fast schedule of glaze (the maths, glaze_of, in
// wash.h; the checks and the plain reference loop in glaze.cpp): each used ramp's row resampled
// once per output row, layers whose wash is 0 skipped where that provably changes no bit, the
// layers composited over the row with the variant as a constant. The reference's values bit for
// bit (tests/stylize/registry_traversal_test.cpp, the Glaze tests of ld06_layers_test.cpp and
// fusion_test.cpp compare the two).
#pragma GCC optimize("no-trapping-math")  // lets the row loop if-convert and vectorise; values unchanged
#include "stylize/stages/glaze.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "stylize/stages/toolkit.h"
#include "stylize/stages/wash.h"

namespace aq::stylize {

using namespace toolkit;

namespace {

//! Ramp texels within ±kRampBound resample to finite values (|a + (c - a)·t| <= 3·10^30 < FLT_MAX),
//! the condition for skipping a layer where its wash is 0 (colour ramps lie in [0, 1]).
constexpr float kRampBound = 1e30f;

// One output row: w pixels of 4 channels; rows = the N used layers' resampled ramp rows, one
// after the other; ch[j] = the wash channel of used layer j (in back-to-front order).
template <bool Mul, int N>
void glaze_row(float* __restrict o, const float* __restrict base, const float* __restrict wash,
               const float* __restrict rows, int w, const int* ch) {
    int c4[N > 0 ? N : 1];
    for (int j = 0; j < N; ++j) c4[j] = ch[j];
    // A pixel's RGB in one 4-lane register (glaze_of; the fourth lane is replaced).
    for (int x = 0; x < w; ++x) {
        const std::size_t i = std::size_t(x) * 4;
        v4f c;
        std::memcpy(&c, base + i, sizeof c);
        for (int j = 0; j < N; ++j) {
            v4f col;
            std::memcpy(&col, rows + (std::size_t(j) * w + x) * 4, sizeof col);
            c = glaze_of<Mul>(c, col, sat(col[3] * wash[i + std::size_t(c4[j])]));
        }
        c[3] = 1.0f;
        std::memcpy(o + i, &c, sizeof c);
    }
}

template <bool Mul>
void glaze_row_n(int n, float* o, const float* base, const float* wash, const float* rows, int w, const int* ch) {
    switch (n) {
        case 0: glaze_row<Mul, 0>(o, base, wash, rows, w, ch); break;
        case 1: glaze_row<Mul, 1>(o, base, wash, rows, w, ch); break;
        case 2: glaze_row<Mul, 2>(o, base, wash, rows, w, ch); break;
        case 3: glaze_row<Mul, 3>(o, base, wash, rows, w, ch); break;
        default: glaze_row<Mul, 4>(o, base, wash, rows, w, ch); break;
    }
}

}  // namespace

void glaze_fast(ImageF& dst, const ImageF* base, const ImageF& wash, const GlazeRamps& src, glm::vec3 paper_color,
                bool multiplicative, const Exec& ex) {
    const int w = wash.width(), h = wash.height();
    const ImageF* const* ramp = src.images;
    const float* wd = wash.data();
    const float* bd = base ? base->data() : nullptr;
    float* od = dst.data();
    // Each used ramp's row resampled once per output row (RowResampler: sample_resampled's
    // values), then the layers composited over the row with the variant as a constant.
    // A multiplicative layer whose wash is 0 multiplies by exactly 1 (dst·(1 - 0·(1 - c))) where
    // its resampled ramp is finite, which holds where the ramp texels it lerps lie within
    // ±kRampBound (a lerp of such values cannot overflow). So such a layer is skipped: in the whole
    // image when its wash is 0 everywhere (the empty slots of an ID pack), else in each row where
    // its wash is 0 (LD06's layers cover parts of the picture: 52-68 % of the oak's layer rows).
    // Over is not skipped (dst + c·0 can turn -0 into +0).
    //
    // Computed ramps (ComputedRamps): ramp_color is sat(·) of finite parameters, so a ramp texel is
    // NaN where its lighting texel is NaN and in [0, 1] otherwise, and alpha is a parameter in
    // [0, 1]: a computed ramp row lies within ±kRampBound exactly where its lighting row has no NaN
    // (all_within with an infinite bound), which is checked instead of computing the row.
    const std::uint32_t painted = multiplicative ? nonzero_channels(ex, wash) : 0xfu;
    const int rw = src.width(), rh = src.height();
    const float* light = src.computed ? src.computed->lighting->data() : nullptr;
    constexpr float kInf = std::numeric_limits<float>::infinity();
    int used[4], n = 0;
    for (int k = 0; k < 4; ++k) {
        const bool bounded = light ? !any_beyond(ex, light, std::size_t(rw) * rh, kInf)
                                   : !any_beyond(ex, ramp[k]->data(), ramp[k]->num_values(), kRampBound);
        const bool skip = !(painted >> k & 1u) && bounded;
        if (!skip) used[n++] = k;
    }
    const ResampleAxis ax(w, rw), ay(h, rh);
    for_each_row_block(ex, h, [&](int y0, int y1) {
        std::vector<RowResampler<4>> up;
        std::vector<std::vector<float>> ramp_rows(light ? std::size_t(n) : 0);  // computed ramps: one row each
        for (int j = 0; j < n; ++j) {
            if (!light) {
                up.emplace_back(ramp[used[j]]->data(), rw, w, ax, ay);
                continue;
            }
            std::vector<float>& buf = ramp_rows[std::size_t(j)];
            buf.resize(std::size_t(rw) * 4);
            const ColorRampLayer& layer = src.computed->ramps.layer[used[j]];
            const RampColors& hue = src.computed->ramps.hue;
            up.emplace_back(
                [&buf, &layer, &hue, light, rw](int r) {
                    color_ramp_row(light + std::size_t(r) * rw, rw, layer, hue, buf.data());
                    return static_cast<const float*>(buf.data());
                },
                rw, w, ax, ay);
        }
        std::vector<float> rows(std::size_t(w) * 4 * std::size_t(std::max(n, 1))), paper_row;
        if (!bd) {  // no picture yet: a row of the paper colour
            paper_row.resize(std::size_t(w) * 4);
            for (int x = 0; x < w; ++x)
                for (int c = 0; c < 3; ++c) paper_row[std::size_t(x) * 4 + c] = paper_color[c];
        }
        // Whether source row r of used layer j lies within ±kRampBound, cached for the rows of
        // this block (each source row serves one or two output rows).
        std::vector<std::int8_t> bounded(std::size_t(n) * std::size_t(rh), -1);
        auto row_bounded = [&](int j, int r) {
            std::int8_t& b = bounded[std::size_t(j) * std::size_t(rh) + std::size_t(r)];
            if (b < 0)
                b = light ? all_within(light + std::size_t(r) * rw, std::size_t(rw), kInf)
                          : all_within(ramp[used[j]]->data() + std::size_t(r) * rw * 4, std::size_t(rw) * 4, kRampBound);
            return b == 1;
        };
        for (int y = y0; y < y1; ++y) {
            const std::size_t i0 = std::size_t(y) * w;
            const std::uint32_t row_painted = multiplicative ? nonzero_channels_of(wd + i0 * 4, std::size_t(w) * 4, 4) : 0xfu;
            int row_used[4], m = 0;
            for (int j = 0; j < n; ++j) {
                const int k = used[j];
                const bool skip = !(row_painted >> k & 1u) && row_bounded(j, ay.i0[std::size_t(y)]) &&
                                  row_bounded(j, ay.i1[std::size_t(y)]);
                if (skip) continue;
                up[std::size_t(j)].row(y, rows.data() + std::size_t(m) * w * 4);
                row_used[m++] = k;
            }
            const float* b = bd ? bd + i0 * 4 : paper_row.data();
            if (multiplicative) glaze_row_n<true>(m, od + i0 * 4, b, wd + i0 * 4, rows.data(), w, row_used);
            else glaze_row_n<false>(m, od + i0 * 4, b, wd + i0 * 4, rows.data(), w, row_used);
        }
    });
}

}  // namespace aq::stylize
