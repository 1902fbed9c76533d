// stylize/stages/layer_wash.schedule.cpp — the fast schedule of layer_wash (layer_wash.h
// layer_wash_fast): the layers packed into one P-channel image (P = 1 + the last present layer)
// and blurred in one call (the delta-form blur computes every value with the same operations
// whatever the channel count, blur.h), then each output row resampled (RowResampler:
// sample_resampled's values) and shaped in one flat loop (wash_amount's values). A layer that
// washes to exactly 0 (empty_washes_to_zero) is skipped like an absent one. The reference computes
// it; the registry-wide test and LayerWash.EmptyLayersAreSkippedWithTheSameBytes compare the two.
#pragma GCC optimize("no-trapping-math")  // lets the shaping loop if-convert and vectorise; values unchanged
#include "stylize/stages/layer_wash.h"

#include <algorithm>
#include <cstdint>
#include <vector>

#include "stylize/paper.h"
#include "stylize/stages/toolkit.h"

namespace aq::stylize {

using namespace toolkit;

namespace {

// wash_amount over n values with the shape's two switches as constants, so the loop has no
// branch left and vectorises; the values are wash_amount's (the same function, inlined).
template <bool Before, bool Additive>
void shape_row_t(float* __restrict o, const float* __restrict I, const float* __restrict R, const float* __restrict H,
                 std::size_t n, WashShape s) {
    s.paper_before = Before;
    s.additive_edge = Additive;
    for (std::size_t i = 0; i < n; ++i) o[i] = wash_amount(I[i], R[i], H[i], s);
}

void shape_row(float* o, const float* I, const float* R, const float* H, std::size_t n, const WashShape& s) {
    if (s.paper_before) {
        if (s.additive_edge) shape_row_t<true, true>(o, I, R, H, n, s);
        else shape_row_t<true, false>(o, I, R, H, n, s);
    } else {
        if (s.additive_edge) shape_row_t<false, true>(o, I, R, H, n, s);
        else shape_row_t<false, false>(o, I, R, H, n, s);
    }
}

//! Whether an all-zero layer (an empty slot of an ID pack) washes to exactly 0 everywhere: when no
//! paper height can lift ρ' = 0 + border·(h - ½) above κ - w (then a = 0, e = 0, p = 0). That is
//! κ - w >= border·|h - ½| at every paper texel (false for NaN), i.e. >= border·max|h - ½|
//! (paper_height_spread: border >= 0, and rounding is monotone, so the maximum of the products is
//! the product with the maximum; a NaN or, at border 0, an infinite spread fails the test as a NaN
//! or infinite texel does).
bool empty_washes_to_zero(const ImageF* paper, const LayerWashParams& p, const Exec& ex, float paper_spread) {
    const float room = p.shape.kappa - p.shape.width;
    bool zero = room >= 0.0f;
    if (zero && paper && p.shape.paper_before) {
        const bool known = paper_spread >= 0.0f || paper_spread != paper_spread;
        zero = room >= p.shape.border * (known ? paper_spread : paper_height_spread(*paper, ex));
    }
    return zero;
}

//! The fast schedule's packed layers and their blur, and what each output row reads.
struct PackedWash {
    const ImageF* const* layers;
    int first;             //!< the first present layer
    bool use[4];           //!< layer k is washed (present, and not skipped as empty)
    int P = 0;             //!< packed channels: 1 + the last used layer
    bool empty_is_zero;    //!< empty_washes_to_zero
    ImageF packed, blurred;
    ResampleAxis ax, ay;   //!< output columns / rows -> packed texels
    Plane hp;
    const WashShape* shape;

    //! The used layers packed into one P-channel image (the others 0), then blurred in one call.
    void pack_and_blur(const LayerWashParams& p, const Exec& ex) {
        const int sw = layers[first]->width(), sh = layers[first]->height();
        packed = ImageF(sw, sh, P, kUninitialized);  // every value written below
        for_each_row_block(ex, sh, [&](int y0, int y1) {
            const std::size_t i0 = std::size_t(y0) * sw, i1 = std::size_t(y1) * sw;
            for (int k = 0; k < P; ++k) {
                const float* src = use[k] ? layers[k]->data() : nullptr;
                float* d = packed.data() + k;
                for (std::size_t i = i0; i < i1; ++i) d[i * std::size_t(P)] = src ? src[i] : 0.0f;
            }
        });
        wash_blur(blurred, packed, p.radius, p.sigma, ex);
    }

