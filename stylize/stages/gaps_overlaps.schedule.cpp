// stylize/stages/gaps_overlaps.schedule.cpp — the fast schedule of gaps_overlaps/wc18
// (gaps_overlaps.h gaps_overlaps_fast): the activity tests and the gap march eight pixels at a
// time, background chunks copied whole, overlaps mixed per row, in place through a list of changed
// pixels. The same operations as GapsOverlapsKernel::operator(), lane by lane: the reference's
// bytes (tests/stylize/gaps_overlaps_test.cpp and the registry-wide traversal test compare them).
#include "stylize/stages/gaps_overlaps.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <vector>

namespace aq::stylize {

using namespace toolkit;

unsigned GapsOverlapsKernel::active8(int x, int y, v8f& ee, v8f& go) const {
    using simd::bits8;
    const Plane alpha{&c.data->w, 4, 4 * c.stride, c.width, c.height};  // c's fourth channel
    ee = plane8(e, x, y);
    go = plane8(ctrl, x, y) * float(p.steps);
    unsigned act = bits8(plane8(alpha, x, y) > p.alpha_threshold) & bits8(ee > p.edge_threshold) &
                   bits8((go > kGoCtrlThreshold) | (go < -kGoCtrlThreshold));
    if (act) act &= bits8(up->sample8(bleed, x, y) < p.bleed_threshold);
    return act;
}

unsigned GapsOverlapsKernel::gaps8(int x, int y, unsigned lanes, v8f go) const {
    using simd::bits8;
    using simd::v8i;
    v8f gu, gv, len;
    lanes &= bits8(gradient_parts([&](int dx, int dy) { return plane8(e, x + dx, y + dy); }, gu, gv, len));
    const v8f gx = gu / len, gy = gv / len;
    const v8i iota = simd::kLaneIndex8;
    const v8f cx = (float(x) + __builtin_convertvector(iota, v8f)) + 0.5f;  // float(x + i) + 0.5f, exact
    const float cy = float(y) + 0.5f;
    const v8f ag = -go;
    const float above = 1.0f / float(p.steps);
    // The march's taps lie within steps + 1 rows of y: gathered relative to the first of them.
    const int ybase = std::max(0, y - p.steps - 1);
    const float* base = e.p + std::ptrdiff_t(ybase) * e.row;
    const int px = int(e.px), row = int(e.row);
    unsigned still = lanes, gap = 0;
    for (int i = 1; i <= p.steps; ++i) {
        still &= ~bits8(ag < float(i));  // not enough gap parameter
        if (!still) break;
        const v8i on = ((v8i{} + int(still)) >> iota & 1) != 0;
        const v8f sx = on ? cx + float(i) * gx : cx, sy = on ? cy + float(i) * gy : v8f{} + cy;
        // sample_bilinear(e, sx, sy, b) lane by lane
        const v8f fx = sx - 0.5f, fy = sy - 0.5f;
        const v8f x0f = simd::floor8(fx), y0f = simd::floor8(fy);
        const v8f tx = fx - x0f, ty = fy - y0f;
        const v8i x0 = __builtin_convertvector(x0f, v8i), y0 = __builtin_convertvector(y0f, v8i);
        const v8i inside = (x0 >= 0) & (x0 + 1 < w) & (y0 >= 0) & (y0 + 1 < h);
        const v8i idx = (on & inside) ? (y0 - ybase) * row + x0 * px : v8i{};
        const v8f a = simd::gather8(base, idx), c = simd::gather8(base, idx + px);
        const v8f dd = simd::gather8(base, idx + row), ed = simd::gather8(base, idx + row + px);
        v8f val = maths::bilerp(a, c, dd, ed, tx, ty);
        for (unsigned out = still & ~bits8(inside); out; out &= out - 1) {
            const int k = __builtin_ctz(out);
            val[k] = sample_bilinear(e, sx[k], sy[k], b);
        }
        const unsigned hit = still & bits8(val > above);
        gap |= hit;
        still &= ~hit;
    }
    return gap;
}

namespace {

//! The fast schedule: a pixel whose extended edge is not above the threshold (NaN included) is
//! its colour, the kernel's second test: 64-pixel chunks without such an edge (the background) are
//! copied whole, their one-channel edges tested eight at a time. In place those chunks are not
//! touched, and the chunks with an edge are computed first, the pixels whose value changes kept
//! per row (their x and value: most active pixels fail a later test and keep their colour) and
//! written once every row is done (write_later).
struct GoFast {
    static constexpr int kChunk = 64;
    struct RowValues {
        std::vector<int> xs;
        std::vector<glm::vec4> values;
    };
    //! A row's overlaps, mixed together at its end: their colours' RYB inverses (most of an
    //! overlap's cost, 2 to 12 Gauss-Newton steps each) four at a time (rgb_to_ryb_many).
    struct Overlaps {
        std::vector<int> xs;
        std::vector<glm::vec3> rgb, ryb;  // per overlap: the pixel's colour, then the one it meets
    };

