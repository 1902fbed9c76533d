// stylize/stages/pigment_apply.schedule.cpp — the fast schedules of pigment_apply (WC17 eq. 9,
// WC18 eq. 1-4; the per-pixel maths, pigment_apply_*_px and the parts both call (wc17's prepare
// and channel, wc18's terms), in pigment_apply.h; the checks and the plain reference loops in
// pigment_apply.cpp). Rows in chunks of 64 pixels, each step a simple loop over arrays, the powers
// in one vectorised pow_c_many; value for value the operations of the _px functions
// (tests/stylize/row_kernels_test.cpp checks them bit for bit; the registry-wide traversal test
// compares the schedules).
// The power loops vectorise only when GCC may evaluate both sides of a select; that needs
// -fno-trapping-math (FP exception flags only — no value changes, unlike -ffast-math: no
// reassociation, no FMA, no reciprocal approximations). See docs/stylize.md "Speed".
#pragma GCC optimize("no-trapping-math")
#include "stylize/stages/pigment_apply.h"

#include <algorithm>
#include <cstring>

namespace aq::stylize {

using namespace toolkit;

void pigment_apply_wc17_fast(const View<glm::vec4>& o, const PigmentInputs& in, const PigmentApplyWc17Params& p,
                             const Exec& ex) {
    const int w = in.c.width, h = in.c.height;
    // Rows in chunks as in wc18: the same operations as pigment_apply_wc17_px, pixel by pixel.
    for_each_row(ex, w, h, [&](int y, int x0, int x1) {
        constexpr int kChunk = 64;
        PigmentWc17Prep q[kChunk];
        float base[3 * kChunk], dexp[3 * kChunk], g[3 * kChunk];
        for (int xs = x0; xs < x1; xs += kChunk) {
            const int n = std::min(kChunk, x1 - xs);
            for (int i = 0; i < n; ++i) {
                const int x = xs + i;
                const glm::vec4 cv = in.c(x, y);
                q[i] = pigment_apply_wc17_prepare(cv, in.height(x, y), in.ctrl(x, y), p);
                for (int k = 0; k < 3; ++k) base[3 * i + k] = cv[k], dexp[3 * i + k] = q[i].d;
            }
            pow_c_many(base, dexp, g, std::size_t(3 * n));
            for (int i = 0; i < n; ++i) {
                const glm::vec4 cv = in.c(xs + i, y);
                o(xs + i, y) = q[i].apply ? glm::vec4(pigment_apply_wc17_channel(cv.x, q[i].sub, g[3 * i]),
                                                      pigment_apply_wc17_channel(cv.y, q[i].sub, g[3 * i + 1]),
                                                      pigment_apply_wc17_channel(cv.z, q[i].sub, g[3 * i + 2]), cv.w)
                                          : cv;
            }
        }
    });
}

void pigment_apply_wc18_fast(const View<glm::vec4>& o, const PigmentInputs& in, bool in_place, glm::vec3 substrate,
                             const PigmentApplyWc18Params& p, const Exec& ex) {
    const int w = in.c.width, h = in.c.height;
    // Rows in chunks of 64 pixels, each step a simple loop over arrays: gather (eight pixels per
    // register), pigment_apply_wc18_terms per pixel (GCC vectorises the loop), the powers per
    // channel plane in pow_c_many (for chunks where a pixel granulates), the blend. Value for value
    // the operations of pigment_apply_wc18_px (tests/stylize/row_kernels_test.cpp checks it bit for
    // bit).
    for_each_row(ex, w, h, [&](int y, int x0, int x1) {
        constexpr int kChunk = 64;
        float cr[kChunk], cg[kChunk], cb[kChunk], ca[kChunk], ht[kChunk], av[kChunk];
        float outr[kChunk], outg[kChunk], outb[kChunk], da[kChunk], fade[kChunk];
        int mode[kChunk];
        float base[3 * kChunk], g[3 * kChunk];
        for (int xs = x0; xs < x1; xs += kChunk) {
            const int n = std::min(kChunk, x1 - xs);
            // Every pixel uncovered (mode 0 below; NaN alpha is uncovered): the colour as it is.
            // The alphas are tested two pixels per register (lanes 3 and 7), the chunk copied whole.
            const float* crow = &in.c(xs, y).x;
            v8i covered{};
            const v8i alpha_lanes{0, 0, 0, -1, 0, 0, 0, -1};
            const v8f mask = v8f{} + kPigmentAlphaMask;
            int i2 = 0;
            for (; i2 + 2 <= n; i2 += 2) covered |= (load8(crow + 4 * i2) >= mask) & alpha_lanes;
            const bool any_covered = !all_zero(covered) || (i2 < n && crow[4 * i2 + 3] >= kPigmentAlphaMask);
            if (!any_covered) {
                if (!in_place) std::memcpy(&o(xs, y).x, crow, sizeof(float) * 4 * std::size_t(n));
                continue;
            }
            int i8 = 0;
            for (; i8 + 8 <= n; i8 += 8) {
                const float* cp = crow + 4 * i8;
                store8(cr + i8, simd::strided8<4>(cp));
                store8(cg + i8, simd::strided8<4>(cp + 1));
                store8(cb + i8, simd::strided8<4>(cp + 2));
                store8(ca + i8, simd::strided8<4>(cp + 3));
                store8(ht + i8, plane8(in.height, xs + i8, y));
                store8(av + i8, plane8(in.ctrl, xs + i8, y));
            }
            for (int i = i8; i < n; ++i) {
                const glm::vec4 cv = in.c(xs + i, y);
                cr[i] = cv.x, cg[i] = cv.y, cb[i] = cv.z, ca[i] = cv.w;
                ht[i] = in.height(xs + i, y);
                av[i] = in.ctrl(xs + i, y);
            }
            for (int i = 0; i < n; ++i) {
                const glm::vec3 rgb(cr[i], cg[i], cb[i]);
                const PigmentWc18Terms q = pigment_apply_wc18_terms(rgb, ht[i], av[i], substrate, p);
                outr[i] = q.dry_brushed.x, outg[i] = q.dry_brushed.y, outb[i] = q.dry_brushed.z;
                da[i] = q.da;
                fade[i] = q.fade;
                // 0: uncovered (unchanged), 1: dry-brushed, 2: granulates
                mode[i] = !(ca[i] >= kPigmentAlphaMask) ? 0 : (q.dry < 0.0f ? 1 : 2);
            }
            // Covered pixels come in runs: when any pixel of the chunk granulates, the powers are
            // taken for the whole chunk (one vectorised loop) and blended where mode == 2.
            bool any = false;
            for (int i = 0; i < n; ++i) any |= mode[i] == 2;
            if (any) {
                // Channel planes (base[c * kChunk + i]): the exponent plane da serves all three.
                for (int i = 0; i < n; ++i) base[i] = std::fabs(cr[i]);
                for (int i = 0; i < n; ++i) base[kChunk + i] = std::fabs(cg[i]);
                for (int i = 0; i < n; ++i) base[2 * kChunk + i] = std::fabs(cb[i]);
                for (int ch = 0; ch < 3; ++ch) pow_c_many(base + ch * kChunk, da, g + ch * kChunk, std::size_t(n));
                for (int i = 0; i < n; ++i) {  // eq. 2, case 2, blended by the substrate fade
                    const bool gr = mode[i] == 2;
                    outr[i] = gr ? mix(cr[i], g[i], fade[i]) : outr[i];
                    outg[i] = gr ? mix(cg[i], g[kChunk + i], fade[i]) : outg[i];
                    outb[i] = gr ? mix(cb[i], g[2 * kChunk + i], fade[i]) : outb[i];
                }
            }
            for (int i = 0; i < n; ++i)
                o(xs + i, y) = mode[i] == 0 ? glm::vec4(cr[i], cg[i], cb[i], ca[i])
                                            : glm::vec4(outr[i], outg[i], outb[i], ca[i]);
        }
    });
}

}  // namespace aq::stylize
