// stylize/stages/substrate_distort.schedule.cpp — the fast schedule of substrate_distort (WC17 §3.3
// / MNPR; the maths and the plain reference loop are in substrate_distort.cpp): whole rows on
// oneTBB in chunks, the flat background margins copied without taps, eight pixels at once where no
// tap needs the border rule. The reference's values bit for bit (tests/stylize/substrate_test.cpp
// compares the two on random inputs, every border and both sides, at 1 and 2 threads).
// -fno-trapping-math (FP exception flags only, no value changes) lets GCC vectorise the selects,
// as in edge_darken.cpp.
#pragma GCC optimize("no-trapping-math")
#include "stylize/stages/substrate_distort.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "stylize/kernels.h"
#include "stylize/paper.h"
#include "stylize/stages/toolkit.h"

namespace aq::stylize {

using namespace toolkit;

namespace {

//! The number of pixels, at most n, from flat index i0 in direction dir (+1 or -1) whose colour (4
//! floats) and depth bits equal those of pixel i0 (memcmp's equality): two colours or eight depths
//! per compare of their bits, then pixel by pixel where the run ends.
int equal_run(const float* cd, const float* zd, int zc, std::size_t i0, int n, int dir) {
    std::uint32_t c0[4], z0;
    std::memcpy(c0, cd + 4 * i0, sizeof c0);
    std::memcpy(&z0, zd + std::size_t(zc) * i0, sizeof z0);
    const v8i cpat{int(c0[0]), int(c0[1]), int(c0[2]), int(c0[3]), int(c0[0]), int(c0[1]), int(c0[2]), int(c0[3])};
    const v8i zpat = v8i{} + int(z0);
    auto all_equal = [](v8i v, v8i pat) { return all_zero(v ^ pat); };
    int k = 0;  // pixels i0 + dir * [0, k) are known equal
    // Colour: pixels i0 + dir*k and i0 + dir*(k + 1) in one register (lowest address first).
    while (k + 2 <= n) {
        const std::size_t lo = dir > 0 ? i0 + std::size_t(k) : i0 - std::size_t(k) - 1;
        v8i v;
        std::memcpy(&v, cd + 4 * lo, sizeof v);
        if (!all_equal(v, cpat)) break;
        k += 2;
    }
    // Depth, eight at a time within the colour run: pixels [0, kz) equal in both.
    int kz = 0;
    if (zc == 1)
        while (kz + 8 <= k) {
            const std::size_t lo = dir > 0 ? i0 + std::size_t(kz) : i0 - std::size_t(kz) - 7;
            v8i v;
            std::memcpy(&v, zd + lo, sizeof v);
            if (!all_equal(v, zpat)) break;
            kz += 8;
        }
    for (k = kz; k < n; ++k) {
        const std::size_t i = dir > 0 ? i0 + std::size_t(k) : i0 - std::size_t(k);
        if (std::memcmp(cd + 4 * i, c0, sizeof c0) != 0 || std::memcmp(zd + std::size_t(zc) * i, &z0, sizeof z0) != 0)
            break;
    }
    return k;
}

//! Eight zero floats: the loads of a lane without taps.
alignas(32) const float kNoTaps[8] = {};

//! Per row y: pixels x < lead[y] and x > trail[y] are flat margins (see substrate_distort).
struct FlatMargins {
    std::vector<int> lead, trail;
};

FlatMargins flat_margins(const ImageF& color, const ImageF& depth, const SubstrateDistortParams& p, Border b,
                         const Exec& ex) {
    const int w = color.width(), h = color.height();
    const float* cd = color.data();
    const float* zd = depth.data();
    const int zc = depth.channels();
    // Pixels i and j (flat indices) hold the same colour and depth bits.
    auto same = [&](std::size_t i, std::size_t j) {
        return std::memcmp(cd + 4 * i, cd + 4 * j, 4 * sizeof(float)) == 0 &&
               std::memcmp(zd + zc * i, zd + zc * j, sizeof(float)) == 0;
    };
    auto finite = [&](int y, int x) {
        const std::size_t i = std::size_t(y) * w + x;
        bool f = std::isfinite(zd[zc * i]);
        for (int k = 0; k < 4; ++k) f = f && std::isfinite(cd[4 * i + k]);
        return f;
    };
    const int M = substrate_distort_reach(p);
    // The rows to compute (a band's window, else all) and the rows their taps reach.
    const int wy0 = std::max(0, ex.row_begin), wy1 = std::min(h, ex.row_end);
    const Exec reach = ex.windowed() ? ex.rows(wy0 - M, wy1 + M) : ex;
    // The leading / trailing runs equal to the row's first / last pixel (0 when it is not finite).
    std::vector<int> run_l(static_cast<std::size_t>(h)), run_t(static_cast<std::size_t>(h));
    for_each_row_block(reach, h, [&](int y0, int y1) {
        for (int y = y0; y < y1; ++y) {
            const std::size_t first = std::size_t(y) * w, last = first + w - 1;
            run_l[std::size_t(y)] = finite(y, 0) ? equal_run(cd, zd, zc, first, w, +1) : 0;
            run_t[std::size_t(y)] = finite(y, w - 1) ? equal_run(cd, zd, zc, last, w, -1) : 0;
        }
    });
    FlatMargins fm;
    fm.lead.assign(std::size_t(h), 0);
    fm.trail.assign(std::size_t(h), w - 1);
    for (int y = wy0; y < wy1; ++y) {
        int lead = run_l[std::size_t(y)], trail = run_t[std::size_t(y)];
        const std::size_t first = std::size_t(y) * w, last = first + w - 1;
        for (int d = -M; d <= M && (lead > 0 || trail > 0); ++d) {
            const int r = resolve_border(y + d, h, b);
            const std::size_t rf = std::size_t(r) * w, rl = rf + w - 1;
            lead = same(rf, first) ? std::min(lead, run_l[std::size_t(r)]) : 0;
            trail = same(rl, last) ? std::min(trail, run_t[std::size_t(r)]) : 0;
        }
        // x is a margin when its taps' columns [x - M, x + M] (resolved at the border: into
        // [0, M] or [w - 1 - M, w - 1]) lie in the run of every row in reach.
        fm.lead[std::size_t(y)] = lead > 2 * M ? lead - M : 0;
        fm.trail[std::size_t(y)] = trail > 2 * M ? w - 1 - (trail - M) : w - 1;
    }
    return fm;
}

//! Pixels per chunk of a row: offsets and weights of a chunk are computed in one vectorisable loop
//! before its taps.
constexpr int kChunk = 64;

//! One chunk's offsets (ox, oy), bilinear weights (tx, ty) and top-left taps (xa, ya), per pixel.
struct Chunk {
    float ox[kChunk], oy[kChunk], tx[kChunk], ty[kChunk];
    int xa[kChunk], ya[kChunk];
};

//! One fast run: the views, the parameters and the flat margins.
struct DistortRun {
    View<const glm::vec4> c;
    Plane z, ctrl, nr, ng;
    View<glm::vec4> o;
    const SubstrateDistortParams& p;
    int w, h;
    FlatMargins fm;
    bool blocked_flat;  //!< a depth step of +0 is blocked

