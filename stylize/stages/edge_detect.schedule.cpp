// stylize/stages/edge_detect.schedule.cpp — the fast schedule of edge_detect/rgbd_sobel
// (edge_detect.h edge_detect_rgbd_sobel_fast): per row block a ring of three planar,
// border-resolved source rows, the squared sums with x innermost (sobel_squares), the magnitudes
// eight at a time (sobel_magnitude over lanes), flat chunks written 0 without the maths. The same
// operations per pixel as the reference: bit-exact (tests/stylize/edge_detect_test.cpp and the
// registry-wide traversal test compare them).
#include "stylize/stages/edge_detect.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "stylize/kernels.h"
#include "stylize/stages/toolkit.h"

namespace aq::stylize {

namespace {

//! Columns per flat-region test of the fast traversal (a multiple of the 8-wide sqrt loop).
constexpr int kFlatChunk = 64;

//! The fast traversal's squared Sobel sums of padded row planes (r, g, b, depth) for pixels
//! [x0, x1): sobel_squares with x innermost (a function of its own, so GCC vectorises the loop:
//! inline in the row loop it did not once the flat-chunk test surrounded it).
void sobel_sums(const float* const* T, const float* const* M, const float* const* B, float wd, int x0, int x1,
                float* __restrict hsr, float* __restrict vsr) {
    for (int x = x0; x < x1; ++x) {
        const float* const* rows[3] = {T, M, B};
        sobel_squares([&rows, x](int r, int col, int c) { return rows[r][c][x + col]; }, wd, hsr[x], vsr[x]);
    }
}

//! The fast schedule's three source rows as padded planes (R, G, B, depth, each w + 2 wide, the
//! border columns resolved by the table) in a ring of three slots, so moving down one row converts
//! only the new row; per slot and column chunk, whether the chunk's taps (padded columns xc ..
//! xe + 1) hold one finite value per plane, and those values (computed once per row, used by three
//! output rows).
class SobelRing {
public:
    SobelRing(const ImageF& color, const ImageF& depth, const std::vector<int>& xt, Border b, bool wd_finite)
        : cd_(color.data()), zd_(depth.data()), w_(color.width()), h_(color.height()), pw_(std::size_t(w_) + 2),
          xt_(xt), b_(b), wd_finite_(wd_finite), nchunks_((std::size_t(w_) + kFlatChunk - 1) / kFlatChunk),
          // Not zero-filled (92 KB per block at 1080p): a slot's planes are filled before they are read.
          buf_(std::make_unique_for_overwrite<float[]>(pw_ * 12)), flat_(3 * nchunks_), flat_val_(3 * nchunks_ * 4) {}

    const float* plane(int slot, int c) const { return buf_.get() + (std::size_t(slot) * 4 + std::size_t(c)) * pw_; }

    //! Slot `slot` becomes source row yy (border-resolved).
    void fill(int slot, int yy) {
        const std::size_t srow = std::size_t(resolve_border(yy, h_, b_)) * w_;
        float* pr = mut(slot, 0);
        float* pg = mut(slot, 1);
        float* pb = mut(slot, 2);
        float* pz = mut(slot, 3);
        auto put = [&](std::size_t i, std::size_t si) {
            pr[i] = cd_[4 * si];
            pg[i] = cd_[4 * si + 1];
            pb[i] = cd_[4 * si + 2];
            pz[i] = zd_[si];
        };
        put(0, srow + std::size_t(xt_[0]));  // the border texels by the table, the row itself in order
        const float* __restrict c4 = cd_ + 4 * srow;
        for (std::size_t i = 0; i < std::size_t(w_); ++i) {
            pr[i + 1] = c4[4 * i];
            pg[i + 1] = c4[4 * i + 1];
            pb[i + 1] = c4[4 * i + 2];
        }
        std::memcpy(pz + 1, zd_ + srow, std::size_t(w_) * sizeof(float));
        put(pw_ - 1, srow + std::size_t(xt_[pw_ - 1]));
        const float* planes[4] = {pr, pg, pb, pz};
        for (std::size_t k = 0; k < nchunks_; ++k) {
            const std::size_t xc = k * kFlatChunk, n = std::min(std::size_t(w_), xc + kFlatChunk) - xc + 2;
            bool flat = wd_finite_;
            for (int c = 0; c < 4 && flat; ++c) {
                const float v = planes[c][xc];
                flat_val_[cell(slot, k) * 4 + std::size_t(c)] = v;
                flat = std::isfinite(v) && toolkit::all_equal(planes[c] + xc, n, v);
            }
            flat_[cell(slot, k)] = flat;
        }
    }