    const GapsOverlapsKernel& k;
    View<glm::vec4> o;
    const float* ed;  //!< the one-channel edges, or null (the chunk test is skipped)
    bool in_place;
    std::vector<RowValues> later;  //!< in place: per row, the changed pixels

    //! Pixel x of row y gets v: written, or in place kept for later when it changes, bit for bit.
    void put(int x, int y, const glm::vec4& v) {
        if (!in_place) {
            o(x, y) = v;
        } else if (std::memcmp(&v, &k.c(x, y), sizeof v) != 0) {
            RowValues& r = later[std::size_t(y)];
            r.xs.push_back(x);
            r.values.push_back(v);
        }
    }

    //! Pixels [xs, xe) of row y, a chunk with an edge: the activity tests eight pixels at a time;
    //! the pixels that pass are painted one by one, overlaps decided here (into ov) and mixed at
    //! the row's end. Gaps that need a march (not direct edges) are marched eight at a time where
    //! the gradient's taps are inside the image.
    void chunk(int y, int xs, int xe, Overlaps& ov) {
        const int w = k.w, h = k.h;
        const bool rows_inside = y >= 1 && y + 1 < h;
        const float direct = 2.0f / float(k.p.steps);
        int x = xs;
        for (; x + 8 <= xe; x += 8) {
            v8f ee, go;
            unsigned act = k.active8(x, y, ee, go);
            if (!in_place) std::memcpy(&o(x, y), &k.c(x, y), 8 * sizeof(glm::vec4));
            if (!act) continue;
            if (rows_inside && x >= 1 && x + 9 <= w) {
                const unsigned march = act & simd::bits8(go < -kGoCtrlThreshold) & ~simd::bits8(ee > direct);
                if (march) {
                    for (unsigned g = k.gaps8(x, y, march, go); g; g &= g - 1) {
                        const int i = __builtin_ctz(g);
                        put(x + i, y, k.gap_colour(k.c(x + i, y)));
                    }
                    act &= ~march;  // the others keep their colour
                }
            }
            for (; act; act &= act - 1) {
                const int i = __builtin_ctz(act);
                const glm::vec4 col = k.c(x + i, y);
                const GapsOverlapsKernel::Painted d = k.decide(x + i, y, col, ee[i], go[i]);
                if (!d.mix) {
                    put(x + i, y, d.value);
                    continue;
                }
                ov.xs.push_back(x + i);
                ov.rgb.push_back(glm::vec3(col));
                ov.rgb.push_back(d.with);
            }
        }
        for (; x < xe; ++x) put(x, y, k(x, y));
    }

    //! Pixels [x0, x1) of row y: background chunks copied (or untouched in place), the others
    //! computed, then the row's overlaps mixed.
    void row(int y, int x0, int x1) {
        thread_local Overlaps ov;
        ov.xs.clear();
        ov.rgb.clear();
        for (int xs = x0; xs < x1; xs += kChunk) {
            const int xe = std::min(x1, xs + kChunk);
            if (ed && !any_above(ed + std::size_t(y) * k.w + xs, std::size_t(xe - xs), k.p.edge_threshold)) {
                if (!in_place) stream_copy(&o(xs, y).x, &k.c(xs, y).x, 4 * std::size_t(xe - xs));
                continue;
            }
            chunk(y, xs, xe, ov);
        }
        ov.ryb.resize(ov.rgb.size());
        rgb_to_ryb_many(ov.rgb.data(), ov.ryb.data(), ov.rgb.size());
        for (std::size_t i = 0; i < ov.xs.size(); ++i) {
            const int x = ov.xs[i];
            put(x, y, k.overlap_colour(k.c(x, y), ov.rgb[2 * i + 1], ov.ryb[2 * i], ov.ryb[2 * i + 1]));
        }
        if (!in_place) stream_fence();  // the copied chunks' non-temporal stores, before the row is done
    }

    //! In place, after every row: the changed pixels written.
    void write_later(const Exec& ex) {
        for_each_row(ex, k.w, k.h, [&](int y, int, int) {
            const RowValues& r = later[std::size_t(y)];
            for (std::size_t i = 0; i < r.xs.size(); ++i) o(r.xs[i], y) = r.values[i];
        });
    }
};

}  // namespace

void gaps_overlaps_fast(const View<glm::vec4>& o, const GapsOverlapsKernel& k, const float* ed, bool in_place,
                        const Exec& ex) {
    GoFast fast{.k = k, .o = o, .ed = ed, .in_place = in_place,
                .later = std::vector<GoFast::RowValues>(in_place ? std::size_t(k.h) : 0)};
    for_each_row(ex, k.w, k.h, [&](int y, int x0, int x1) { fast.row(y, x0, x1); });
    if (in_place) fast.write_later(ex);
}

}  // namespace aq::stylize