    void offsets(Chunk& k, int xs, int n, int y) const;
    void one(const Chunk& k, int x, int i, int y) const;
    bool eight(const Chunk& k, int x, int i, int y) const;
    void row(int y, int x0, int x1) const;
};

//! Offsets (substrate_offset itself) and bilinear weights of pixels [xs, xs + n) of row y: the
//! scalar taps' operations, value by value, in one vectorisable loop.
void DistortRun::offsets(Chunk& k, int xs, int n, int y) const {
    float tr[kChunk], tg[kChunk], tc[kChunk];
    int i8 = 0;
    for (; i8 + 8 <= n; i8 += 8) {
        store8(tr + i8, plane8(nr, xs + i8, y));
        store8(tg + i8, plane8(ng, xs + i8, y));
        store8(tc + i8, plane8(ctrl, xs + i8, y));
    }
    for (int i = i8; i < n; ++i) tr[i] = nr(xs + i, y), tg[i] = ng(xs + i, y), tc[i] = ctrl(xs + i, y);
    const float fyc = float(y) + 0.5f;
    for (int i = 0; i < n; ++i) {
        const glm::vec2 off = substrate_offset(tr[i], tg[i], tc[i], p);
        const float offx = off.x, offy = off.y;
        k.ox[i] = offx, k.oy[i] = offy;
        const float px = float(xs + i) + 0.5f + offx, py = fyc + offy;
        const float fx = px - 0.5f, fy = py - 0.5f;
        const float x0f = std::floor(fx), y0f = std::floor(fy);
        k.tx[i] = fx - x0f, k.ty[i] = fy - y0f;
        k.xa[i] = int(x0f), k.ya[i] = int(y0f);
    }
}

//! Pixel x (index i of its chunk) of row y, as the reference computes it.
void DistortRun::one(const Chunk& k, int x, int i, int y) const {
    if (k.ox[i] == 0.0f && k.oy[i] == 0.0f) {
        o(x, y) = c(x, y);
        return;
    }
    if (x < fm.lead[std::size_t(y)] || x > fm.trail[std::size_t(y)]) {
        o(x, y) = blocked_flat ? c(x, y) : c(x, y) + 0.0f;
        return;
    }
    const Border b = p.border;
    const float tx = k.tx[i], ty = k.ty[i];
    int xa = k.xa[i], ya = k.ya[i], xb = xa + 1, yb = ya + 1;
    if (xa < 0 || yb >= h || ya < 0 || xb >= w) {
        xa = resolve_border(xa, w, b), xb = resolve_border(xb, w, b);
        ya = resolve_border(ya, h, b), yb = resolve_border(yb, h, b);
    }
    const float za = z(xa, ya), zc = z(xb, ya), zd0 = z(xa, yb), ze = z(xb, yb);
    const float dz = z(x, y) - maths::bilerp(za, zc, zd0, ze, tx, ty);
    const bool blocked = p.both_sides ? !(std::fabs(dz) <= p.depth_threshold) : (dz > p.depth_threshold);
    if (blocked) {
        o(x, y) = c(x, y);
        return;
    }
    const glm::vec4 ca = c(xa, ya), cc = c(xb, ya), cd = c(xa, yb), ce = c(xb, yb);
    o(x, y) = maths::bilerp(ca, cc, cd, ce, tx, ty);
}

//! Pixels x.. x + 7 (indices i.. of their chunk) of row y at once where none of their taps needs
//! the border rule (false, nothing written, otherwise): the depth taps gathered and tested in
//! lanes, then each pixel's colour from two loads (a tap and its right neighbour are adjacent) and
//! one 8-lane lerp for top and bottom — the operations of `one`, value by value, with the pixel's
//! result selected instead of branched to.
bool DistortRun::eight(const Chunk& k, int x, int i, int y) const {
    const int flat_lo = fm.lead[std::size_t(y)], flat_hi = fm.trail[std::size_t(y)];
    const float* zp = z.p;
    const int zpx = int(z.px), zrow = int(z.row);
    const v8i xv = simd::kLaneIndex8 + x;
    v8i xa, ya;
    std::memcpy(&xa, k.xa + i, sizeof xa);
    std::memcpy(&ya, k.ya + i, sizeof ya);
    const v8f tx = load8(k.tx + i), ty = load8(k.ty + i);
    const v8i zero = (load8(k.ox + i) == 0.0f) & (load8(k.oy + i) == 0.0f);
    const v8i flat = (xv < flat_lo) | (xv > flat_hi);
    const v8i tapped = ~zero & ~flat;
    const v8i inside = (xa >= 0) & (ya >= 0) & (xa < w - 1) & (ya < h - 1);
    if (!all_zero(tapped & ~inside)) return false;
    // Lanes without taps read pixel (0, 0): their depth step is not used.
    const v8i ia = (ya * zrow + xa * zpx) & tapped;
    const v8f za = simd::gather8(zp, ia), zc = simd::gather8(zp, ia + zpx);
    const v8f zd0 = simd::gather8(zp, ia + zrow), ze = simd::gather8(zp, ia + (zrow + zpx));
    const v8f dz = plane8(z, x, y) - maths::bilerp(za, zc, zd0, ze, tx, ty);
    const v8i blocked = p.both_sides ? ~(simd::abs8(dz) <= p.depth_threshold) : (dz > p.depth_threshold);
    const v8i sample = tapped & ~blocked;
    const v8i plus0 = blocked_flat ? v8i{} : ~zero & flat;
    for (int l = 0; l < 8; ++l) {
        const float* pa = sample[l] ? &c(xa[l], ya[l]).x : kNoTaps;
        const float* pd = sample[l] ? &c(xa[l], ya[l] + 1).x : kNoTaps;
        const v8f top_pair = load8(pa), bot_pair = load8(pd);  // (a, a + 1) per row
        const v8f left = __builtin_shufflevector(top_pair, bot_pair, 0, 1, 2, 3, 8, 9, 10, 11);
        const v8f right = __builtin_shufflevector(top_pair, bot_pair, 4, 5, 6, 7, 12, 13, 14, 15);
        const v8f rows = left + (right - left) * tx[l];  // top | bottom
        const v4f top = __builtin_shufflevector(rows, rows, 0, 1, 2, 3);
        const v4f bot = __builtin_shufflevector(rows, rows, 4, 5, 6, 7);
        const v4f s = top + (bot - top) * ty[l];
        v4f own;
        std::memcpy(&own, &c(x + l, y).x, sizeof own);
        const v4f r = sample[l] ? s : (plus0[l] ? own + 0.0f : own);
        std::memcpy(&o(x + l, y).x, &r, sizeof r);
    }
    return true;
}

//! Pixels [x0, x1) of row y in chunks: margins copied whole where their value is the result
//! whatever the offset, else offsets, then eight pixels at once or one by one.
void DistortRun::row(int y, int x0, int x1) const {
    const int flat_lo = fm.lead[std::size_t(y)], flat_hi = fm.trail[std::size_t(y)];
    // Where a margin's value is its own + 0 (no -0 in it), the result is the colour whatever the
    // offset: whole chunks are copied without reading the paper and control.
    auto plus_zero_is_itself = [&](int x) {
        const glm::vec4 v = c(x, y), v0 = v + 0.0f;
        return std::memcmp(&v, &v0, sizeof v) == 0;
    };
    const bool copy_lead = flat_lo > 0 && plus_zero_is_itself(0);
    const bool copy_trail = flat_hi < w - 1 && plus_zero_is_itself(w - 1);
    Chunk k;
    for (int xs = x0; xs < x1; xs += kChunk) {
        const int n = std::min(kChunk, x1 - xs);
        if ((copy_lead && xs + n <= flat_lo) || (copy_trail && xs > flat_hi)) {
            stream_copy(&o(xs, y).x, &c(xs, y).x, 4 * std::size_t(n));  // non-temporal: no read of o's lines
            continue;
        }
        offsets(k, xs, n, y);
        int i = 0;
        for (; i + 8 <= n; i += 8)
            if (!eight(k, xs + i, i, y))
                for (int l = i; l < i + 8; ++l) one(k, xs + l, l, y);
        for (; i < n; ++i) one(k, xs + i, i, y);
    }
    stream_fence();  // the copied margins' non-temporal stores, before the row is done
}

}  // namespace

void substrate_distort_fast(ImageF& dst, const ImageF& color, const ImageF& depth, const ImageF& ctrl_substrate,
                            const ImageF* paper, const SubstrateDistortParams& p, const Exec& ex) {
    const int w = color.width(), h = color.height();
    const float thr = p.depth_threshold;
    // Flat margins: where every colour and depth tap a pixel can read holds the pixel's own values
    // (bit for bit, finite), its bilinear samples are those values + 0 (a + (a - a) t) and its
    // depth step +0, so the result is known without the taps: the colour when +0 is blocked or the
    // offset is 0, else the colour + 0 (which turns a -0 into +0, as the taps would). Such pixels
    // are the rows' leading and trailing runs equal to their first / last pixel, where every row
    // within reach of the offsets (|offset| <= 5 * distortion) has the same run value over the
    // reach: the background around a model.
    const DistortRun run{.c = color.view<glm::vec4>(),
                         .z = plane(depth, 0),
                         .ctrl = plane(ctrl_substrate, control::kSubstrateDistortion.channel),
                         .nr = paper ? plane(*paper, 0) : constant_plane(&kFlatPaperNormal, w, h),
                         .ng = paper ? plane(*paper, 1) : constant_plane(&kFlatPaperNormal, w, h),
                         .o = dst.view<glm::vec4>(),
                         .p = p,
                         .w = w,
                         .h = h,
                         .fm = flat_margins(color, depth, p, p.border, ex),
                         .blocked_flat = p.both_sides ? !(std::fabs(0.0f) <= thr) : (0.0f > thr)};
    for_each_row(ex, w, h, [&](int y, int x0, int x1) { run.row(y, x0, x1); });
}

}  // namespace aq::stylize
