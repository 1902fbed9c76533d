// stylize/stages/blur.cpp — see blur.h.
#include "stylize/stages/blur.h"

#include <algorithm>
#include <cstdint>

#include "stylize/stages/toolkit.h"

namespace aq::stylize {

namespace {

void pass_reference(ImageF& dst, const ImageF& src, const std::vector<float>& w, Border b, bool horizontal) {
    const int W = src.width(), H = src.height(), C = src.channels();
    const int r = int(w.size() / 2);
    toolkit::ensure_output(dst, W, H, C);
    const float* s = src.data();
    float* o = dst.data();
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            for (int c = 0; c < C; ++c) {
                const float sv = s[(std::size_t(y) * W + x) * C + c];
                float acc = sv;
                for (int a = -r; a <= r; ++a) {
                    const std::size_t di = horizontal ? std::size_t(y) * W + resolve_border(x + a, W, b)
                                                      : std::size_t(resolve_border(y + a, H, b)) * W + x;
                    acc = acc + w[std::size_t(a + r)] * (s[di * C + c] - sv);
                }
                o[(std::size_t(y) * W + x) * C + c] = acc;
            }
}

// Zeros blur to +0 for weights >= 0 (acc = e0 + Σ w·(0 − e0) = ±0 + 0 = +0 for e0 = ±0; a
// negative weight could keep −0): with such weights a row, or a column chunk of kChunk pixels of
// a row, whose every tap is zero (±0) is written as +0 without its taps (the layers' intensity
// maps are zero around the plant, the edges around a model). zero[y * chunks + c] (horizontal
// pass) records the chunks it wrote that way, for the vertical pass; a conservative record
// (computed chunks are not marked) keeps the bytes.
constexpr int kChunk = 64;

void pass_fast(ImageF& dst, const ImageF& src, const std::vector<float>& w, Border b, bool horizontal,
               const Exec& ex, std::vector<std::uint8_t>& zero) {
    const int W = src.width(), H = src.height(), C = src.channels();
    const int r = int(w.size() / 2);
    toolkit::ensure_output(dst, W, H, C);
    const float* s = src.data();
    float* o = dst.data();
    const std::size_t n = std::size_t(W) * C;
    const int nch = (W + kChunk - 1) / kChunk;
    auto chunk_end = [&](int c) { return std::min(W, (c + 1) * kChunk); };
    if (horizontal) {
        const std::vector<int> xt = toolkit::border_table(W, r, b);
        zero.assign(std::size_t(H) * nch, 0);
        const bool skip_zero_rows = std::all_of(w.begin(), w.end(), [](float v) { return v >= 0.0f && v <= 1e30f; });
        toolkit::for_each_row_block(ex, H, [&](int y0, int y1) {
            std::vector<float> pad(std::size_t(W + 2 * r) * C);
            std::vector<const float*> dp(w.size());
            for (int y = y0; y < y1; ++y) {
                const float* sr = s + std::size_t(y) * n;
                float* orow = o + std::size_t(y) * n;
                std::uint8_t* zr = zero.data() + std::size_t(y) * nch;
                if (skip_zero_rows && toolkit::all_within(sr, n, 0.0f)) {
                    std::fill_n(orow, n, 0.0f);
                    std::fill_n(zr, nch, std::uint8_t(1));
                    continue;
                }
                toolkit::pad_row(pad.data(), sr, W, C, xt, r);
                for (int k = 0; k < nch; ++k) {
                    const std::size_t x0 = std::size_t(k) * kChunk, x1 = std::size_t(chunk_end(k));
                    // Chunk k's taps read padded texels [x0, x1 + 2r).
                    if (skip_zero_rows && toolkit::all_within(pad.data() + x0 * C, (x1 - x0 + 2 * std::size_t(r)) * C, 0.0f)) {
                        std::fill(orow + x0 * C, orow + x1 * C, 0.0f);
                        zr[k] = 1;
                        continue;
                    }
                    for (int ai = 0; ai <= 2 * r; ++ai) dp[std::size_t(ai)] = pad.data() + (x0 + std::size_t(ai)) * C;
                    accumulate_taps(orow + x0 * C, sr + x0 * C, dp.data(), w.data(), 2 * r + 1, (x1 - x0) * C);
                }
            }
        });
    } else {
        const std::vector<int> yt = toolkit::border_table(H, r, b);
        toolkit::for_each_row_block(ex, H, [&](int y0, int y1) {
            std::vector<const float*> dp(w.size());
            for (int y = y0; y < y1; ++y) {
                const float* sr = s + std::size_t(y) * n;
                float* orow = o + std::size_t(y) * n;
                for (int k = 0; k < nch; ++k) {
                    const std::size_t x0 = std::size_t(k) * kChunk, x1 = std::size_t(chunk_end(k));
                    bool all_zero = true;
                    for (int ai = 0; ai <= 2 * r && all_zero; ++ai)
                        all_zero = zero[std::size_t(yt[std::size_t(y + ai)]) * nch + k] != 0;
                    if (all_zero) {
                        std::fill(orow + x0 * C, orow + x1 * C, 0.0f);
                        continue;
                    }
                    for (int ai = 0; ai <= 2 * r; ++ai)
                        dp[std::size_t(ai)] = s + std::size_t(yt[std::size_t(y + ai)]) * n + x0 * C;
                    accumulate_taps(orow + x0 * C, sr + x0 * C, dp.data(), w.data(), 2 * r + 1, (x1 - x0) * C);
                }
            }
        });
    }
}

}  // namespace

void separable_blur(ImageF& dst, const ImageF& src, const std::vector<float>& w, Border b, const Exec& ex) {
    if (src.empty()) throw Error("separable_blur: empty input");
    if (w.size() % 2 != 1) throw Error("separable_blur: weights must have odd length");
    ImageF tmp;
    if (ex.traversal == Traversal::Reference) {
        pass_reference(tmp, src, w, b, true);
        pass_reference(dst, tmp, w, b, false);
    } else {
        std::vector<std::uint8_t> zero;  // rows of tmp written as zeros
        pass_fast(tmp, src, w, b, true, ex, zero);
        pass_fast(dst, tmp, w, b, false, ex, zero);
    }
}

}  // namespace aq::stylize
