// stylize/stages/bleed.cpp's fast schedules (bleed.h bleed_passes_fast, bleed_halve_into_planes):
// the two 1-D passes over rows — padded row copies (horizontal) or row pointers (vertical), eight
// pixels per register with the taps innermost (the sums stay in registers), oneTBB row blocks —
// and the half-resolution planes eight outputs at a time. Each pixel gets the reference's
// expression in the reference's order with the rule bleeds<R> (bleed.h), so the bytes are the
// reference's (tests/stylize/bleed_test.cpp and the registry-wide traversal test compare them).
#include "stylize/stages/bleed.h"

#include <algorithm>
#include <cstring>
#include <vector>

#include "stylize/kernels.h"

namespace aq::stylize {

namespace {

using toolkit::load8;
using toolkit::store8;
using toolkit::v8f;
using toolkit::v8i;


// ---- fast: rows, eight pixels per register, taps innermost ---------------------------------
// Column chunks of kChunk pixels: the unit in which a pass skips pixels whose taps see no
// positive control.
constexpr int kChunk = 128;

inline int chunk_count(int w) { return (w + kChunk - 1) / kChunk; }

//! Writes s + 0 over [x0, x1): what the taps yield when no tap bleeds (every term is +0), bit for bit.
inline void plus_zero(const float* const* s, float* const* o, int x0, int x1) {
    for (int p = 0; p < 4; ++p)
        for (int x = x0; x < x1; ++x) o[p][x] = s[p][x] + 0.0f;
}

// One output row. src[p][j] / dst-tap rows are given as pointer tables indexed by tap.
template <BleedRule R>
inline void row_kernel(int w, const float* const* s, const float* zs_row, float* const* o, const BleedKernel& k,
                       const float* const* d, const float* const* zd, int x_shift_per_tap, const char* active) {
    // s[p]: source rows (p = 0..3, 3 = control); d[a][p] rows for tap a (H: the padded row with a
    // shift, V: the tap's row); zd[a]: depth rows of the taps. active[c] (null: all) is false for a
    // chunk c none of whose taps reads a positive control: no tap bleeds there (the rules of
    // JointBilateral and Mnpr need cs > 0 or cd > 0), so it is s + 0 without the taps.
    for (int xc = 0; xc < w; xc += kChunk) {
        const int xe = std::min(w, xc + kChunk);
        if (R != BleedRule::Naive && active && !active[xc / kChunk]) {
            plus_zero(s, o, xc, xe);
            continue;
        }
        // Per pixel the taps run in ascending order (same sums as the reference). Eight pixels at
        // a time with GCC vector extensions (lane-wise IEEE ops: the values of the scalar
        // expression below), all taps of a group before the next, the sums in registers; then a
        // scalar tail, tap by tap. The difference is computed unconditionally and selected by the
        // rule mask (bits of +0 where no bleeding), like (b ? d - s : 0).
        const float t = k.t;
        const v8f vt = v8f{} + t;
        const float* __restrict sr = s[0];
        const float* __restrict sg = s[1];
        const float* __restrict sb = s[2];
        const float* __restrict scs = s[3];
        const float* __restrict zsr = zs_row;
        int x = xc;
        for (; x + 8 <= xe; x += 8) {
            const v8f vr = load8(sr + x), vg = load8(sg + x), vb = load8(sb + x), cs = load8(scs + x);
            const v8f zt = load8(zsr + x) - vt;
            v8f a0 = vr, a1 = vg, a2 = vb, a3 = cs;
            for (int ai = 0; ai <= 2 * k.r; ++ai) {
                const int off = ai * x_shift_per_tap + x;
                const v8f cd = load8(d[ai * 4 + 3] + off);
                const v8i b = bleeds<R>(cs, cd, zt, load8(zd[ai] + off), k.scope[std::size_t(ai)]);
                const float wa = k.w[std::size_t(ai)];
                const v8f d0 = load8(d[ai * 4 + 0] + off) - vr, d1 = load8(d[ai * 4 + 1] + off) - vg;
                const v8f d2 = load8(d[ai * 4 + 2] + off) - vb, d3 = cd - cs;
                a0 = a0 + wa * (v8f)((v8i)d0 & b);
                a1 = a1 + wa * (v8f)((v8i)d1 & b);
                a2 = a2 + wa * (v8f)((v8i)d2 & b);
                if constexpr (R != BleedRule::Naive) a3 = a3 + wa * (v8f)((v8i)d3 & b);
            }
            store8(o[0] + x, a0);
            store8(o[1] + x, a1);
            store8(o[2] + x, a2);
            store8(o[3] + x, a3);
        }
        const int xt = x;
        for (int p = 0; p < 4; ++p)
            for (x = xt; x < xe; ++x) o[p][x] = s[p][x];
        for (int ai = 0; ai <= 2 * k.r; ++ai) {
            const float wa = k.w[std::size_t(ai)];
            const float sc = k.scope[std::size_t(ai)];
            const int off = ai * x_shift_per_tap;
            const float* __restrict dr = d[ai * 4 + 0] + off;
            const float* __restrict dg = d[ai * 4 + 1] + off;
            const float* __restrict db = d[ai * 4 + 2] + off;
            const float* __restrict dc = d[ai * 4 + 3] + off;
            const float* __restrict dz = zd[ai] + off;
            float* __restrict o0 = o[0];
            float* __restrict o1 = o[1];
            float* __restrict o2 = o[2];
            float* __restrict o3 = o[3];
            for (x = xt; x < xe; ++x) {
                const bool b = bleeds<R>(scs[x], dc[x], zsr[x] - t, dz[x], sc);
                const float d0 = dr[x] - sr[x], d1 = dg[x] - sg[x], d2 = db[x] - sb[x], d3 = dc[x] - scs[x];
                o0[x] = o0[x] + wa * (b ? d0 : 0.0f);
                o1[x] = o1[x] + wa * (b ? d1 : 0.0f);
                o2[x] = o2[x] + wa * (b ? d2 : 0.0f);
                if constexpr (R != BleedRule::Naive) o3[x] = o3[x] + wa * (b ? d3 : 0.0f);
            }
        }
    }
}

inline bool any_positive(const float* v, int n) { return toolkit::any_above(v, std::size_t(n), 0.0f); }

template <BleedRule R>
void pass_fast_h(const BleedPlanes& in, const std::vector<float>& ctrl, const std::vector<float>& z, BleedPlanes& out,
                 const BleedKernel& k, Border border, const Exec& ex) {
    const int w = in.w, h = in.h, r = k.r;
    const std::vector<int> xt = toolkit::border_table(w, r, border);
    const int pw = w + 2 * r, nch = chunk_count(w);
    toolkit::for_each_row_block(ex, h, [&](int y0, int y1) {
        std::vector<float> pad(std::size_t(pw) * 5);
        std::vector<char> active(std::size_t(nch), 1);
        for (int y = y0; y < y1; ++y) {
            const std::size_t row = std::size_t(y) * w;
            const float* src[4] = {in.p[0].data() + row, in.p[1].data() + row, in.p[2].data() + row, ctrl.data() + row};
            float* o[4] = {out.p[0].data() + row, out.p[1].data() + row, out.p[2].data() + row, out.p[3].data() + row};
            const float* zr = z.data() + row;
            const float* rows5[5] = {src[0], src[1], src[2], src[3], zr};
            // The padded control holds values of this row only (clamp or mirror): without a
            // positive one no tap bleeds and the row is s + 0, unpadded.
            if (R != BleedRule::Naive && !any_positive(src[3], w)) {
                plus_zero(src, o, 0, w);
                continue;
            }
            for (int q = 0; q < 5; ++q) toolkit::pad_row(pad.data() + std::size_t(q) * pw, rows5[q], w, 1, xt, r);
            // Chunk c's taps read the padded control over [xc, xe - 1 + 2r].
            const float* pc = pad.data() + 3 * std::size_t(pw);
            bool any = R == BleedRule::Naive;
            if (R != BleedRule::Naive)
                for (int c = 0; c < nch; ++c) {
                    const int xc = c * kChunk, xe = std::min(w, xc + kChunk);
                    active[std::size_t(c)] = any_positive(pc + xc, xe - xc + 2 * r);
                    any = any || active[std::size_t(c)];
                }
            if (!any) {
                plus_zero(src, o, 0, w);
                continue;
            }
            // Tap a reads padded index x + a + r: pointer base pad_q + 0, shifted by ai per tap.
            std::vector<const float*> d(std::size_t(2 * r + 1) * 4);
            std::vector<const float*> zd(std::size_t(2 * r + 1));
            for (int ai = 0; ai <= 2 * r; ++ai) {
                for (int q = 0; q < 4; ++q) d[std::size_t(ai) * 4 + q] = pad.data() + std::size_t(q) * pw;
                zd[std::size_t(ai)] = pad.data() + 4 * std::size_t(pw);
            }
            row_kernel<R>(w, src, zr, o, k, d.data(), zd.data(), 1, active.data());
            if (R == BleedRule::Naive)
                for (int x = 0; x < w; ++x) o[3][x] = src[3][x];
        }
    });
}

template <BleedRule R>
void pass_fast_v(const BleedPlanes& in, const std::vector<float>& ctrl, const std::vector<float>& z, BleedPlanes& out,
                 const BleedKernel& k, Border border, const Exec& ex) {
    const int w = in.w, h = in.h, r = k.r;
    const std::vector<int> yt = toolkit::border_table(h, r, border);
    // pos[y * nch + c]: chunk c of control row y holds a positive value. A chunk of an output row
    // is active when that of any of its tap rows is (the taps read the same columns).
    const int nch = chunk_count(w);
    std::vector<char> pos(R != BleedRule::Naive ? std::size_t(h) * nch : 0, 0);
    if (R != BleedRule::Naive)
        toolkit::for_each_row_block(ex, h, [&](int y0, int y1) {
            for (int y = y0; y < y1; ++y)
                for (int c = 0; c < nch; ++c) {
                    const int xc = c * kChunk, xe = std::min(w, xc + kChunk);
                    pos[std::size_t(y) * nch + c] = any_positive(ctrl.data() + std::size_t(y) * w + xc, xe - xc);
                }
        });
    toolkit::for_each_row_block(ex, h, [&](int y0, int y1) {
        std::vector<const float*> d(std::size_t(2 * r + 1) * 4);
        std::vector<const float*> zd(std::size_t(2 * r + 1));
        std::vector<char> active(std::size_t(nch), 0);
        for (int y = y0; y < y1; ++y) {
            const std::size_t row = std::size_t(y) * w;
            const float* src[4] = {in.p[0].data() + row, in.p[1].data() + row, in.p[2].data() + row, ctrl.data() + row};
            float* o[4] = {out.p[0].data() + row, out.p[1].data() + row, out.p[2].data() + row, out.p[3].data() + row};
            bool any = R == BleedRule::Naive;
            std::fill(active.begin(), active.end(), char(0));
            for (int ai = 0; ai <= 2 * r; ++ai) {
                const std::size_t ty = std::size_t(yt[std::size_t(y + ai)]), trow = ty * w;
                if (R != BleedRule::Naive)
                    for (int c = 0; c < nch; ++c) {
                        active[std::size_t(c)] |= pos[ty * nch + c];
                        any = any || active[std::size_t(c)];
                    }
                d[std::size_t(ai) * 4 + 0] = in.p[0].data() + trow;
                d[std::size_t(ai) * 4 + 1] = in.p[1].data() + trow;
                d[std::size_t(ai) * 4 + 2] = in.p[2].data() + trow;
                d[std::size_t(ai) * 4 + 3] = ctrl.data() + trow;
                zd[std::size_t(ai)] = z.data() + trow;
            }
            if (!any) {
                plus_zero(src, o, 0, w);
                continue;
            }
            row_kernel<R>(w, src, z.data() + row, o, k, d.data(), zd.data(), 0, active.data());
            if (R == BleedRule::Naive)
                for (int x = 0; x < w; ++x) o[3][x] = src[3][x];
        }
    });
}

}  // namespace

void bleed_passes_fast(BleedRule rule, const BleedPlanes& src, BleedPlanes& tmp, BleedPlanes& dst, const BleedKernel& k,
                       Border border, const Exec& ex) {
    auto passes = [&]<BleedRule R>() {
        pass_fast_h<R>(src, src.p[3], src.p[4], tmp, k, border, ex);
        pass_fast_v<R>(tmp, tmp.p[3], src.p[4], dst, k, border, ex);
    };
    switch (rule) {
        case BleedRule::Naive: passes.template operator()<BleedRule::Naive>(); break;
        case BleedRule::JointBilateral: passes.template operator()<BleedRule::JointBilateral>(); break;
        case BleedRule::Mnpr: passes.template operator()<BleedRule::Mnpr>(); break;
    }
}

void bleed_halve_into_planes(BleedPlanes& src, const float* cd, const float* kd, const float* zd, int w,
                             const toolkit::ResampleAxis& ax, const toolkit::ResampleAxis& ay, const Exec& ex) {
    using simd::transpose8x8;
    constexpr std::size_t kc = control::kAbstractionBleeding.channel;  // ctrl.abstraction.b (spec §1)
    const int wr = src.w;
    toolkit::for_each_row_block(ex, src.h, [&](int y0, int y1) {
        for (int y = y0; y < y1; ++y) {
            const std::size_t o = std::size_t(y) * wr;
            const std::size_t s0 = std::size_t(ay.i0[std::size_t(y)]) * w, s1 = std::size_t(ay.i1[std::size_t(y)]) * w;
            const float ty = ay.t[std::size_t(y)];
            const float* tx = ax.t.data();
            // Eight outputs: the lerps of the even (e) and odd (d) source values of rows 2y (0) and 2y + 1 (1).
            auto lerp8 = [&](v8f e0, v8f d0, v8f e1, v8f d1, v8f t, v8f vty) { return maths::bilerp(e0, d0, e1, d1, t, vty); };
            // Source pixels 2x .. 2x + 15 of an RGBA image in both rows, transposed: a[c] / a[4 + c] =
            // channel c of the even / odd pixels of row 2y, b the same of row 2y + 1.
            auto rgba_pairs = [&](const float* p, int xs, v8f a[8], v8f b[8]) {
                for (int k = 0; k < 8; ++k) {
                    a[k] = load8(p + 4 * (s0 + 2 * std::size_t(xs + k)));
                    b[k] = load8(p + 4 * (s1 + 2 * std::size_t(xs + k)));
                }
                transpose8x8(a);
                transpose8x8(b);
            };
            int x = 0;
            for (; x + 8 <= wr; x += 8) {
                const v8f t = load8(tx + x), vty = v8f{} + ty;
                v8f a[8], b[8];
                rgba_pairs(cd, x, a, b);  // colour: channels R, G, B
                for (int c = 0; c < 3; ++c) store8(src.p[c].data() + o + x, lerp8(a[c], a[c + 4], b[c], b[c + 4], t, vty));
                rgba_pairs(kd, x, a, b);  // control: channel kc
                store8(src.p[3].data() + o + x, lerp8(a[kc], a[kc + 4], b[kc], b[kc + 4], t, vty));
                if (!zd) continue;  // depth: one channel, even and odd values by shuffles
                const v8f z0 = load8(zd + s0 + 2 * std::size_t(x)), z1 = load8(zd + s0 + 2 * std::size_t(x) + 8);
                const v8f z2 = load8(zd + s1 + 2 * std::size_t(x)), z3 = load8(zd + s1 + 2 * std::size_t(x) + 8);
                store8(src.p[4].data() + o + x,
                       lerp8(__builtin_shufflevector(z0, z1, 0, 2, 4, 6, 8, 10, 12, 14),
                             __builtin_shufflevector(z0, z1, 1, 3, 5, 7, 9, 11, 13, 15),
                             __builtin_shufflevector(z2, z3, 0, 2, 4, 6, 8, 10, 12, 14),
                             __builtin_shufflevector(z2, z3, 1, 3, 5, 7, 9, 11, 13, 15), t, vty));
            }
            for (; x < wr; ++x) {  // the same operations, one output pixel at a time
                const std::size_t e0 = s0 + 2 * std::size_t(x), e1 = s1 + 2 * std::size_t(x);
                auto lerp2 = [&](const float* p, std::size_t stride) {
                    return maths::bilerp(p[stride * e0], p[stride * (e0 + 1)], p[stride * e1], p[stride * (e1 + 1)], tx[x], ty);
                };
                for (int c = 0; c < 3; ++c) src.p[c][o + x] = lerp2(cd + c, 4);
                src.p[3][o + x] = lerp2(kd + kc, 4);
                if (zd) src.p[4][o + x] = lerp2(zd, 1);
            }
            if (!zd) std::fill_n(src.p[4].data() + o, wr, 0.0f);
        }
    });
}

}  // namespace aq::stylize