    //! The resampling from the packed images to an out_w x out_h output.
    void set_output_size(int out_w, int out_h) {
        ax = ResampleAxis(out_w, packed.width());
        ay = ResampleAxis(out_h, packed.height());
    }

    //! Output rows [y0, y1) with N = P packed channels: each row resampled from both packed images
    //! (RowResampler: sample_resampled's values) and shaped in one flat loop.
    template <int N>
    void rows(ImageF& dst, int y0, int y1) const {
        const int sw = packed.width(), sh = packed.height(), out_w = dst.width();
        float* o = dst.data();
        RowResampler<N> ri(packed.data(), sw, out_w, ax, ay), rr(blurred.data(), sw, out_w, ax, ay);
        const std::size_t n = std::size_t(out_w) * N;
        std::vector<float> I(n), R(n), H(n), A(n);
        // A row whose source rows hold only zeros in every packed layer, blurred or not, washes to
        // exactly 0 where empty layers do (empty_is_zero): written as such (the rows around the
        // plant). Each source row's answer is kept for the block.
        std::vector<std::int8_t> zero_rows(std::size_t(sh), -1);
        auto zero_row = [&](int r) {
            std::int8_t& z = zero_rows[std::size_t(r)];
            if (z < 0) {
                const std::size_t at = std::size_t(r) * std::size_t(sw) * P, m = std::size_t(sw) * P;
                z = all_within(packed.data() + at, m, 0.0f) && all_within(blurred.data() + at, m, 0.0f);
            }
            return z == 1;
        };
        for (int y = y0; y < y1; ++y) {
            if (empty_is_zero && zero_row(ay.i0[std::size_t(y)]) && zero_row(ay.i1[std::size_t(y)])) {
                std::fill_n(o + std::size_t(y) * out_w * 4, std::size_t(out_w) * 4, 0.0f);
                continue;
            }
            ri.row(y, I.data());
            rr.row(y, R.data());
            for (int x = 0; x < out_w; ++x)
                for (int k = 0; k < N; ++k) H[std::size_t(x) * N + k] = hp(x, y);
            shape_row(A.data(), I.data(), R.data(), H.data(), n, *shape);
            float* row = o + std::size_t(y) * out_w * 4;
            for (int x = 0; x < out_w; ++x)
                for (int k = 0; k < 4; ++k) row[std::size_t(x) * 4 + k] = k < N && use[k] ? A[std::size_t(x) * N + k] : 0.0f;
        }
    }
};

}  // namespace

void layer_wash_fast(ImageF& dst, const ImageF* const layers[4], int first, const ImageF* paper, const Plane& hp, int out_w,
                     int out_h, const LayerWashParams& p, const Exec& ex, float paper_spread) {
    PackedWash pw{.layers = layers, .first = first, .use = {}, .P = 0, .empty_is_zero = empty_washes_to_zero(paper, p, ex, paper_spread),
                  .packed = {}, .blurred = {}, .ax = {}, .ay = {}, .hp = hp, .shape = &p.shape};
    for (int k = 0; k < 4; ++k) {
        pw.use[k] = layers[k] != nullptr && (!pw.empty_is_zero || (nonzero_channels(ex, *layers[k]) & 1u) != 0);
        if (pw.use[k]) pw.P = k + 1;
    }
    ensure_output(dst, out_w, out_h, 4);
    if (pw.P == 0) {
        std::fill(dst.data(), dst.data() + dst.num_values(), 0.0f);
        return;
    }
    pw.pack_and_blur(p, ex);
    pw.set_output_size(out_w, out_h);
    for_each_row_block(ex, out_h, [&](int y0, int y1) {
        switch (pw.P) {
            case 1: pw.rows<1>(dst, y0, y1); break;
            case 2: pw.rows<2>(dst, y0, y1); break;
            case 3: pw.rows<3>(dst, y0, y1); break;
            default: pw.rows<4>(dst, y0, y1); break;
        }
    });
}

}  // namespace aq::stylize
