// stylize/stages/substrate_distort.cpp — paper distortion (WC17 §3.3 / MNPR). Each output pixel
// reads a bounded neighbourhood of its inputs only (offsets are at most 5*distortion pixels), so
// reference and fast traversals are bit-exact.
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

//! Reach of the taps in pixels: |offset| <= 5 * distortion, the bilinear footprint one more, and
//! one of margin for the float rounding of the sample position. Also the stage's row halo.
int distort_reach(const SubstrateDistortParams& p) {
    const float maxoff = std::max(0.0f, p.distortion) * kDistortPixelsPerUnit;
    return int(std::min(std::ceil(maxoff), 1.0e6f)) + 2;
}

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
    const int M = distort_reach(p);
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

}  // namespace

void substrate_distort(ImageF& dst, const ImageF& color, const ImageF& depth, const ImageF& ctrl_substrate,
                       const ImageF* paper, const SubstrateDistortParams& p,  const Exec& ex) {
    const std::string st = "substrate_distort/mnpr";
    check_input(&color, 4, Channels::Exactly, st, "color");
    check_input(&depth, 1, Channels::AtLeast, st, "depth");
    check_same_size(depth, color, st, "depth", "color");
    check_input(&ctrl_substrate, 1, Channels::AtLeast, st, "ctrl_substrate");
    check_same_size(ctrl_substrate, color, st, "ctrl_substrate", "color");
    check_paper(paper, color, st, "color");
    check_not_alias(dst, &color, st, "color");
    check_not_alias(dst, &depth, st, "depth");
    check_not_alias(dst, &ctrl_substrate, st, "ctrl_substrate");
    check_not_alias(dst, paper, st, "paper");
    const int w = color.width(), h = color.height();
    ensure_output(dst, w, h, 4);
    const View<const glm::vec4> c = color.view<glm::vec4>();
    const Plane z = plane(depth, 0), ctrl = plane(ctrl_substrate, control::kSubstrateDistortion.channel);
    const Plane nr = paper ? plane(*paper, 0) : constant_plane(&kFlatPaperNormal, w, h);
    const Plane ng = paper ? plane(*paper, 1) : constant_plane(&kFlatPaperNormal, w, h);
    const Border b = p.border;
    const View<glm::vec4> o = dst.view<glm::vec4>();
    if (ex.traversal == Traversal::Reference) {  // the plain reference: WC17 §3.3 pixel by pixel
        plain_loop(w, h, [&](int x, int y) {
            const glm::vec2 off = substrate_offset(nr(x, y), ng(x, y), ctrl(x, y), p);
            if (off.x == 0.0f && off.y == 0.0f) {
                o(x, y) = c(x, y);
                return;
            }
            const float px = float(x) + 0.5f + off.x, py = (float(y) + 0.5f) + off.y;
            const float dz = z(x, y) - sample_bilinear(z, px, py, b);
            const bool blocked = p.both_sides ? !(std::fabs(dz) <= p.depth_threshold) : (dz > p.depth_threshold);
            o(x, y) = blocked ? c(x, y) : sample_bilinear(c, px, py, b);
        });
        return;
    }
    // Flat margins (schedule only): where every colour and depth tap a pixel can read holds the
    // pixel's own values (bit for bit, finite), its bilinear samples are those values + 0 (a + (a
    // - a) t) and its depth step +0, so the result is known without the taps: the colour when
    // +0 is blocked or the offset is 0, else the colour + 0 (which turns a -0 into +0, as the taps
    // would). Such pixels are the rows' leading and trailing runs equal to their first / last
    // pixel, where every row within reach of the offsets (|offset| <= 5 * distortion) has the same
    // run value over the reach: the background around a model.
    const FlatMargins fm = flat_margins(color, depth, p, b, ex);
    const float thr = p.depth_threshold;
    const bool blocked_flat = p.both_sides ? !(std::fabs(0.0f) <= thr) : (0.0f > thr);
    // Rows in chunks: offsets and bilinear weights in one vectorisable loop (the same operations
    // as substrate_offset and the scalar taps below, value by value), then the taps.
    for_each_row(ex, w, h, [&](int y, int x0, int x1) {
        const int flat_lo = fm.lead[std::size_t(y)], flat_hi = fm.trail[std::size_t(y)];
        // Where a margin's value is its own + 0 (no -0 in it), the result is the colour whatever
        // the offset: whole chunks are copied without reading the paper and control.
        auto plus_zero_is_itself = [&](int x) {
            const glm::vec4 v = c(x, y), v0 = v + 0.0f;
            return std::memcmp(&v, &v0, sizeof v) == 0;
        };
        const bool copy_lead = flat_lo > 0 && plus_zero_is_itself(0);
        const bool copy_trail = flat_hi < w - 1 && plus_zero_is_itself(w - 1);
        constexpr int kChunk = 64;
        float tr[kChunk], tg[kChunk], tc[kChunk], ox[kChunk], oy[kChunk], txs[kChunk], tys[kChunk];
        int xas[kChunk], yas[kChunk];
        const float dist5 = p.distortion;
        const float* zp = z.p;
        const int zpx = int(z.px), zrow = int(z.row);
        const float fyc = float(y) + 0.5f;
        for (int xs = x0; xs < x1; xs += kChunk) {
            const int n = std::min(kChunk, x1 - xs);
            if ((copy_lead && xs + n <= flat_lo) || (copy_trail && xs > flat_hi)) {
                stream_copy(&o(xs, y).x, &c(xs, y).x, 4 * std::size_t(n));  // non-temporal: no read of o's lines
                continue;
            }
            int i8 = 0;
            for (; i8 + 8 <= n; i8 += 8) {
                store8(tr + i8, plane8(nr, xs + i8, y));
                store8(tg + i8, plane8(ng, xs + i8, y));
                store8(tc + i8, plane8(ctrl, xs + i8, y));
            }
            for (int i = i8; i < n; ++i) tr[i] = nr(xs + i, y), tg[i] = ng(xs + i, y), tc[i] = ctrl(xs + i, y);
            for (int i = 0; i < n; ++i) {
                float vx = tr[i] * 2.0f - 1.0f, vy = tg[i] * 2.0f - 1.0f;
                vx = vx > -1.0f ? (vx < 1.0f ? vx : 1.0f) : -1.0f;
                vy = vy > -1.0f ? (vy < 1.0f ? vy : 1.0f) : -1.0f;
                float k = tc[i] + kDistortCtrlBias;
                k = k > 0.0f ? (k < 1.0f ? k : 1.0f) : 0.0f;
                const float sc = dist5 * kDistortPixelsPerUnit * k;
                const float offx = vx * sc, offy = vy * sc;
                ox[i] = offx, oy[i] = offy;
                const float px = float(xs + i) + 0.5f + offx, py = fyc + offy;
                const float fx = px - 0.5f, fy = py - 0.5f;
                const float x0f = std::floor(fx), y0f = std::floor(fy);
                txs[i] = fx - x0f, tys[i] = fy - y0f;
                xas[i] = int(x0f), yas[i] = int(y0f);
            }
            auto one = [&](int i) {
                const int x = xs + i;
                if (ox[i] == 0.0f && oy[i] == 0.0f) {
                    o(x, y) = c(x, y);
                    return;
                }
                if (x < flat_lo || x > flat_hi) {
                    o(x, y) = blocked_flat ? c(x, y) : c(x, y) + 0.0f;
                    return;
                }
                const float tx = txs[i], ty = tys[i];
                int xa = xas[i], ya = yas[i], xb = xa + 1, yb = ya + 1;
                if (xa < 0 || yb >= h || ya < 0 || xb >= w) {
                    xa = resolve_border(xa, w, b), xb = resolve_border(xb, w, b);
                    ya = resolve_border(ya, h, b), yb = resolve_border(yb, h, b);
                }
                const float za = z(xa, ya), zc = z(xb, ya), zd0 = z(xa, yb), ze = z(xb, yb);
                const float ztop = za + (zc - za) * tx, zbot = zd0 + (ze - zd0) * tx;
                const float dz = z(x, y) - (ztop + (zbot - ztop) * ty);
                const bool blocked =
                    p.both_sides ? !(std::fabs(dz) <= p.depth_threshold) : (dz > p.depth_threshold);
                if (blocked) {
                    o(x, y) = c(x, y);
                    return;
                }
                const glm::vec4 ca = c(xa, ya), cc = c(xb, ya), cd = c(xa, yb), ce = c(xb, yb);
                const glm::vec4 top = ca + (cc - ca) * tx, bot = cd + (ce - cd) * tx;
                o(x, y) = top + (bot - top) * ty;
            };
            // Eight pixels at once where none of their taps needs the border rule: the depth taps
            // gathered and tested in lanes, then each pixel's colour from two loads (a tap and its
            // right neighbour are adjacent) and one 8-lane lerp for top and bottom — the operations
            // of `one`, value by value, with the pixel's result selected instead of branched to.
            auto eight = [&](int i) {
                const int x = xs + i;
                const v8i xv = simd::kLaneIndex8 + x;
                v8i xa, ya;
                std::memcpy(&xa, xas + i, sizeof xa);
                std::memcpy(&ya, yas + i, sizeof ya);
                const v8f tx = load8(txs + i), ty = load8(tys + i);
                const v8i zero = (load8(ox + i) == 0.0f) & (load8(oy + i) == 0.0f);
                const v8i flat = (xv < flat_lo) | (xv > flat_hi);
                const v8i tapped = ~zero & ~flat;
                const v8i inside = (xa >= 0) & (ya >= 0) & (xa < w - 1) & (ya < h - 1);
                if (!all_zero(tapped & ~inside)) return false;
                // Lanes without taps read pixel (0, 0): their depth step is not used.
                const v8i ia = (ya * zrow + xa * zpx) & tapped;
                const v8f za = simd::gather8(zp, ia), zc = simd::gather8(zp, ia + zpx);
                const v8f zd0 = simd::gather8(zp, ia + zrow), ze = simd::gather8(zp, ia + (zrow + zpx));
                const v8f ztop = za + (zc - za) * tx, zbot = zd0 + (ze - zd0) * tx;
                const v8f dz = plane8(z, x, y) - (ztop + (zbot - ztop) * ty);
                const v8i blocked =
                    p.both_sides ? ~(simd::abs8(dz) <= p.depth_threshold) : (dz > p.depth_threshold);
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
            };
            int i = 0;
            for (; i + 8 <= n; i += 8)
                if (!eight(i))
                    for (int l = i; l < i + 8; ++l) one(l);
            for (; i < n; ++i) one(i);
        }
        stream_fence();  // the copied margins' non-temporal stores, before the row is done
    });
}

