// stylize/stages/edge_detect.cpp — RGBD Sobel edge detection (WC18 §3 "Edge detection"; MNPR
// quadEdgeDetection.ogsfx sobelRGBDFrag, same kernel orientation and accumulation order).
// Reference: every tap through the border rule, per pixel. Fast: planar border-resolved row copies
// and the same expressions, x innermost (vectorised); same operations per pixel -> bit-exact.
#include "stylize/stages/edge_detect.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#ifdef __AVX__
#endif
#include <vector>

#include "core/lanes.h"
#include "stylize/kernels.h"
#include "stylize/stages/toolkit.h"

namespace aq::stylize {

namespace {

//! Columns per flat-region test of the fast traversal (a multiple of the 8-wide sqrt loop).
constexpr int kFlatChunk = 64;

//! The Sobel maths of one pixel, once: the squared horizontal and vertical responses summed over
//! (r, g, b, depth * wd). tap(row, col, c) is channel c of the neighbour at row 0..2 (top to
//! bottom), column 0..2 (left to right). Differences of opposite taps, so a flat neighbourhood
//! gives exactly 0 (MNPR sums the six weighted taps left to right, which leaves rounding residue
//! ~1e-8 on flat colour).
template <class Tap>
inline void sobel_squares(Tap&& tap, float wd, float& hs, float& vs) {
    hs = 0.0f, vs = 0.0f;
    for (int c = 0; c < 4; ++c) {
        float hk = (tap(0, 0, c) - tap(2, 0, c)) + 2.0f * (tap(0, 1, c) - tap(2, 1, c)) + (tap(0, 2, c) - tap(2, 2, c));
        float vk = (tap(0, 0, c) - tap(0, 2, c)) + 2.0f * (tap(1, 0, c) - tap(1, 2, c)) + (tap(2, 0, c) - tap(2, 2, c));
        if (c == 3) {
            hk *= wd;
            vk *= wd;
        }
        hs += hk * hk;
        vs += vk * vk;
    }
}

//! The edge value from the squared sums, over lanes (one value, or eight in simd::v8f):
//! min(1, |(|H|, |V|)|), NaN staying NaN.
template <class F>
inline F sobel_magnitude(F hs, F vs) {
    const F lh = lanes::root(hs), lv = lanes::root(vs);
    const F m = lanes::root(lh * lh + lv * lv);
    return lanes::min_of(m, lanes::splat<F>(1.0f));
}

//! n[0..8] = TL, TM, TR, ML, M, MR, BL, BM, BR; each {r, g, b, depth}.
inline float sobel_pixel(const float (*n)[4], float wd) {
    float hs, vs;
    sobel_squares([n](int r, int col, int c) { return n[3 * r + col][c]; }, wd, hs, vs);
    return sobel_magnitude(hs, vs);
}

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

}  // namespace

void edge_detect_rgbd_sobel(ImageF& edges, const ImageF& color, const ImageF& depth, const EdgeDetectParams& p,
                            const Exec& ex) {
    toolkit::check_input(&color, 4, toolkit::Channels::Exactly, "edge_detect", "color");
    toolkit::check_input(&depth, 1, toolkit::Channels::Exactly, "edge_detect", "depth");
    toolkit::check_same_size(depth, color, "edge_detect", "depth", "color");
    const int w = color.width(), h = color.height();
    toolkit::ensure_output(edges, w, h, 1);
    const float* cd = color.data();
    const float* zd = depth.data();
    float* out = edges.data();
    const Border b = p.border;
    auto gather_border = [&](int x, int y, float (*n)[4]) {
        int k = 0;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx, ++k) {
                const std::size_t i = std::size_t(resolve_border(y + dy, h, b)) * w + resolve_border(x + dx, w, b);
                n[k][0] = cd[4 * i];
                n[k][1] = cd[4 * i + 1];
                n[k][2] = cd[4 * i + 2];
                n[k][3] = zd[i];
            }
    };
    if (ex.traversal == Traversal::Reference) {
        float n[9][4];
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                gather_border(x, y, n);
                out[std::size_t(y) * w + x] = sobel_pixel(n, p.depth_weight);
            }
        return;
    }
    // Fast: per output row, planar border-resolved copies of the three source rows (R, G, B, depth,
    // each w + 2 wide), then the same expressions as sobel_pixel with the x loop innermost.
    const std::vector<int> xt = toolkit::border_table(w, 1, b);
    const float wd = p.depth_weight;
    const bool wd_finite = std::isfinite(wd);  // (+-0) x wd is +-0: the flat test's premise
    toolkit::for_each_row_block(ex, h, [&](int y0, int y1) {
        const std::size_t pw = std::size_t(w) + 2;
        // Not zero-filled (92 KB per block at 1080p): a slot's planes are filled before they are
        // read, and the sums of a span before their magnitudes.
        const auto buf = std::make_unique_for_overwrite<float[]>(pw * 12);
        const auto hsv = std::make_unique_for_overwrite<float[]>(std::size_t(w) * 2);
        auto plane = [&](int r, int c) { return buf.get() + (std::size_t(r) * 4 + std::size_t(c)) * pw; };
        // Per slot and column chunk: whether the chunk's taps (padded columns xc .. xe + 1) hold one
        // finite value per plane, and those values (computed once per row, used by three output rows).
        const std::size_t nchunks = (std::size_t(w) + kFlatChunk - 1) / kFlatChunk;
        std::vector<std::uint8_t> flat_row(3 * nchunks);
        std::vector<float> flat_val(3 * nchunks * 4);
        auto cell = [&](int slot, std::size_t k) { return std::size_t(slot) * nchunks + k; };
        // The three rows live in a ring of slots: moving down one row converts only the new row.
        auto fill = [&](int slot, int yy) {
            const std::size_t srow = std::size_t(resolve_border(yy, h, b)) * w;
            float* pr = plane(slot, 0);
            float* pg = plane(slot, 1);
            float* pb = plane(slot, 2);
            float* pz = plane(slot, 3);
            auto put = [&](std::size_t i, std::size_t si) {
                pr[i] = cd[4 * si];
                pg[i] = cd[4 * si + 1];
                pb[i] = cd[4 * si + 2];
                pz[i] = zd[si];
            };
            put(0, srow + std::size_t(xt[0]));  // the border texels by the table, the row itself in order
            const float* __restrict c4 = cd + 4 * srow;
            for (std::size_t i = 0; i < std::size_t(w); ++i) {
                pr[i + 1] = c4[4 * i];
                pg[i + 1] = c4[4 * i + 1];
                pb[i + 1] = c4[4 * i + 2];
            }
            std::memcpy(pz + 1, zd + srow, std::size_t(w) * sizeof(float));
            put(pw - 1, srow + std::size_t(xt[pw - 1]));
            const float* planes[4] = {pr, pg, pb, pz};
            for (std::size_t k = 0; k < nchunks; ++k) {
                const std::size_t xc = k * kFlatChunk, n = std::min(std::size_t(w), xc + kFlatChunk) - xc + 2;
                bool flat = wd_finite;
                for (int c = 0; c < 4 && flat; ++c) {
                    const float v = planes[c][xc];
                    flat_val[cell(slot, k) * 4 + std::size_t(c)] = v;
                    flat = std::isfinite(v) && toolkit::all_equal(planes[c] + xc, n, v);
                }
                flat_row[cell(slot, k)] = flat;
            }
        };
        int slot[3] = {0, 1, 2};  // slots of rows y - 1, y, y + 1
        for (int y = y0; y < y1; ++y) {
            if (y == y0) {
                for (int r = 0; r < 3; ++r) fill(slot[r], y + r - 1);
            } else {
                const int t = slot[0];
                slot[0] = slot[1];
                slot[1] = slot[2];
                slot[2] = t;
                fill(slot[2], y + 1);
            }
            float* __restrict orow = out + std::size_t(y) * w;
            const float* T[4] = {plane(slot[0], 0), plane(slot[0], 1), plane(slot[0], 2), plane(slot[0], 3)};
            const float* M[4] = {plane(slot[1], 0), plane(slot[1], 1), plane(slot[1], 2), plane(slot[1], 3)};
            const float* B[4] = {plane(slot[2], 0), plane(slot[2], 1), plane(slot[2], 2), plane(slot[2], 3)};
            float* __restrict hsr = hsv.get();
            float* __restrict vsr = hsv.get() + w;
            // Pixels [xa, xb) of the row: the squared sums, then the magnitudes.
            auto compute = [&](int xa, int xb) {
                if (xa >= xb) return;
                sobel_sums(T, M, B, wd, xa, xb, hsr, vsr);
                // The magnitudes eight at a time (sqrt through the vector unit, IEEE-exact like
                // sqrtss: the tail's values). Kept by measurement (issue 9): the plain scalar loop
                // was 1.3-1.45x slower for the whole stage at 1080p, 1 thread (36 -> 47-52 ms).
                int x = xa;
                for (; x + 8 <= xb; x += 8)
                    simd::store8(orow + x, sobel_magnitude(simd::load8(hsr + x), simd::load8(vsr + x)));
                for (; x < xb; ++x) orow[x] = sobel_magnitude(hsr[x], vsr[x]);
            };
            // Column chunks whose neighbourhood is flat are written +0; the runs between them are
            // computed in one call each (a row without a flat chunk is one run, as before).
            int run = 0;
            for (int xc = 0; xc < w; xc += kFlatChunk) {
                const int xe = std::min(w, xc + kFlatChunk);
                // A flat neighbourhood: every tap of the chunk's pixels (padded columns xc .. xe + 1 of
                // the three rows) holds one finite value per plane. Then every difference is +0 or -0,
                // their squares +0, and the output exactly +0, what compute() gives (schedule only:
                // the background of a frame, where colour and depth are constant).
                const std::size_t k = std::size_t(xc / kFlatChunk);
                bool flat = flat_row[cell(slot[0], k)] && flat_row[cell(slot[1], k)] && flat_row[cell(slot[2], k)];
                for (int c = 0; c < 4 && flat; ++c) {
                    const float v = flat_val[cell(slot[0], k) * 4 + std::size_t(c)];
                    flat = flat_val[cell(slot[1], k) * 4 + std::size_t(c)] == v && flat_val[cell(slot[2], k) * 4 + std::size_t(c)] == v;
                }
                if (!flat) continue;
                compute(run, xc);
                std::fill(orow + xc, orow + xe, 0.0f);
                run = xe;
            }
            compute(run, w);
        }
    });
}

void register_edge_detect(Registry& r) {
    using P = EdgeDetectParams;
    StageVariant v = declare({.stage = "edge_detect",
                              .variant = "rgbd_sobel",
                              .doc = "WC18 3: 3x3 Sobel on (r, g, b, depth*wD), magnitude clamped to 1",
                              .inputs = {{"color", "color.adjusted", 4, false}, {"depth", "depth", 1, false}},
                              .outputs = {{"edges", "edges", 1, false}},
                              .reference = StageVariant::Reference::PlainLoop},
                             ParamTable<P>()
                                 .f("depth_weight", &P::depth_weight, 0, 1000, "wD, depth gradient weight (MNPR 5)")
                                 .border(&P::border),
                             [](StageIO& io, const P& p, const Exec& ex) {
                                 edge_detect_rgbd_sobel(*io.out[0], *io.in[0], *io.in[1], p, ex);
                             });
    v.row_halo = [](const ParamValues&) { return 1; };  // the 3 x 3 Sobel taps
    r.add(std::move(v));
}

}  // namespace aq::stylize