    //! Whether column chunk k's neighbourhood in the three rows of `slot` is flat: every tap of the
    //! chunk's pixels holds one finite value per plane. Then every difference is +0 or -0, their
    //! squares +0, and the output exactly +0, what the sums give (schedule only: the background of
    //! a frame, where colour and depth are constant).
    bool flat(const int slot[3], std::size_t k) const {
        bool f = flat_[cell(slot[0], k)] && flat_[cell(slot[1], k)] && flat_[cell(slot[2], k)];
        for (int c = 0; c < 4 && f; ++c) {
            const float v = flat_val_[cell(slot[0], k) * 4 + std::size_t(c)];
            f = flat_val_[cell(slot[1], k) * 4 + std::size_t(c)] == v && flat_val_[cell(slot[2], k) * 4 + std::size_t(c)] == v;
        }
        return f;
    }

private:
    float* mut(int slot, int c) { return buf_.get() + (std::size_t(slot) * 4 + std::size_t(c)) * pw_; }
    std::size_t cell(int slot, std::size_t k) const { return std::size_t(slot) * nchunks_ + k; }

    const float* cd_;
    const float* zd_;
    int w_, h_;
    std::size_t pw_;
    const std::vector<int>& xt_;
    Border b_;
    bool wd_finite_;
    std::size_t nchunks_;
    std::unique_ptr<float[]> buf_;
    std::vector<std::uint8_t> flat_;
    std::vector<float> flat_val_;
};

//! One output row from the ring's slots (rows y - 1, y, y + 1): flat column chunks written +0, the
//! runs between them as squared sums then magnitudes (a row without a flat chunk is one run).
//! hsr, vsr: w floats each of scratch.
void sobel_row(const SobelRing& ring, const int slot[3], float wd, int w, float* __restrict orow, float* __restrict hsr,
               float* __restrict vsr) {
    const float* T[4] = {ring.plane(slot[0], 0), ring.plane(slot[0], 1), ring.plane(slot[0], 2), ring.plane(slot[0], 3)};
    const float* M[4] = {ring.plane(slot[1], 0), ring.plane(slot[1], 1), ring.plane(slot[1], 2), ring.plane(slot[1], 3)};
    const float* B[4] = {ring.plane(slot[2], 0), ring.plane(slot[2], 1), ring.plane(slot[2], 2), ring.plane(slot[2], 3)};
    // Pixels [xa, xb) of the row: the squared sums, then the magnitudes.
    auto compute = [&](int xa, int xb) {
        if (xa >= xb) return;
        sobel_sums(T, M, B, wd, xa, xb, hsr, vsr);
        // The magnitudes eight at a time (sqrt through the vector unit, IEEE-exact like sqrtss:
        // the tail's values). Kept by measurement (issue 9): the plain scalar loop was 1.3-1.45x
        // slower for the whole stage at 1080p, 1 thread (36 -> 47-52 ms).
        int x = xa;
        for (; x + 8 <= xb; x += 8) simd::store8(orow + x, sobel_magnitude(simd::load8(hsr + x), simd::load8(vsr + x)));
        for (; x < xb; ++x) orow[x] = sobel_magnitude(hsr[x], vsr[x]);
    };
    int run = 0;
    for (int xc = 0; xc < w; xc += kFlatChunk) {
        const int xe = std::min(w, xc + kFlatChunk);
        if (!ring.flat(slot, std::size_t(xc / kFlatChunk))) continue;
        compute(run, xc);
        std::fill(orow + xc, orow + xe, 0.0f);
        run = xe;
    }
    compute(run, w);
}

}  // namespace

void edge_detect_rgbd_sobel_fast(ImageF& edges, const ImageF& color, const ImageF& depth, const EdgeDetectParams& p,
                                 const Exec& ex) {
    const int w = color.width(), h = color.height();
    // Fast: per output row, planar border-resolved copies of the three source rows, then the same
    // expressions as sobel_pixel with the x loop innermost.
    const std::vector<int> xt = toolkit::border_table(w, 1, p.border);
    const bool wd_finite = std::isfinite(p.depth_weight);  // (+-0) x wd is +-0: the flat test's premise
    toolkit::for_each_row_block(ex, h, [&](int y0, int y1) {
        SobelRing ring(color, depth, xt, p.border, wd_finite);
        // Not zero-filled: the sums of a span are written before their magnitudes read them.
        const auto hsv = std::make_unique_for_overwrite<float[]>(std::size_t(w) * 2);
        int slot[3] = {0, 1, 2};  // slots of rows y - 1, y, y + 1
        for (int y = y0; y < y1; ++y) {
            if (y == y0) {
                for (int r = 0; r < 3; ++r) ring.fill(slot[r], y + r - 1);
            } else {
                const int t = slot[0];
                slot[0] = slot[1];
                slot[1] = slot[2];
                slot[2] = t;
                ring.fill(slot[2], y + 1);
            }
            sobel_row(ring, slot, p.depth_weight, w, edges.data() + std::size_t(y) * w, hsv.get(), hsv.get() + w);
        }
    });
}

}  // namespace aq::stylize