void register_substrate_distort(Registry& r) {
    using D = SubstrateDistortParams;
    static const ParamTable<D> t = ParamTable<D>()
        .f("distortion", &D::distortion, 0, 10, "global paper distortion: 5 px per unit at full control (MNPR 1)")
        .f("depth_threshold", &D::depth_threshold, 0, 1, "no sampling across this normalised depth step (MNPR 0.01)")
        .b("both_sides", &D::both_sides, "also refuse destinations behind the pixel (MNPR: only in front)")
        .border(&D::border);
    r.add(declare({.stage = "substrate_distort",
                   .variant = "mnpr",
                   .doc = "WC17 3.3 / MNPR: sample colour at +n*distortion*5*sat(ctrl.substrate.r+0.2) px, depth-guarded",
                   .inputs = {{"color", target::kColor, 4, false},
                              {"depth", "depth", 1, false},
                              {"ctrl_substrate", target::kCtrlSubstrate, 4, false}},
                   .outputs = {{"color", "color.distorted", 4, false}},
                   .reference = StageVariant::Reference::PlainLoop,
                   .row_halo = [](const ParamValues& pv) { return distort_reach(t.from(pv)); }},
                  t, [](StageIO& io, const D& p, const Exec& ex) {
                      substrate_distort(*io.out[0], *io.in[0], *io.in[1], *io.in[2], globals_of(io).paper, p, ex);
                  }));
}

}  // namespace aq::stylize
